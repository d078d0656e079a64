#!/usr/bin/env python3
"""Writes a tiny valid seed file per loader format into <out>/<format>/ (hand-made
here, so no data file is copied into the repository). Usage: make_seeds.py OUT_DIR"""
import os, struct, sys

def tfx(version, strands=2, vps=3, thickness=True):
    header = 296 if version == 3 else 160
    stride = 12 if version == 3 else 16
    pos = header
    thick = pos + strands * vps * stride
    b = bytearray(thick + (strands * 4 if thickness else 0))
    struct.pack_into('<fII', b, 0, float(version), strands, vps)
    struct.pack_into('<I', b, 144 if version == 3 else 12, pos)
    if thickness: struct.pack_into('<I', b, 148 if version == 3 else 24, thick)
    for s in range(strands):
        for v in range(vps):
            o = pos + (s * vps + v) * stride
            struct.pack_into('<fff', b, o, s, v, 0.5 * s)
            if stride == 16: struct.pack_into('<f', b, o + 12, 1.0)
        if thickness: struct.pack_into('<f', b, thick + 4 * s, 0.5 + s)
    return bytes(b)

def hair():
    segs = [2, 1]
    pts = sum(s + 1 for s in segs)
    flags = 1 | 2 | 4
    b = b'HAIR' + struct.pack('<IIIIff3f', len(segs), pts, flags, 2, 0.1, 1.0, 1, 1, 1) + b'\0' * 88
    b += b''.join(struct.pack('<H', s) for s in segs)
    b += b''.join(struct.pack('<3f', i, i * 0.5, 0) for i in range(pts))
    b += b''.join(struct.pack('<f', 0.01 * (i + 1)) for i in range(pts))
    return b

def trk(order='<', vox_to_ras=False):
    h = bytearray(1000)
    h[0:6] = b'TRACK\0'
    struct.pack_into(order + 'h', h, 36, 1)     # n_scalars
    struct.pack_into(order + 'h', h, 238, 1)    # n_properties
    if vox_to_ras:  # version 2 space: dim, voxel_size, vox_to_ras (a turn and a shift), voxel_order
        struct.pack_into(order + '3h', h, 6, 4, 5, 6)
        struct.pack_into(order + '3f', h, 12, 2, 4, 0.5)
        struct.pack_into(order + '16f', h, 440, 0, -4, 0, 10, 2, 0, 0, -20, 0, 0, 0.5, 5, 0, 0, 0, 1)
        h[948:952] = b'LPS\0'  # disagrees with vox_to_ras ("ALS"): reoriented
    struct.pack_into(order + 'iii', h, 988, 2, 2, 1000)
    body = b''
    for m in (3, 2):
        body += struct.pack(order + 'i', m)
        for p in range(m): body += struct.pack(order + '4f', p, p * 2, 1, 0.5)
        body += struct.pack(order + 'f', 7)
    return bytes(h) + body

def tck(head='mrtrix tracks\ndatatype: Float32LE\ncount: 2\nfile: . {}\nEND\n', off=64):
    text = head.format(off).encode()
    text += b'\0' * (off - len(text))
    nan, inf = float('nan'), float('inf')
    data = [(0, 0, 0), (1, 0, 0), (1, 1, 0), (nan, nan, nan), (0, 0, 1), (0, 1, 1), (nan, nan, nan), (inf, inf, inf)]
    return text + b''.join(struct.pack('<3f', *p) for p in data)

# A header as MRtrix reads it: comments, a line without a key, repeated keys, any case.
TCK_HEAD = ('mrtrix tracks\n# comment\ncommand_history: a\ncommand_history: b\nno colon here\n'
            'DataType: Int16LE\ndatatype: float32le # last wins\ncount: 2\nFILE : . {}\nEND\n')

SWC = b"""# tiny neuron
1 1 0 0 0 2.0 -1
2 3 0 5 0 1.0 1
3 3 0 10 1 0.5 2
4 2 3 0 0 0.3 1
"""
PLY = b"""ply
format ascii 1.0
element vertex 4
property float x
property float y
property float z
element face 2
property list uchar int vertex_indices
element edge 1
property int vertex1
property int vertex2
end_header
0 0 0
1 0 0
1 1 0
0 1 0
3 0 1 2
4 0 1 2 3
0 2
"""
PLYBIN = (b"ply\nformat binary_little_endian 1.0\nelement vertex 3\nproperty float x\nproperty float y\n"
          b"property float z\nelement face 1\nproperty list uchar uint vertex_indices\nend_header\n"
          + struct.pack('<9f', 0, 0, 0, 1, 0, 0, 0, 1, 0) + struct.pack('<B3I', 3, 0, 1, 2))
OBJ = b"""# tiny
v 0 0 0
v 1 0 0
v 1 1 0
v 0 1 1
vt 0 0
vn 0 0 1
f 1/1/1 2/1/1 3/1/1
f -1 -2 -3
l 1 2 4
"""
NFF = b"""v
from 0 0 -5
at 0 0 0
up 0 1 0
angle 40
hither 1
resolution 64 64
b 0.1 0.1 0.1
l 1 1 1
f 1 0 0 0.5 0.5 0 0
s 0 0 0 1
c 0 0 0 0.1 0 1 0 0.05
p 3
0 0 0
1 0 0
0 1 0
pp 3
0 0 0 0 0 1
1 0 0 0 0 1
0 1 0 0 0 1
"""
JSON = b"""{"name": "seed", "camera": {"eye": [0, 0, -5], "target": [0, 0, 0], "up": [0, 1, 0], "fov": 40},
 "objects": [
  {"generator": "bundle", "count": 4, "radius": 0.01, "tilt": 30, "seed": 1, "prim": "curve", "subdiv": 2,
   "transform": {"translate": [1, 0, 0], "scale": [1, 2, 1], "rotate": {"axis": [0, 1, 0], "deg": 30}}},
  {"generator": "hair", "strands": 3, "points": 4, "length": 0.5, "radius": 0.002, "curl": 0.1, "seed": 2, "prim": "cone"},
  {"generator": "streamlines", "lines": 2, "steps": 5, "radius": 0.01, "seed": 3},
  {"generator": "ground", "height": -1, "size": 2},
  {"file": "missing.swc", "radius": 0.5, "prim": "capsule"}
 ]}
"""

SEEDS = {
    'tfx': {'v3.tfx': tfx(3), 'v4.tfx': tfx(4, thickness=False)},
    'hair': {'tiny.hair': hair()},
    'trk': {'tiny.trk': trk(), 'big.trk': trk('>'), 'space.trk': trk(vox_to_ras=True),
            'space_big.trk': trk('>', vox_to_ras=True)},
    'tck': {'tiny.tck': tck(), 'header.tck': tck(TCK_HEAD, 192)},
    'swc': {'tiny.swc': SWC},
    'ply': {'ascii.ply': PLY, 'binary.ply': PLYBIN},
    'obj': {'tiny.obj': OBJ},
    'nff': {'tiny.nff': NFF},
    'json': {'tiny.json': JSON, 'bundle.json': b'{"objects": [{"generator": "bundle", "count": 3}]}'},
}

if __name__ == '__main__':
    out = sys.argv[1]
    for fmt, files in SEEDS.items():
        os.makedirs(os.path.join(out, fmt), exist_ok=True)
        for name, data in files.items():
            with open(os.path.join(out, fmt, name), 'wb') as f: f.write(data)

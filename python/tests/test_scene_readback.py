"""What a scene holds, read back: each geometry's arrays (and the strands of loaded
segments, against the file's own layout), the world bounds, the camera and pinhole rays
(against numpy's own pinhole), and what an Accel was built with."""
import os
import warnings

import numpy as np
import pytest

import masq


def mixed_scene(rng):
    s = masq.Scene()
    tri_v = rng.uniform(-1, 1, size=(5, 3)).astype(np.float32)
    tri_i = np.array([[0, 1, 2], [2, 3, 4]], np.uint32)
    a = rng.uniform(-1, 1, size=(6, 3)).astype(np.float32)
    b = a + np.float32(0.5)
    r = rng.uniform(0.01, 0.1, size=6).astype(np.float32)
    ra, rb = r, r * np.float32(0.5)
    centers = rng.uniform(-1, 1, size=(3, 3)).astype(np.float32)
    points = rng.uniform(-1, 1, size=(2, 4, 3)).astype(np.float32)
    s.add_triangles(tri_v, tri_i)
    s.add_capsules(a, b, r)
    s.add_round_cones(a, ra, b, rb)
    s.add_spheres(centers, r[:3])
    s.add_curves(points, r[:2])
    normal = rng.normal(size=(6, 3)).astype(np.float32)
    s.add_ribbons(a, ra, b, rb, normal)
    given = [
        {"type": "triangle", "vertices": tri_v, "indices": tri_i},
        {"type": "capsule", "a": a, "b": b, "radius": r},
        {"type": "round_cone", "a": a, "ra": ra, "b": b, "rb": rb},
        {"type": "sphere", "centers": centers, "radius": r[:3]},
        {"type": "curve", "points": points, "radius": r[:2]},
        {"type": "ribbon", "p0": a, "r0": ra, "p1": b, "r1": rb, "normal": normal},
    ]
    return s, given


def unit(v):
    return v / np.linalg.norm(v, axis=-1, keepdims=True)


def test_every_type_reads_back_as_it_was_added():
    s, given = mixed_scene(np.random.default_rng(2))
    for i, want in enumerate(given):
        got = s.geometry(i)
        assert got["type"] == want["type"]
        for key, value in want.items():
            if key != "type":
                np.testing.assert_array_equal(got[key], value, err_msg=f"{want['type']} {key}")
        oriented = want["type"] in ("capsule", "round_cone", "curve", "ribbon")
        assert ("strands" in got) == oriented and ("tangents" in got) == oriented
    # Tangents: unit b - a; a curve's derivative at its middle, B'(1/2) = 3/4 (p3 + p2 - p1 - p0).
    np.testing.assert_allclose(s.geometry(1)["tangents"], unit(given[1]["b"] - given[1]["a"]), rtol=1e-6)
    p = given[4]["points"].astype(np.float64)
    np.testing.assert_allclose(s.geometry(4)["tangents"], unit(p[:, 3] + p[:, 2] - p[:, 1] - p[:, 0]), rtol=1e-5)
    # A ribbon's normal comes back as it was added (not unit length), its tangent unit p1 - p0.
    np.testing.assert_allclose(s.geometry(5)["tangents"], unit(given[5]["p1"] - given[5]["p0"]), rtol=1e-6)
    with pytest.raises(IndexError, match="Scene.geometry: id: geometry 6 does not exist"):
        s.geometry(6)
    with pytest.raises(IndexError):
        s.geometry(-1)


def test_a_read_back_geometry_rebuilds_the_same_scene():
    s, given = mixed_scene(np.random.default_rng(3))
    copy = masq.Scene()
    adders = {"triangle": (copy.add_triangles, ("vertices", "indices")),
              "capsule": (copy.add_capsules, ("a", "b", "radius")),
              "round_cone": (copy.add_round_cones, ("a", "ra", "b", "rb")),
              "sphere": (copy.add_spheres, ("centers", "radius")),
              "curve": (copy.add_curves, ("points", "radius")),
              "ribbon": (copy.add_ribbons, ("p0", "r0", "p1", "r1", "normal"))}
    for i in range(s.geometry_count):
        g = s.geometry(i)
        add, keys = adders[g["type"]]
        add(*(g[k] for k in keys))
    rays = s.camera_rays(48, 32)
    ctx = masq.Context("cpu")
    a = ctx.trace(masq.Accel.build(s), rays)
    b = ctx.trace(masq.Accel.build(copy), rays)
    assert np.array_equal(a["prim"], b["prim"]) and np.array_equal(a["t"], b["t"])


def test_strands_chain_segments_that_meet():
    s = masq.Scene()
    # Strands 0: three chained segments; 1: one; 2: two (it starts away from strand 1's end).
    pts = np.array([[0, 0, 0], [1, 0, 0], [2, 0, 0], [3, 0, 0]], np.float32)
    a = np.concatenate([pts[:-1], [[5, 0, 0]], [[7, 0, 0], [8, 0, 0]]]).astype(np.float32)
    b = np.concatenate([pts[1:], [[6, 0, 0]], [[8, 0, 0], [9, 1, 0]]]).astype(np.float32)
    s.add_capsules(a, b, 0.1)
    strands = s.geometry(0)["strands"]
    np.testing.assert_array_equal(strands, [0, 0, 0, 1, 2, 2])
    # The rule, in numpy: a new strand wherever a segment does not start at the last one's end.
    starts = np.concatenate([[True], np.any(a[1:] != b[:-1], axis=1)])
    np.testing.assert_array_equal(strands, np.cumsum(starts) - 1)


def test_loaded_hair_strands_are_the_files(data_dir):
    # TressFX 3: numStrands and vertsPerStrand at bytes 4 and 8, the positions' offset at
    # 144, then numStrands x vertsPerStrand float32 points.
    path = os.path.join(data_dir, "hair", "tressfx3_ponytail_tail.tfx")
    raw = np.fromfile(path, dtype=np.uint8)
    strands, per = (int(x) for x in raw[4:12].view("<u4"))
    offset = int(raw[144:148].view("<u4")[0])
    verts = raw[offset:offset + strands * per * 12].view("<f4").reshape(strands, per, 3)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", masq.LoadWarning)
        g = masq.Scene.load(path).geometry(0)
    assert g["type"] == "capsule"
    np.testing.assert_array_equal(g["a"], verts[:, :-1].reshape(-1, 3))
    np.testing.assert_array_equal(g["b"], verts[:, 1:].reshape(-1, 3))
    np.testing.assert_array_equal(g["strands"], np.repeat(np.arange(strands), per - 1))
    assert g["strands"].dtype == np.int32
    np.testing.assert_allclose(g["tangents"], unit(g["b"].astype(np.float64) - g["a"]), rtol=1e-5, atol=1e-6)


def test_bounds_hold_every_placed_primitive():
    s = masq.Scene()
    c = np.array([[0, 0, 0], [2, 1, -1]], np.float32)
    r = np.array([0.5, 0.25], np.float32)
    g = s.add_spheres(c, r)
    np.testing.assert_allclose(s.bounds, [np.min(c - r[:, None], 0), np.max(c + r[:, None], 0)])
    lo, hi = s.bounds
    assert lo.shape == hi.shape == (3,) and s.bounds.dtype == np.float64
    # Placed twice: shifted, and stretched along x by 3 (a ball's reach along x with it).
    m = np.hstack([np.diag([3.0, 1.0, 1.0]), [[10.0], [0.0], [0.0]]])
    s.add_instance(g, np.hstack([np.eye(3), [[0.0], [-5.0], [0.0]]]))
    s.add_instance(g, m)
    shifted = c + [0, -5, 0]
    stretched = c * [3, 1, 1] + [10, 0, 0]
    reach = r[:, None] * [3, 1, 1]
    want_lo = np.minimum(np.min(shifted - r[:, None], 0), np.min(stretched - reach, 0))
    want_hi = np.maximum(np.max(shifted + r[:, None], 0), np.max(stretched + reach, 0))
    np.testing.assert_allclose(s.bounds, [want_lo, want_hi])
    empty = masq.Scene().bounds
    assert np.all(empty[0] == np.inf) and np.all(empty[1] == -np.inf)


def pinhole(width, height, eye, target, up, fov):
    """numpy's own pinhole: unit directions through pixel centres, row-major from the top."""
    eye, target, up = (np.asarray(v, np.float64) for v in (eye, target, up))
    f = unit(target - eye)
    right = unit(np.cross(f, up))
    true_up = np.cross(right, f)
    half_h = np.tan(np.radians(fov) / 2)
    half_w = half_h * width / height
    x = (2 * (np.arange(width) + 0.5) / width - 1) * half_w
    y = (1 - 2 * (np.arange(height) + 0.5) / height) * half_h
    d = f + x[None, :, None] * right + y[:, None, None] * true_up
    return unit(d).reshape(-1, 3)


def test_pinhole_rays_are_a_pinholes():
    eye, target, up, fov = (1.0, 2.0, -6.0), (0.0, 0.5, 0.0), (0.0, 1.0, 0.0), 55.0
    rays = masq.pinhole_rays(16, 9, eye, target, up, fov)
    assert rays.dtype == masq.ray_dtype and rays.shape == (16 * 9,)
    np.testing.assert_allclose(rays["dir"], pinhole(16, 9, eye, target, up, fov), atol=1e-6)
    assert np.all(rays["org"] == np.float32(eye)) and np.all(rays["tmin"] == 0)
    # The top row looks up (along up), the left column to the left.
    assert rays["dir"][0, 1] > rays["dir"][-1, 1]
    # A scene's camera with parts replaced is that pinhole too.
    s = masq.Scene()
    s.add_spheres(np.zeros((1, 3)), 1.0)
    np.testing.assert_array_equal(s.camera_rays(16, 9, eye=eye, target=target, up=up, fov=fov), rays)
    np.testing.assert_array_equal(masq.pinhole_rays(16, 9, eye, target), masq.pinhole_rays(16, 9, eye, target, up, 40))


def test_the_scenes_camera_is_what_camera_rays_uses():
    s = masq.Scene()
    s.add_capsules(np.zeros((1, 3)), np.array([[4.0, 1.0, 0.0]]), 0.2)
    cam = s.camera
    assert set(cam) == {"eye", "target", "up", "fov", "orthographic", "ortho_height"}
    # The framed view looks at the middle of the bounds.
    np.testing.assert_allclose(cam["target"], s.bounds.mean(axis=0))
    default = s.camera_rays(20, 10)
    same = s.camera_rays(20, 10, eye=cam["eye"], target=cam["target"], up=cam["up"], fov=cam["fov"])
    np.testing.assert_array_equal(default, same)
    np.testing.assert_allclose(default["dir"], pinhole(20, 10, cam["eye"], cam["target"], cam["up"], cam["fov"]),
                               atol=1e-6)
    # Only the eye moved: the rays start there and still look at the target.
    moved = s.camera_rays(21, 21, eye=cam["eye"] + [0, 0, -3])
    centre = moved.reshape(21, 21)[10, 10]
    np.testing.assert_allclose(unit(centre["dir"]), unit(cam["target"] - (cam["eye"] + [0, 0, -3])), atol=1e-6)
    # Images as grids: reshape(height, width), and the hits come back that shape.
    hits = masq.Context("cpu").trace(masq.Accel.build(s), default.reshape(10, 20))
    assert hits.shape == (10, 20) and np.any(hits["prim"] >= 0)


@pytest.mark.parametrize("kwargs, words", [
    ({"fov": 0}, "fov: 0"), ({"fov": 180}, "fov: 180"),
    ({"target": (0, 0, -5), "eye": (0, 0, -5)}, "target: equals eye"),
    ({"eye": (0, 0, -5), "target": (0, 0, 0), "up": (0, 0, 1)}, "up: zero or parallel"),
    ({"eye": (0, np.nan, 0)}, "eye: component 1 is not finite"), ({"up": (0, 1)}, r"up: expected three numbers"),
])
def test_bad_cameras_name_the_argument(kwargs, words):
    s = masq.Scene()
    s.add_spheres(np.zeros((1, 3)), 1.0)
    with pytest.raises(ValueError, match=f"Scene.camera_rays: {words}"):
        s.camera_rays(4, 4, **kwargs)
    with pytest.raises(ValueError, match="pinhole_rays: width and height must be positive"):
        masq.pinhole_rays(0, 4, (0, 0, -1), (0, 0, 0))


def test_an_accel_says_what_it_was_built_with():
    rng = np.random.default_rng(8)
    s = masq.Scene()
    a = rng.uniform(-1, 1, size=(300, 3))
    s.add_capsules(a, a + rng.normal(scale=0.2, size=(300, 3)), 0.01)
    masq_accel = masq.Accel.build(s, method="masq", nodes="w8")
    assert masq_accel.method == "masq" and masq_accel.stats.method == "masq"
    assert masq_accel.stats.primitives == s.primitive_count == 300
    text = repr(masq_accel)
    for words in ("masq.Accel", "method=masq", "nodes=w8", "primitives=300", "instances=300"):
        assert words in text, text
    automatic = masq.Accel.build(s, method="auto")
    assert automatic.options["method"] == "auto"
    assert automatic.method in {"ref", "masq", "cluster", "mix"}
    assert f"method={automatic.method} (chosen by auto)" in repr(automatic)
    # What auto kept traces as that method built directly does (cluster: auto may have
    # kept another cluster shape than the default).
    if automatic.method in ("ref", "masq"):
        ctx = masq.Context("cpu")
        rays = s.camera_rays(32, 32)
        kept = masq.Accel.build(s, method=automatic.method)
        assert automatic.stats.instances == kept.stats.instances
        assert np.array_equal(ctx.trace(automatic, rays)["prim"], ctx.trace(kept, rays)["prim"])
    assert "masq.Scene" in repr(s) and "300 primitives" in repr(s)
    assert "method=masq" in repr(masq_accel.stats)


def test_the_package_carries_its_type_stub():
    folder = os.path.dirname(masq.__file__)
    assert os.path.isfile(os.path.join(folder, "py.typed"))
    with open(os.path.join(folder, "_masq.pyi")) as f:
        stub = f.read()
    for name in ("class Scene", "def trace", "def geometry", "def pinhole_rays", "def bounds", "def method"):
        assert name in stub, name

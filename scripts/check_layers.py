#!/usr/bin/env python3
"""Checks that includes point down the layers (docs/architecture.md): a file may include
files of its own folder and of folders on a lower layer, never of a folder on its own
layer or above. Run from anywhere; exits 1 naming every include that points the wrong way
(ctest: layers).

The table below is the one list of folders and their layers, top to bottom. A folder
not listed is an error, so a new folder gets a row here (and a line in
docs/architecture.md) before it gets code.
"""
import os
import re
import subprocess
import sys

# Folder -> layer (higher includes lower). Folders on one layer do not include each other.
LAYERS = {
    "tests": 90, "examples": 90,
    "fuzz": 85,
    "cli": 80,
    "bench": 70, "stress": 70,
    "api": 60, "peers": 60, "image": 60,
    "host/registry": 55,
    "host/cpu": 50, "host/opencl": 50, "host/vulkan": 50,
    "host": 45,
    "bvh/bv": 40,
    "bvh/twolevel": 38,
    "bvh/nodes": 36,
    "bvh/build": 34,
    "bvh/bounds": 32,
    "bvh": 30,
    "oracle": 25,
    "scenes/loaders": 22,
    "scenes": 20,
    "kernels": 10,
    "include/masq": 0,
}
SOURCE = re.compile(r"\.(h|hpp|cpp|inc|comp|cl)$")
INCLUDE = re.compile(r'^\s*#\s*include\s+"([^"]+)"')


def folder_of(path):
    """The longest LAYERS key that is a folder prefix of path (None if none is)."""
    parts = path.split("/")[:-1]
    for n in range(len(parts), 0, -1):
        key = "/".join(parts[:n])
        if key in LAYERS:
            return key
    return None


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    files = subprocess.check_output(["git", "ls-files"], cwd=root, text=True).split()
    known = set(files)
    problems = []
    for f in files:
        if not SOURCE.search(f) or f.startswith("scripts/"):
            continue
        src = folder_of(f)
        if src is None:
            problems.append(f"{f}: folder not in the layer table of scripts/check_layers.py")
            continue
        with open(os.path.join(root, f), errors="replace") as text:
            for lineno, line in enumerate(text, 1):
                m = INCLUDE.match(line)
                if not m:
                    continue
                inc = m.group(1)
                candidates = [os.path.normpath(os.path.join(os.path.dirname(f), inc)), inc, "include/" + inc]
                target = next((c for c in candidates if c in known), None)
                if target is None:
                    continue  # generated headers (spirv/, opencl/, cpu/) and system ones
                dst = folder_of(target)
                if dst is None or dst == src:
                    continue
                if LAYERS[dst] >= LAYERS[src]:
                    problems.append(f"{f}:{lineno}: includes {target} ({dst}, layer {LAYERS[dst]}) from "
                                    f"{src} (layer {LAYERS[src]})")
    for p in problems:
        print(p)
    if problems:
        print(f"check_layers: {len(problems)} include(s) point up or sideways (docs/architecture.md)")
        return 1
    print("check_layers: every include points down")
    return 0


if __name__ == "__main__":
    sys.exit(main())

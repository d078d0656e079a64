#!/usr/bin/env python3
"""Checks that includes point down the layers (docs/architecture.md): a file may include
files of its own folder and of folders on a lower layer, never of a folder on its own
layer or above; that the drivers reach host/ through its front door only; and that no
files include each other in a circle, inside a folder either. Run from anywhere; exits
1 naming every include that points the wrong way and every circle (ctest: layers).

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
    "python": 88,
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
    "bvh/binary": 34,
    "bvh/bounds": 32,
    "bvh": 30,
    "oracle": 25,
    "scenes/loaders": 22,
    "scenes": 20,
    "kernels": 10,
    "knobs": 5,
    "include/masq": 0,
}
# The drivers and the Python module reach the backends through these host/ headers (or
# the public API, include/masq/) and no other: the rest of host/ is the backends' own
# business (docs/architecture.md, "Layers").
DRIVERS = {"cli", "bench", "stress", "python"}
FRONT_DOOR = {"host/backend.h", "host/bv_tracer.h"}
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


def source_files(root):
    """The repository's files: git's list, or a walk of the tree outside a checkout."""
    try:
        return subprocess.check_output(["git", "ls-files"], cwd=root, text=True, stderr=subprocess.DEVNULL).split()
    except (OSError, subprocess.CalledProcessError):
        out = []
        for folder, dirs, names in os.walk(root):
            dirs[:] = [d for d in dirs if not d.startswith((".", "build", "_"))]
            out += [os.path.relpath(os.path.join(folder, n), root) for n in names]
        return out


def circles(graph):
    """The include circles of graph (file -> files it includes): strongly connected
    components of more than one file (Tarjan's algorithm, iterative)."""
    index, low, on_stack, stack, found = {}, {}, set(), [], []
    for start in graph:
        if start in index:
            continue
        work = [(start, iter(graph[start]))]
        index[start] = low[start] = len(index)
        stack.append(start)
        on_stack.add(start)
        while work:
            node, children = work[-1]
            child = next(children, None)
            if child is not None:
                if child not in index:
                    index[child] = low[child] = len(index)
                    stack.append(child)
                    on_stack.add(child)
                    work.append((child, iter(graph.get(child, []))))
                elif child in on_stack:
                    low[node] = min(low[node], index[child])
                continue
            work.pop()
            if work:
                low[work[-1][0]] = min(low[work[-1][0]], low[node])
            if low[node] == index[node]:
                component = []
                while True:
                    member = stack.pop()
                    on_stack.discard(member)
                    component.append(member)
                    if member == node:
                        break
                if len(component) > 1:
                    found.append(sorted(component))
    return found


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    files = source_files(root)
    known = set(files)
    problems = []
    graph = {}
    for f in files:
        if not SOURCE.search(f) or f.startswith("scripts/"):
            continue
        graph.setdefault(f, [])
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
                graph[f].append(target)
                dst = folder_of(target)
                if src in DRIVERS and target.startswith("host/") and target not in FRONT_DOOR:
                    problems.append(f"{f}:{lineno}: includes {target} from {src}: drivers include only "
                                    f"{' and '.join(sorted(FRONT_DOOR))} of host/")
                if dst is None or dst == src:
                    continue
                if LAYERS[dst] >= LAYERS[src]:
                    problems.append(f"{f}:{lineno}: includes {target} ({dst}, layer {LAYERS[dst]}) from "
                                    f"{src} (layer {LAYERS[src]})")
    for circle in circles(graph):
        problems.append("include circle: " + " -> ".join(circle))
    for p in problems:
        print(p)
    if problems:
        print(f"check_layers: {len(problems)} include(s) point up or sideways, pass the front door, or go round "
              "(docs/architecture.md)")
        return 1
    print("check_layers: every include points down, drivers use the front door, and none goes round")
    return 0


if __name__ == "__main__":
    sys.exit(main())

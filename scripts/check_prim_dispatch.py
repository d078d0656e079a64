#!/usr/bin/env python3
"""Checks that code outside the kernels, the tests and the primitive-type tables does not
dispatch on the primitive type: no `case PrimType::X` / `case MASQ_PRIM_X` (a switch on
the type) and no `==` / `!=` against `PrimType::X` or `MASQ_PRIM_X` (issue 37). Such code
calls through its layer's table row or reads one of the row's columns instead
(docs/architecture.md, "The tables"). Run from anywhere; exits 1 naming every dispatch
outside the tables (ctest: prim_dispatch). `--count` prints the dispatches per file,
tables and exempt folders included, and exits 0.
"""
import os
import re
import sys

# The same file list and source pattern as the layer check (this script's folder is on
# sys.path when it runs).
from check_layers import SOURCE, source_files

# Folders where dispatching on the type is the point.
EXEMPT_FOLDERS = {
    "kernels/": "the one intersector dispatch the kernels keep (kernels/intersect_primitive.h)",
    "tests/": "tests name the types they test",
}

# The tables themselves: each holds one row per primitive type and static_asserts it.
TABLE_FILES = {
    "scenes/scene.h": "prim_type_rows: names, help and aliases (the NameTable)",
    "scenes/prim_table.cpp": "the scenes layer's rows: count, validation, hull balls, shape, MASQ_PRIM_* id, packing, cost",
    "oracle/oracle.cpp": "the oracle's rows: its intersector per type",
    "host/vulkan/rt_pipeline.h": "kHitGroups: rtpipeline's hit group per type",
    "stress/stress_prim_rows.cpp": "the stress suite's rows: placement, degenerate cells, aims",
}

TYPE = r"(?:PrimType::\w+|MASQ_PRIM_\w+)"
DISPATCH = re.compile(r"\bcase\s+" + TYPE + r"|(?:==|!=)\s*" + TYPE + r"|" + TYPE + r"\s*(?:==|!=)")


def dispatches(path):
    """(line number, line) of every dispatch on the type in path; comments skipped."""
    found = []
    with open(path, errors="replace") as text:
        for lineno, line in enumerate(text, 1):
            code = line.split("//", 1)[0]
            found += [(lineno, line.rstrip())] * len(DISPATCH.findall(code))
    return found


def main():
    root = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
    count_only = "--count" in sys.argv[1:]
    files = [f for f in source_files(root) if SOURCE.search(f) and not f.startswith("scripts/")]
    problems, total, outside = [], 0, 0
    for f in sorted(files):
        path = os.path.join(root, f)
        if not os.path.exists(path):
            continue
        found = dispatches(path)
        if not found:
            continue
        exempt = next((k for k in EXEMPT_FOLDERS if f.startswith(k)), None)
        total += len(found)
        if count_only:
            where = "exempt" if exempt else "table" if f in TABLE_FILES else "outside"
            print(f"{len(found):4d}  {f}  ({where})")
        if exempt or f in TABLE_FILES:
            continue
        outside += len(found)
        problems += [f"{f}:{n}: dispatches on the primitive type: {line.strip()}" for n, line in found]
    if count_only:
        print(f"check_prim_dispatch: {total} dispatches in all, {outside} outside kernels/, tests/ and the tables")
        return 0
    for p in problems:
        print(p)
    if problems:
        print("check_prim_dispatch: call through the layer's table of primitive types, or read a column of its row "
              "(docs/architecture.md, \"The tables\")")
        return 1
    print("check_prim_dispatch: no dispatch on the primitive type outside the tables")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""Shows that no undefined value decides anything in the shipped SPIR-V kernels.

Each module is optimised with `spirv-opt -O` (as a driver's compiler would fold it) and
disassembled; every OpUndef is then followed through the values computed from it
(phis, composite construction and extraction, arithmetic, selects, shuffles) until it
reaches a use where its value would matter:
  a comparison, a branch or switch condition, a select's condition, an index or base
  of an access chain, a load's or store's pointer, a stored value, a call argument or
  any other instruction not known to merely pass values on.
Such a use fails the module. An OpUndef may stay where it only arrives through a phi
edge from a block the function's entry cannot reach, or where it fills a part of a
composite that nothing ever extracts or stores: those are listed, as allowed.

Composite parts are tracked by index path, so a struct written field by field (one
OpCompositeInsert per field) is undefined only in the fields never written.

usage: spirv_undef_check.py [--spirv-opt PATH] [--spirv-dis PATH] [--expect-fail PROBE.spv]
                            MODULE.spv ...
Exit status 0 when every module passes (and the probe, if given, fails: the check can
fail), 1 otherwise (each failure printed with the chain of instructions from the OpUndef
to the use, with source lines where the module carries them: compile with glslang -g),
2 on bad arguments or tools.
"""
import argparse
import os
import re
import subprocess
import sys
import tempfile

# Instructions whose result is computed from their operands without deciding anything:
# an undefined operand makes the result undefined (wholly) and goes no further.
PASS_THROUGH = {
    "OpFAdd", "OpFSub", "OpFMul", "OpFDiv", "OpFRem", "OpFMod", "OpFNegate", "OpIAdd", "OpISub", "OpIMul",
    "OpSDiv", "OpUDiv", "OpSRem", "OpSMod", "OpUMod", "OpSNegate", "OpShiftLeftLogical", "OpShiftRightLogical",
    "OpShiftRightArithmetic", "OpBitwiseAnd", "OpBitwiseOr", "OpBitwiseXor", "OpNot", "OpBitFieldInsert",
    "OpBitFieldSExtract", "OpBitFieldUExtract", "OpBitReverse", "OpBitCount", "OpConvertFToU", "OpConvertFToS",
    "OpConvertSToF", "OpConvertUToF", "OpUConvert", "OpSConvert", "OpFConvert", "OpBitcast",
    "OpVectorTimesScalar", "OpMatrixTimesScalar", "OpVectorTimesMatrix", "OpMatrixTimesVector",
    "OpMatrixTimesMatrix", "OpOuterProduct", "OpDot", "OpTranspose", "OpExtInst", "OpLogicalAnd",
    "OpLogicalOr", "OpLogicalNot", "OpLogicalEqual", "OpLogicalNotEqual", "OpCopyObject", "OpCopyLogical",
    "OpQuantizeToF16", "OpVectorExtractDynamic", "OpVectorInsertDynamic", "OpAny", "OpAll",
}
# Uses that need no further look: their result does not depend on the operand's value.
HARMLESS = {"OpName", "OpMemberName", "OpDecorate", "OpMemberDecorate", "OpLine", "OpNoLine"}

BLOCK_ENDS = {"OpBranch", "OpBranchConditional", "OpSwitch", "OpReturn", "OpReturnValue", "OpKill",
              "OpUnreachable", "OpTerminateInvocation", "OpIgnoreIntersectionKHR", "OpTerminateRayKHR"}

LINE = re.compile(r"^\s*(?:(%\w+)\s*=\s*)?(Op\w+)(.*)$")


class Inst:
    __slots__ = ("result", "op", "args", "text", "block")

    def __init__(self, result, op, args, text, block):
        self.result, self.op, self.args, self.text, self.block = result, op, args, text, block


def tokens(rest):
    # Strings may hold spaces; ids and literals do not.
    return re.findall(r'"(?:[^"\\]|\\.)*"|\S+', rest)


def parse(text):
    """The instructions; each one's text ends with its source line where the module
    carries OpLine (a module compiled with glslang -g), for a readable chain."""
    insts, block, strings, where = [], None, {}, ""
    for line in text.splitlines():
        m = LINE.match(line)
        if not m:
            continue
        result, op, rest = m.group(1), m.group(2), m.group(3)
        args = tokens(rest)
        if op == "OpString" and args:
            strings[result] = os.path.basename(args[0].strip('"'))
        if op == "OpLine" and len(args) >= 2:
            where = f"{strings.get(args[0], args[0])}:{args[1]}"
        if op in ("OpNoLine", "OpFunctionEnd"):
            where = ""
        if op == "OpLabel":
            block = result
        if op == "OpFunctionEnd":
            block = None
        text_ = line.strip() + (f"    [{where}]" if where and op not in ("OpLine", "OpString") else "")
        insts.append(Inst(result, op, args, text_, block))
    return insts


class Module:
    def __init__(self, insts):
        self.insts = insts
        self.defs = {i.result: i for i in insts if i.result}
        self.consts = {}
        for i in insts:
            if i.op in ("OpConstant", "OpSpecConstant") and len(i.args) >= 2:
                try:
                    self.consts[i.result] = int(i.args[1], 0)
                except ValueError:
                    pass
        self.reachable = self._reachable_blocks()

    def _reachable_blocks(self):
        succ, entries, current_fn_first = {}, set(), None
        for i in self.insts:
            if i.op == "OpFunction":
                current_fn_first = None
            elif i.op == "OpLabel":
                if current_fn_first is None:
                    current_fn_first = i.result
                    entries.add(i.result)
                succ.setdefault(i.result, [])
            elif i.op in ("OpBranch", "OpBranchConditional", "OpSwitch") and i.block:
                succ[i.block].extend(a for a in i.args if self._is_label(a))
        seen, todo = set(), list(entries)
        while todo:
            b = todo.pop()
            if b in seen:
                continue
            seen.add(b)
            todo.extend(succ.get(b, []))
        return seen

    def _is_label(self, name):
        d = self.defs.get(name)
        return d is not None and d.op == "OpLabel"

    # The child types of a composite type (struct members, array/vector/matrix elements).
    def children(self, type_id):
        t = self.defs.get(type_id)
        if t is None:
            return []
        if t.op == "OpTypeStruct":
            return list(t.args)
        if t.op in ("OpTypeVector", "OpTypeMatrix"):
            return [t.args[0]] * int(t.args[1])
        if t.op == "OpTypeArray":
            n = self.consts.get(t.args[1])
            return [t.args[0]] * n if n is not None else []
        return []

    def type_of(self, value_id):
        d = self.defs.get(value_id)
        return d.args[0] if d is not None and d.args else None

    def type_at(self, type_id, path):
        for k in path:
            kids = self.children(type_id)
            if k >= len(kids):
                return None
            type_id = kids[k]
        return type_id

    def width(self, value_id):
        t = self.defs.get(self.type_of(value_id))
        if t is not None and t.op == "OpTypeVector":
            return int(t.args[1])
        return 1


def is_prefix(p, q):
    return len(p) <= len(q) and q[: len(p)] == p


def remove_path(mod, type_id, taint, idx):
    """The taint of a composite of type type_id after OpCompositeInsert at idx."""
    out = set()
    for p in taint:
        if is_prefix(idx, p):
            continue  # overwritten
        if not is_prefix(p, idx):
            out.add(p)
            continue
        # p (undefined) holds idx: split it into its children down to idx's level.
        cur = p
        while len(cur) < len(idx):
            kids = mod.children(mod.type_at(type_id, cur))
            nxt = idx[len(cur)]
            for k in range(len(kids)):
                if k != nxt:
                    out.add(cur + (k,))
            cur = cur + (nxt,)
    return out


class Analysis:
    def __init__(self, mod):
        self.mod = mod
        self.taint = {}  # id -> set of index paths (() = the whole value)
        self.origin = {}  # id -> (from id, instruction text): one step back towards an OpUndef
        self.allowed_edges = []  # (undef-carrying value, phi text)
        self.violations = []  # (value id, instruction text, why)

    def t(self, v):
        return self.taint.get(v, set())

    def set(self, rid, new, src, inst):
        if not new:
            return False
        old = self.taint.get(rid, set())
        if new <= old:
            return False
        self.taint[rid] = old | new
        self.origin.setdefault(rid, (src, inst.text))
        return True

    def run(self):
        mod = self.mod
        for i in mod.insts:
            if i.op == "OpUndef":
                self.taint[i.result] = {()}
                self.origin[i.result] = (None, i.text)
        changed = True
        while changed:
            changed = False
            for i in mod.insts:
                changed |= self.step(i)
        for i in mod.insts:
            self.check_sink(i)

    def step(self, i):
        mod, args = self.mod, i.args
        if not i.result or i.op == "OpUndef":
            return False
        if i.op == "OpPhi":
            new, src = set(), None
            pairs = list(zip(args[1::2], args[2::2]))
            for value, parent in pairs:
                if self.t(value):
                    if parent not in mod.reachable:
                        self.allowed_edges.append((value, i.text))
                        continue
                    new |= self.t(value)
                    src = value
            return self.set(i.result, new, src, i)
        if i.op == "OpCompositeInsert":
            obj, comp, idx = args[1], args[2], tuple(int(a) for a in args[3:])
            new = remove_path(mod, args[0], self.t(comp), idx) | {idx + p for p in self.t(obj)}
            return self.set(i.result, new, obj if self.t(obj) else comp, i)
        if i.op == "OpCompositeExtract":
            comp, idx = args[1], tuple(int(a) for a in args[2:])
            ct = self.t(comp)
            if any(is_prefix(p, idx) for p in ct):
                return self.set(i.result, {()}, comp, i)
            return self.set(i.result, {p[len(idx):] for p in ct if is_prefix(idx, p)}, comp, i)
        if i.op == "OpCompositeConstruct":
            result_type = mod.defs.get(args[0])
            new, offset, src = set(), 0, None
            vector = result_type is not None and result_type.op == "OpTypeVector"
            for k, c in enumerate(args[1:]):
                w = mod.width(c) if vector else 1
                for p in self.t(c):
                    src = c
                    if not vector:
                        new.add((k,) + p)
                    elif p == ():
                        new |= {(offset + j,) for j in range(w)}
                    else:
                        new.add((offset + p[0],) + p[1:])
                offset += w
            return self.set(i.result, new, src, i)
        if i.op == "OpVectorShuffle":
            v1, v2, comps = args[1], args[2], [int(a) for a in args[3:]]
            n1, new, src = mod.width(v1), set(), None
            for k, c in enumerate(comps):
                v, j = (v1, c) if c < n1 else (v2, c - n1)
                if c == 0xFFFFFFFF:
                    continue
                if any(is_prefix(p, (j,)) for p in self.t(v)):
                    new.add((k,))
                    src = v
            return self.set(i.result, new, src, i)
        if i.op == "OpSelect":
            a, b = args[2], args[3]
            return self.set(i.result, self.t(a) | self.t(b), a if self.t(a) else b, i)
        if i.op in PASS_THROUGH:
            for a in args[1:]:
                if a.startswith("%") and self.t(a):
                    return self.set(i.result, {()}, a, i)
        return False

    def check_sink(self, i):
        if i.op in PASS_THROUGH or i.op in HARMLESS or i.op in ("OpPhi", "OpCompositeInsert", "OpCompositeExtract",
                                                                 "OpCompositeConstruct", "OpVectorShuffle",
                                                                 "OpUndef"):
            return
        used = i.args[1:] if i.result else i.args
        if i.op == "OpSelect":
            used = [i.args[1]]
        for a in used:
            if a.startswith("%") and self.t(a):
                self.violations.append((a, i.text, "undefined value used by " + i.op))

    def chain(self, v):
        steps, seen = [], set()
        while v is not None and v not in seen:
            seen.add(v)
            src, text = self.origin.get(v, (None, "?"))
            steps.append(text)
            v = src
        return list(reversed(steps))


def check(path, spirv_opt, spirv_dis):
    with tempfile.TemporaryDirectory() as tmp:
        opt = os.path.join(tmp, "opt.spv")
        subprocess.run([spirv_opt, "-O", path, "-o", opt], check=True)
        text = subprocess.run([spirv_dis, "--raw-id", opt], check=True, capture_output=True, text=True).stdout
    mod = Module(parse(text))
    a = Analysis(mod)
    a.run()
    name = os.path.basename(path)
    undefs = [i.result for i in mod.insts if i.op == "OpUndef"]
    if a.violations:
        print(f"FAIL {name}: {len(a.violations)} use(s) of undefined values ({len(undefs)} OpUndef after spirv-opt -O)")
        for v, text, why in a.violations[:5]:
            print(f"  {why}: {text}")
            for step in a.chain(v):
                print(f"      from {step}")
        return False
    notes = []
    if a.allowed_edges:
        notes.append(f"{len(a.allowed_edges)} on phi edges from unreachable blocks")
    partial = [u for u in undefs if u not in {e[0] for e in a.allowed_edges}]
    if partial:
        notes.append(f"{len(partial)} only in composite parts never extracted or stored")
    print(f"ok   {name}: {len(undefs)} OpUndef after spirv-opt -O" + (f" ({'; '.join(notes)})" if notes else ""))
    return True


def main():
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--spirv-opt", default="spirv-opt")
    ap.add_argument("--spirv-dis", default="spirv-dis")
    ap.add_argument("--expect-fail", metavar="PROBE", help="a module the check must fail")
    ap.add_argument("modules", nargs="+")
    o = ap.parse_args()
    ok = True
    if o.expect_fail:
        try:
            if check(o.expect_fail, o.spirv_opt, o.spirv_dis):
                print(f"FAIL the probe {os.path.basename(o.expect_fail)} passed: the check cannot find an undefined value")
                ok = False
            else:
                print(f"ok   the probe {os.path.basename(o.expect_fail)} failed, as it must")
        except (OSError, subprocess.CalledProcessError) as e:
            print(f"spirv_undef_check: {o.expect_fail}: {e}", file=sys.stderr)
            return 2
    for m in o.modules:
        if not os.path.isfile(m):
            print(f"spirv_undef_check: {m}: no such file", file=sys.stderr)
            return 2
        try:
            ok &= check(m, o.spirv_opt, o.spirv_dis)
        except (OSError, subprocess.CalledProcessError) as e:
            print(f"spirv_undef_check: {m}: {e}", file=sys.stderr)
            return 2
    return 0 if ok else 1


if __name__ == "__main__":
    sys.exit(main())

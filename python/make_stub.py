#!/usr/bin/env python3
"""Writes python/masq/_masq.pyi, the type stub of the compiled module, from the built
module with mypy's stubgen (Debian's python3-mypy), or with --check compares a fresh one
with the committed stub (ctest python_stub), so that the stub cannot go stale:

    python3 python/make_stub.py build/python                 # rewrite python/masq/_masq.pyi
    python3 python/make_stub.py build/python --check         # exit 1 and a diff when stale

The signatures are the ones pybind11 writes into the docstrings (python/src/bindings.h
names the array-like arguments). Four things stubgen 1.0 gets wrong for pybind11 are
mended here, each by what the module itself says rather than by a list of names:
static methods (written as methods of self, without their signatures), keyword-only
arguments (a signature with `*` is not read at all), the dtypes' type
(numpy.dtype[void]) and __version__ (dunder names are skipped). --check exits 77
(ctest: skipped) without mypy, or with a mypy other than the one the stub was made with,
whose stubgen writes other text.
"""
import argparse
import difflib
import inspect
import os
import re
import sys
import tempfile

HERE = os.path.dirname(os.path.abspath(__file__))
STUB = os.path.join(HERE, "masq", "_masq.pyi")
SKIP = 77
HEADER = ("# The masq._masq type stub, generated from the built module by python/make_stub.py with "
          "mypy {version}'s stubgen.\n# Do not edit: rerun it (ctest python_stub fails when this is stale).\n")


def static_methods(module):
    """{class name: names of its static methods}."""
    found = {}
    for name, cls in vars(module).items():
        if inspect.isclass(cls):
            found[name] = {k for k, v in vars(cls).items() if isinstance(v, staticmethod)}
    return found


def generate(build_python):
    """The stub's text for the masq._masq built under build_python."""
    sys.path.insert(0, build_python)
    import mypy.version
    from mypy import stubdoc, stubgenc
    import masq._masq as module

    class Pybind11Signatures(stubgenc.DocstringSignatureGenerator):
        """Reads a static method's signature from the function it wraps, and keyword-only
        arguments, whose `*` stubgen 1.0 cannot parse: the signatures are read without it,
        and it is put back before the argument that followed it."""

        def get_function_sig(self, func, module_name, name):
            doc = getattr(func, "__doc__", None)
            if not doc:
                return None
            keyword_only = set(re.findall(r"\*, (\w+):", doc))
            sigs = stubdoc.infer_sig_from_docstring(doc.replace("*, ", ""), name)
            if sigs and stubgenc.is_pybind11_overloaded_function_docstring(doc, name):
                del sigs[-1]  # pybind11's umbrella (*args, **kwargs)
            for sig in sigs or ():
                first = next((i for i, a in enumerate(sig.args) if a.name in keyword_only), None)
                if first is not None:
                    sig.args.insert(first, stubdoc.ArgSig(name="*"))
            return sigs

        def get_method_sig(self, func, module_name, class_name, name, self_var):
            return self.get_function_sig(getattr(func, "__func__", func), module_name, name)

    with tempfile.TemporaryDirectory() as tmp:
        target = os.path.join(tmp, "_masq.pyi")
        stubgenc.generate_stub_for_c_module(
            "masq._masq", target, [Pybind11Signatures(), stubgenc.FallbackSignatureGenerator()])
        with open(target) as f:
            lines = f.read().splitlines()

    statics = static_methods(module)
    out, cls = [], None
    for line in lines:
        m = re.match(r"class (\w+)", line)
        if m:
            cls = m.group(1)
        elif line and not line.startswith(" "):
            cls = None
        m = re.match(r"(    )def (\w+)\(self(?:, )?(.*)$", line)
        if cls and m and m.group(2) in statics.get(cls, ()):
            out.append(m.group(1) + "@staticmethod")
            line = f"{m.group(1)}def {m.group(2)}({m.group(3)}"
        # numpy.dtype's subclasses print as numpy.dtype[void]: the scalar type is numpy.void.
        out.append(line.replace("numpy.dtype[void]", "numpy.dtype[numpy.void]"))
    out.append("__version__: str")
    return HEADER.format(version=mypy.version.__version__) + "\n".join(out) + "\n"


def main():
    p = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    p.add_argument("build_python", help="the build tree's python/ folder (it holds masq/_masq*.so)")
    p.add_argument("--check", action="store_true", help="compare with the committed stub instead of writing it")
    args = p.parse_args()
    try:
        import mypy.version
    except ImportError:
        if args.check:
            print("make_stub: skipped: no mypy here (Debian: apt-get install python3-mypy)")
            return SKIP
        raise
    if args.check:
        with open(STUB) as f:
            committed = f.read()
        made_with = re.search(r"with mypy (\S+)'s stubgen", committed)
        if not made_with or made_with.group(1) != mypy.version.__version__:
            print(f"make_stub: skipped: {STUB} was made with mypy {made_with.group(1) if made_with else '?'}, "
                  f"this is mypy {mypy.version.__version__}, whose stubgen may write other text")
            return SKIP
    text = generate(os.path.abspath(args.build_python))
    if not args.check:
        with open(STUB, "w") as f:
            f.write(text)
        print(f"make_stub: wrote {STUB}")
        return 0
    if text == committed:
        print(f"make_stub: {STUB} matches the module")
        return 0
    sys.stdout.writelines(difflib.unified_diff(committed.splitlines(True), text.splitlines(True),
                                               "committed " + STUB, "from the module"))
    print(f"make_stub: {STUB} is stale: run python3 python/make_stub.py <build>/python and commit it")
    return 1


if __name__ == "__main__":
    sys.exit(main())

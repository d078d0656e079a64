#!/usr/bin/env bash
# `pip install .` into a virtual environment that sees the system's numpy, reusing the
# configured build (no second compile of the library), and `pip wheel .`; checks the
# wheel's files and that the venv imports the installed package from outside the source
# and build trees (ctest: python_pip_install; python_pytest then runs the Python tests
# with this venv's interpreter, against the installed package).
set -euo pipefail
source_dir=$1
build=$2
python=$3
venv="$build/_pip_venv"
rm -rf "$venv" "$build/_pip_wheel"
"$python" -m venv --system-site-packages "$venv"
# The configured build's own settings, so pip's configure changes nothing that forces a
# rebuild (pyproject.toml's MASQ_NATIVE_ISA=OFF is for wheels built from scratch).
native=$(sed -n 's/^MASQ_NATIVE_ISA:BOOL=//p' "$build/CMakeCache.txt")
pip_args=(--no-build-isolation --no-deps --no-index -q --config-settings "build-dir=$build" --config-settings "cmake.define.MASQ_NATIVE_ISA=${native:-ON}")
# pip's configure points the build's Python entries at the venv's interpreter (a link to
# the same python) and adds its SKBUILD_* entries: put the build's own back afterwards,
# whatever happens, so the venv can go without breaking the next configure.
restore() {
  cmake -S "$source_dir" -B "$build" -DPython3_EXECUTABLE="$python" -UPython_EXECUTABLE -UPYTHON_EXECUTABLE \
    -UPython3_ROOT_DIR -UPython_ROOT_DIR -U'SKBUILD*' >/dev/null
}
trap restore EXIT
"$venv/bin/pip" install "${pip_args[@]}" "$source_dir"
"$venv/bin/pip" wheel "${pip_args[@]}" -w "$build/_pip_wheel" "$source_dir" >/dev/null
wheel=$(ls "$build"/_pip_wheel/masq-*.whl)
"$venv/bin/python" - "$wheel" <<'PY'
import sys, zipfile
names = zipfile.ZipFile(sys.argv[1]).namelist()
assert "masq/__init__.py" in names and any(n.startswith("masq/_masq") for n in names), names
print("wheel:", sys.argv[1].rsplit("/", 1)[-1], len(names), "files")
PY
cd /
"$venv/bin/python" -c "import masq, sys; site = sys.argv[1]; assert masq.__file__.startswith(site), masq.__file__; print('masq', masq.__version__, 'from', masq.__file__)" "$venv"

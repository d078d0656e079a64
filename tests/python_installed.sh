#!/usr/bin/env bash
# Installs masq from BUILD_DIR into BUILD_DIR/_install_python, then imports the Python
# package from that prefix alone (outside the build and source trees) and traces one ray
# through it, and checks that its type stub and py.typed marker are there (a ctest
# test: python_installed).
set -euo pipefail
build=$1
python=$2
prefix="$build/_install_python"
rm -rf "$prefix"
cmake --install "$build" --prefix "$prefix" >/dev/null
site="$prefix/lib/python3/dist-packages"
# Type checkers read the stub beside the module when the package has the PEP 561 marker.
for f in _masq.pyi py.typed; do
  [[ -f "$site/masq/$f" ]] || { echo "python_installed: $site/masq/$f was not installed" >&2; exit 1; }
done
cd /
PYTHONPATH="$site" "$python" - "$site" <<'PY'
import os, sys
import numpy as np
import masq
site = sys.argv[1]
assert os.path.realpath(masq.__file__).startswith(os.path.realpath(site)), masq.__file__
s = masq.Scene()
s.add_spheres(np.array([[0, 0, 5]], np.float32), 1.0)
hits = masq.Context("cpu").trace(masq.Accel.build(s), np.zeros((1, 3)), np.array([[0, 0, 1.0]]))
assert hits["prim"][0] == 0 and abs(hits["t"][0] - 4) < 1e-5, hits
print(f"masq {masq.__version__} imported from {os.path.dirname(masq.__file__)}: t = {hits['t'][0]}")
PY

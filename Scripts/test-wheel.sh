#!/usr/bin/env bash
# Tests the pip route (pyproject.toml): in a venv of Debian's python3 without system
# site-packages (pip's VTK must not meet ParaView's), the newest vtk, pyvista, pytest, nanobind and
# scikit-build-core from PyPI, then `pip install .`, then
# - pytest on Testing/Wheel: the wheel's filter against analytic truth, bad input, PyVista off
#   screen (pip's VTK renders through EGL: no X server needed), and agreement with the C++ filter,
#   whose outputs Testing/Wheel/cxx_reference.py writes first from build/ (ParaView's VTK 9.2);
# - the wheel fuzzer's short form (a fixed seed);
# - the ParaView Python plugin in Debian's pvpython 5.11 (the installed package on PYTHONPATH).
# Needs Scripts/setup.sh's packages and its build/ (Scripts/test.sh runs it after them).
set -euo pipefail
cd "$(dirname "$0")/.."
venv=build/wheel-venv
out=build/wheel-tests
mkdir -p "$out"

/usr/bin/python3 -m venv "$venv"
"$venv/bin/python" -m pip install -q --upgrade pip
nice -n 10 "$venv/bin/python" -m pip install -q --upgrade vtk pyvista pytest numpy nanobind scikit-build-core
# The wheel's build, as `pip install .` makes it (its build requirements are the ones just installed).
CMAKE_BUILD_PARALLEL_LEVEL="${CMAKE_BUILD_PARALLEL_LEVEL:-2}" nice -n 10 \
  "$venv/bin/python" -m pip install -q --no-build-isolation --force-reinstall --no-deps .
"$venv/bin/python" - <<'PY'
import importlib.metadata as m
import sys
print("Tested with Python", sys.version.split()[0], "and", ", ".join(
    f"{name} {m.version(name)}" for name in
    ("tetdsr", "vtk", "pyvista", "numpy", "nanobind", "scikit_build_core", "pytest")))
PY

PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Testing/Wheel/cxx_reference.py Data \
  "$out/cxx_reference.npz"
TETDSR_CXX_REFERENCE="$out/cxx_reference.npz" VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow \
  "$venv/bin/python" -m pytest -p no:cacheprovider -v -s --junitxml="$out/wheel-tests.xml" \
  Testing/Wheel
# Here every test runs: a skip (pyvista missing, the C++ reference not found) fails the run.
/usr/bin/python3 - "$out/wheel-tests.xml" <<'PY'
import sys
import xml.etree.ElementTree as ET
suites = ET.parse(sys.argv[1]).getroot()
tests = sum(int(s.get("tests", 0)) for s in suites.iter("testsuite"))
skipped = sum(int(s.get("skipped", 0)) for s in suites.iter("testsuite"))
print(f"wheel tests: {tests} run, {skipped} skipped")
sys.exit(1 if skipped or not tests else 0)
PY

# The wheel fuzzer's short form (Testing/Fuzz/fuzz_wheel.py: the binding and the filter given
# hostile arrays, values, call orders and threads), fixed seed, about 30-60 s on a loaded machine.
(cd "$out" && VTK_DEFAULT_OPENGL_WINDOW=vtkEGLRenderWindow "../../$venv/bin/python" \
  ../../Testing/Fuzz/fuzz_wheel.py --seed 21 --cases 4000 --timeout 60 --out fuzz-wheel-failures)

# pvpython sees only the installed package (not the venv's VTK): a folder holding a link to it.
package=$("$venv/bin/python" -c "import os, tetdsr; print(os.path.dirname(tetdsr.__file__))")
mkdir -p "$out/pvpython-path"
ln -sfn "$package" "$out/pvpython-path/tetdsr"
PYTHONPATH="$out/pvpython-path" pvpython Testing/Wheel/pvpython_plugin_tests.py Data

#!/usr/bin/env bash
# Set-up and build (Scripts/setup.sh), then run every test: core, C++ image tests, Python,
# ParaView plugin (pvpython and pvbatch); then all but the speed-vs-error smoke test again in the
# sanitizer build (Scripts/sanitize.sh); then the pip route (Scripts/test-wheel.sh: the wheel in a
# venv with PyPI's newest vtk and pyvista, against truth and the C++ filter, and its ParaView
# plugin). Xvfb provides the X display rendering code may ask for.
set -euo pipefail
cd "$(dirname "$0")/.."
bash Scripts/setup.sh
xvfb-run -a -s "-screen 0 1280x1024x24 -noreset" ctest --test-dir build --output-on-failure
# Then the same code with AddressSanitizer + UBSan (build-asan/): any report fails the run.
bash Scripts/sanitize.sh
# The pip route: pyproject.toml's wheel, pip's VTK and PyVista, the ParaView Python plugin.
bash Scripts/test-wheel.sh

#!/usr/bin/env bash
# Set-up and build (Scripts/setup.sh), then run every test: core, C++ image tests, Python,
# ParaView plugin (pvpython and pvbatch). Xvfb provides the X display rendering code may ask for.
set -euo pipefail
cd "$(dirname "$0")/.."
bash Scripts/setup.sh
xvfb-run -a ctest --test-dir build --output-on-failure

#!/usr/bin/env bash
# Set-up and build (Scripts/setup.sh), then render the bundled default dataset (the paper's
# 27-node cube, distance field, iso-value 0.8) to cube27.png with the VTK Python pipeline.
set -euo pipefail
cd "$(dirname "$0")/.."
bash Scripts/setup.sh
PYTHONPATH="$PWD/build/lib/python3/dist-packages" /usr/bin/python3 Examples/render_isosurface.py \
  Data/cube27.vtu --iso 0.8 --size 800 800 --view 3 2.2 4.1 --out cube27.png

#!/usr/bin/env bash
# Set-up and build (Scripts/setup.sh), then render the bundled default dataset (the expansion
# flow: a Navier-Stokes solution at Reynolds number 50 on 8,396 quadratic tets, see
# Scripts/make_expansion_flow.py) to expansion_flow.png with the VTK Python pipeline: the
# isosurface speed = 0.25 of the jet, coloured by pressure.
set -euo pipefail
cd "$(dirname "$0")/.."
bash Scripts/setup.sh
PYTHONPATH="$PWD/build/lib/python3/dist-packages" /usr/bin/python3 Examples/render_isosurface.py \
  Data/expansion_flow.vtu --array speed --iso 0.25 --color-by pressure \
  --view 0.5 0.8 1 --zoom 1.6 --size 800 450 --out expansion_flow.png

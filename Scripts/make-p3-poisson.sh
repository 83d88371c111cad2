#!/usr/bin/env bash
# Runs Scripts/make_p3_poisson.py with the given arguments in the flow venv (Scripts/flow-venv.sh:
# gmsh, scipy, and ParaView's VTK), e.g.
#   bash Scripts/make-p3-poisson.sh --out Data/p3_poisson.vtu \
#       --image docs/images/p3_poisson_contour.png
set -euo pipefail
cd "$(dirname "$0")/.."
exec bash Scripts/flow-venv.sh Scripts/make_p3_poisson.py "$@"

#!/usr/bin/env bash
# Runs Scripts/make_hex_poisson.py with the given arguments in the flow venv (Scripts/flow-venv.sh:
# scikit-fem, scipy, and ParaView's VTK), e.g.
#   bash Scripts/make-hex-poisson.sh --out Data/hex_poisson.vtu \
#       --image docs/images/hex_poisson_contour.png
set -euo pipefail
cd "$(dirname "$0")/.."
exec bash Scripts/flow-venv.sh Scripts/make_hex_poisson.py "$@"

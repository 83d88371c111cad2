#!/usr/bin/env bash
# Runs Scripts/make_cylinder_flow.py with the given arguments in the flow venv
# (Scripts/flow-venv.sh: gmsh, scikit-fem, scipy, and ParaView's VTK), e.g.
#   bash Scripts/make-cylinder-flow.sh --out Data/cylinder_flow.vtu --check
set -euo pipefail
cd "$(dirname "$0")/.."
exec bash Scripts/flow-venv.sh Scripts/make_cylinder_flow.py "$@"

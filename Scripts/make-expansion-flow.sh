#!/usr/bin/env bash
# Runs Scripts/make_expansion_flow.py with the given arguments in the flow venv
# (Scripts/flow-venv.sh: gmsh, scikit-fem, pyamg, and ParaView's VTK), e.g.
#   bash Scripts/make-expansion-flow.sh --size 0.15 --out build/expansion_flow_0.15.vtu --check
set -euo pipefail
cd "$(dirname "$0")/.."
exec bash Scripts/flow-venv.sh Scripts/make_expansion_flow.py "$@"

#!/usr/bin/env bash
# The exact surface's speed-against-error study in one command: set-up and build (Scripts/setup.sh),
# then exact_surface_vs_contour.py on the bundled real datasets. Writes exact-surface.md (table) and
# exact-surface.png (plot) into the folder given (default build/exact-surface).
#   bash Testing/SpeedVsError/run_exact_surface.sh
#   DATASETS="mfem_hex_q3 p3_poisson" RUNS=1 bash Testing/SpeedVsError/run_exact_surface.sh /tmp/quick
set -euo pipefail
cd "$(dirname "$0")/../.."
bash Scripts/setup.sh > /dev/null   # also installs python3-matplotlib for the plot

OUT=${1:-build/exact-surface}
DATASETS=${DATASETS:-"mfem_hex_q3 p3_poisson hex_poisson calculix_bracket expansion_flow cylinder_flow"}
RUNS=${RUNS:-3}
COMMAND="DATASETS=\"$DATASETS\" RUNS=$RUNS bash Testing/SpeedVsError/run_exact_surface.sh $OUT"
# /usr/bin/python3 is Debian's, the one that sees ParaView's VTK and the built tetdsr module.
PYTHONPATH=build/lib/python3/dist-packages /usr/bin/python3 Testing/SpeedVsError/exact_surface_vs_contour.py \
  --data Data --out "$OUT" --datasets $DATASETS --runs "$RUNS" --command "$COMMAND"
echo "wrote $OUT/exact-surface.md and $OUT/exact-surface.png"

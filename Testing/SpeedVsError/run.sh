#!/usr/bin/env bash
# The speed-vs-error report in one command: set-up and build (Scripts/setup.sh), then every
# method on every scene under Xvfb. Writes speed-vs-error.md (tables) and speed-vs-error.png
# (time against error) into the folder given (default build/speed-vs-error).
#   bash Testing/SpeedVsError/run.sh                        # lattices n = 3 26 56, 1024 x 1024
#   SIZES=3 IMAGE=128 bash Testing/SpeedVsError/run.sh /tmp/quick   # a quick run
# FLOW lists the real flow's .vtu files (default: Data/expansion_flow.vtu if present; larger
# ones come from Scripts/make-expansion-flow.sh, e.g. FLOW="Data/expansion_flow.vtu
# build/expansion_flow_0.15.vtu").
set -euo pipefail
cd "$(dirname "$0")/../.."
bash Scripts/setup.sh > /dev/null   # also installs python3-matplotlib for the plot

OUT=${1:-build/speed-vs-error}
SIZES=${SIZES:-"3 26 56"}
IMAGE=${IMAGE:-1024}
FLOW=${FLOW-$(ls Data/expansion_flow.vtu 2> /dev/null || true)}
COMMAND="SIZES=\"$SIZES\" IMAGE=$IMAGE FLOW=\"$(echo $FLOW)\" bash Testing/SpeedVsError/run.sh $OUT"
# /usr/bin/python3 is Debian's, the one that sees ParaView's VTK and the built tetdsr module.
PYTHONPATH=build/lib/python3/dist-packages xvfb-run -a /usr/bin/python3 Testing/SpeedVsError/speed_vs_error.py \
  --out "$OUT" --sizes $SIZES --image "$IMAGE" --data Data --flow $FLOW --command "$COMMAND"
echo "wrote $OUT/speed-vs-error.md and $OUT/speed-vs-error.png"

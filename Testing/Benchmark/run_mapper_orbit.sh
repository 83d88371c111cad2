#!/usr/bin/env bash
# vtkDirectSurfaceMapper orbit benchmark (Testing/Benchmark/mapper_orbit.py) under Xvfb; prints a
# Markdown table and writes it to Testing/Benchmark/results/mapper-orbit.md.
#   bash Testing/Benchmark/run_mapper_orbit.sh                 # 1024 x 1024, lattice n = 61, 36 frames
#   bash Testing/Benchmark/run_mapper_orbit.sh --size 512 --lattice 26
# Needs the build (cmake --build build). Takes about 2 minutes on 2 cores. Other processes on the
# cores skew the timings: it first waits (at most WAIT_IDLE seconds, default 180) for the 1-minute
# load average to fall below 0.5; the table reports the load before and after.
set -euo pipefail
cd "$(dirname "$0")/../.."
BUILD=${BUILD:-build}
if [ ! -d "$BUILD/lib/python3/dist-packages/tetdsr" ]; then
  echo "no TetDSR Python package under $BUILD: run cmake --build $BUILD first" >&2
  exit 1
fi
WAIT_IDLE=${WAIT_IDLE:-180}
for ((waited = 0; waited < WAIT_IDLE; waited += 10)); do
  awk '{ exit !($1 < 0.5) }' /proc/loadavg && break
  [ "$waited" -eq 0 ] && echo "waiting for the load average ($(cut -d' ' -f1 /proc/loadavg)) to fall below 0.5..." >&2
  sleep 10
done
mkdir -p Testing/Benchmark/results
OUT=Testing/Benchmark/results/mapper-orbit.md
PYTHONPATH="$PWD/$BUILD/lib/python3/dist-packages${PYTHONPATH:+:$PYTHONPATH}" \
  xvfb-run -a -s "-screen 0 1280x1280x24" /usr/bin/python3 Testing/Benchmark/mapper_orbit.py "$@" \
  > "$OUT.tmp"
{
  echo "# vtkDirectSurfaceMapper: 36-frame orbit"
  echo
  echo "\`bash Testing/Benchmark/run_mapper_orbit.sh $*\` on $(date -u +%Y-%m-%d)."
  echo
  cat "$OUT.tmp"
} > "$OUT"
rm -f "$OUT.tmp"
cat "$OUT"

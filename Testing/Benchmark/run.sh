#!/usr/bin/env bash
# The benchmark, in one run: set-up and build (Scripts/setup.sh), a venv with the newest `vtk`
# wheel from PyPI, then TetDSR and VTK 9.2's contour + render (tetdsr-benchmark) and the wheel's
# contour + render on the same mesh files, joined into one Markdown table.
#   bash Testing/Benchmark/run.sh            # lattices n = 12 26 61 120 (10 k, 105 k, 1.36 M, 10.4 M cells)
#   SIZES="12 26" IMAGE=512 bash Testing/Benchmark/run.sh
set -euo pipefail
cd "$(dirname "$0")/../.."
# Embree, for the comparison of ray hierarchies at the end (built only where it is installed).
if ! dpkg -s libembree-dev > /dev/null 2>&1; then
  SUDO=""; if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  { $SUDO apt-get update -q && $SUDO apt-get install -y -q --no-install-recommends libembree-dev; } > /dev/null ||
    echo "libembree-dev could not be installed: the Embree comparison is skipped"
fi
bash Scripts/setup.sh > /dev/null

SIZES=${SIZES:-"12 26 61 120"}
IMAGE=${IMAGE:-1024}
OUT=build/benchmark
VENV=build/benchmark-venv
mkdir -p "$OUT"
if [ ! -x "$VENV/bin/python" ]; then
  # Any Python 3 with venv will do for the wheel (Debian's needs python3-venv; a pyenv one has it).
  python3 -m venv "$VENV"
  "$VENV/bin/pip" install -q --upgrade pip vtk
fi

echo "machine: $(nproc) cores, $(awk '/MemTotal/ {printf "%.0f GiB", $2/1048576}' /proc/meminfo), $(grep -m1 'model name' /proc/cpuinfo | cut -d: -f2 | xargs)"
echo "image: ${IMAGE}x${IMAGE}; lattices: $SIZES"
xvfb-run -a build/bin/tetdsr-benchmark "$OUT" "$IMAGE" $SIZES > "$OUT/tetdsr.tsv"
xvfb-run -a "$VENV/bin/python" Testing/Benchmark/vtk_wheel_contour.py "$OUT/tetdsr.tsv" "$OUT" "$IMAGE" \
  > "$OUT/wheel.tsv"
# Our hierarchy against Embree's BVH over the same cells, one core, at 1.36 M cells (the table's
# Embree column; its full tables are printed at the end).
EMBREE=()
if [ -x build/bin/tetdsr-embree-comparison ]; then
  build/bin/tetdsr-embree-comparison --tsv "$OUT/embree.tsv" "$IMAGE" 61 > "$OUT/embree.md"
  EMBREE=("$OUT/embree.tsv")
fi
/usr/bin/python3 Testing/Benchmark/report.py "$OUT/tetdsr.tsv" "$OUT/wheel.tsv" "${EMBREE[@]}"
echo
echo "Normal schemes (the paper's Table 1), lattice n = 26 (105,456 cells), ${IMAGE}x${IMAGE}, re-render times:"
build/bin/tetdsr-benchmark --normals "$IMAGE" 26
echo
echo "Appearance options, lattice n = 26 (105,456 cells), ${IMAGE}x${IMAGE}, re-render times (best of 3):"
build/bin/tetdsr-benchmark --options "$IMAGE" 26
echo
echo "Curved cells against their straightened copies (Testing/Benchmark/curved_cost.py), ${IMAGE}x${IMAGE}:"
PYTHONPATH="$PWD/build/lib/python3/dist-packages" /usr/bin/python3 Testing/Benchmark/curved_cost.py "$IMAGE"
if [ -f "$OUT/embree.md" ]; then
  echo
  echo "Our ray hierarchy against Embree's BVH over the same cells (tetdsr-embree-comparison), ${IMAGE}x${IMAGE}:"
  cat "$OUT/embree.md"
fi

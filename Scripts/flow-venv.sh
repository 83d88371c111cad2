#!/usr/bin/env bash
# Creates (or reuses) build/flow-venv, or the folder $TETDSR_FLOW_VENV names (a test of another
# build folder passes its own), with gmsh, scikit-fem, pyamg at pinned versions, and runs its
# Python with the given arguments; the dataset scripts (make-expansion-flow.sh,
# make-cylinder-flow.sh, make-p3-poisson.sh) go through it. The venv sees Debian's site packages
# for ParaView's VTK 9.2 (python3-paraview), which writes and checks the .vtu; its own numpy stays
# below 2 for that VTK.
set -euo pipefail
cd "$(dirname "$0")/.."

# ParaView's VTK comes from Scripts/setup.sh (which also builds TetDSR): run it only when the
# Python side of ParaView is missing, so that this script does not rebuild the project.
if ! dpkg -s python3-paraview python3-numpy > /dev/null 2>&1; then
  bash Scripts/setup.sh > /dev/null
fi
# Venv support, and the X and GL libraries gmsh's wheel loads.
EXTRA=(python3-venv libglu1-mesa libxcursor1 libxft2 libxinerama1 libxrender1 libfontconfig1)
if ! dpkg -s "${EXTRA[@]}" > /dev/null 2>&1; then
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${EXTRA[@]}"
fi

VENV="${TETDSR_FLOW_VENV:-build/flow-venv}"
if [ ! -x "$VENV/bin/python" ]; then
  /usr/bin/python3 -m venv --system-site-packages "$VENV"
fi
"$VENV/bin/pip" install -q --disable-pip-version-check \
  numpy==1.26.4 scipy==1.15.3 pyamg==5.4.1 scikit-fem==12.0.2 gmsh==4.15.2
exec "$VENV/bin/python" "$@"

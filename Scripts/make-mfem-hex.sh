#!/usr/bin/env bash
# Creates (or reuses) build/mfem-venv (PyMFEM at a pinned version) and runs
# Scripts/make_mfem_hex.py there with the given arguments, e.g.
#   bash Scripts/make-mfem-hex.sh --out Data/mfem_hex_q3.vtu
# The script writes a Q3 solution on curved hexahedra with MFEM's ParaViewDataCollection, then runs
# itself again under /usr/bin/python3 (ParaView's VTK 9.2) to check MFEM's output and write the
# .vtu. The venv does not see Debian's site packages: PyMFEM 4.10 needs numpy >= 2.4.1, ParaView's
# VTK 9.2 Debian's numpy 1.24, so each half keeps its own. PyMFEM's wheel is for CPython 3.11
# (manylinux_2_28), which Debian 12's /usr/bin/python3 is.
set -euo pipefail
cd "$(dirname "$0")/.."

# ParaView's VTK comes from Scripts/setup.sh (which also builds TetDSR): run it only when the
# Python side of ParaView is missing, so that this script does not rebuild the project.
if ! dpkg -s python3-paraview python3-numpy > /dev/null 2>&1; then
  bash Scripts/setup.sh > /dev/null
fi
if ! dpkg -s python3-venv > /dev/null 2>&1; then
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends python3-venv
fi

VENV=build/mfem-venv
if [ ! -x "$VENV/bin/python" ]; then
  /usr/bin/python3 -m venv "$VENV"
fi
"$VENV/bin/pip" install -q --disable-pip-version-check \
  mfem==4.10.0.1 numpy==2.4.6 scipy==1.17.1 numba==0.68.1 llvmlite==0.50.0
exec "$VENV/bin/python" Scripts/make_mfem_hex.py "$@"

#!/usr/bin/env bash
# Runs Scripts/make_calculix_bracket.py with the given arguments: CalculiX (Debian's calculix-ccx)
# solves an L-shaped steel bracket on 20-node hexahedra (C3D20R) and ccx2paraview converts its
# .frd into a .vtu of VTK_QUADRATIC_HEXAHEDRON cells, e.g.
#   bash Scripts/make-calculix-bracket.sh --out Data/calculix_bracket.vtu
# Installs what is missing: calculix-ccx, python3-venv, ParaView's Python VTK 9.2
# (python3-paraview, which checks and rewrites the .vtu) and numpy, and the venv
# build/calculix-venv with ccx2paraview at a pinned version. The venv sees Debian's site packages
# (ParaView's VTK, which ccx2paraview imports as `vtk`, and Debian's numpy, below 2 for that VTK).
set -euo pipefail
cd "$(dirname "$0")/.."

PACKAGES=(calculix-ccx python3-venv python3-paraview python3-numpy)
if ! dpkg -s "${PACKAGES[@]}" > /dev/null 2>&1; then
  SUDO=""
  if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends \
    "${PACKAGES[@]}"
fi

VENV=build/calculix-venv
if [ ! -x "$VENV/bin/python" ]; then
  mkdir -p build
  /usr/bin/python3 -m venv --system-site-packages "$VENV"
fi
# "numpy<2": Debian's numpy 1.24 satisfies it; pip must not bring numpy 2 for ParaView's VTK 9.2.
"$VENV/bin/pip" install -q --disable-pip-version-check ccx2paraview==3.2.0 "numpy<2"
exec "$VENV/bin/python" Scripts/make_calculix_bracket.py "$@"

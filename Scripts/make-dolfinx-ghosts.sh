#!/usr/bin/env bash
# Creates (or reuses) build/dolfinx-venv (DOLFINx's pinned wheel on a pyenv Python 3.12: DOLFINx
# needs Python >= 3.12, which Debian 12 does not have) and runs Scripts/make_dolfinx_ghosts.py on
# 2 ranks with the wheel's own MPICH mpiexec, writing into the given folder, e.g.
#   bash Scripts/make-dolfinx-ghosts.sh Testing/Data/dolfinx_ghosts
# DOLFINx's writer names the files ball.pvd, ball000000.pvtu and ball_p{0,1}_000000.vtu.
set -euo pipefail
cd "$(dirname "$0")/.."
OUT=${1:-Testing/Data/dolfinx_ghosts}

PYTHON312=${PYTHON312:-}
if [ -z "$PYTHON312" ]; then
  for candidate in python3.12 "$HOME"/.pyenv/versions/3.12*/bin/python3.12; do
    if command -v "$candidate" > /dev/null 2>&1; then PYTHON312=$(command -v "$candidate"); break; fi
  done
fi
if [ -z "$PYTHON312" ]; then
  echo "make-dolfinx-ghosts: needs a Python 3.12 (set PYTHON312=/path/to/python3.12)" >&2
  exit 1
fi
VENV=build/dolfinx-venv
if [ ! -x "$VENV/bin/python" ]; then
  "$PYTHON312" -m venv "$VENV"
fi
"$VENV/bin/pip" install -q --disable-pip-version-check dolfinx-solver-real==0.11.0.post0
mkdir -p "$OUT"
exec "$VENV/bin/mpiexec" -n 2 "$VENV/bin/python" Scripts/make_dolfinx_ghosts.py "$OUT"

#!/usr/bin/env bash
# Installs what TetDSR needs on Debian 12 (as root, or with sudo) and builds it into build/.
# Safe to re-run: packages already installed are not fetched again, the build is incremental.
set -euo pipefail
cd "$(dirname "$0")/.."

SUDO=""
if [ "$(id -u)" -ne 0 ]; then SUDO="sudo"; fi

# ParaView 5.11 brings the VTK 9.2 we build against (and the paraview client, for the GUI test);
# its CMake package needs the Qt5, MPI and third-party development packages below even for a
# server-side plugin. The pip route's tests (Scripts/test-wheel.sh) need python3-venv, and EGL for
# pip's VTK to render off screen. The GUI's responsiveness test drives the client as a user would
# (openbox, xdotool; xdpyinfo from x11-utils).
PACKAGES=(
  cmake ninja-build g++ libgtest-dev libglm-dev
  paraview paraview-dev python3-paraview python3-numpy python3-matplotlib
  qtbase5-dev libqt5svg5-dev qttools5-dev libqt5opengl5-dev qtxmlpatterns5-dev-tools
  openmpi-bin libopenmpi-dev
  libdouble-conversion-dev liblz4-dev libutfcpp-dev libexpat1-dev liblzma-dev libxml2-dev
  libfreetype-dev libpng-dev libjpeg-dev libtiff-dev libglew-dev libgl2ps-dev libeigen3-dev
  libpugixml-dev libx11-dev libxt-dev libgl-dev
  xvfb xauth libgl1-mesa-dri openbox xdotool x11-utils
  python3-venv libegl1 libegl-mesa0
)
if ! dpkg -s "${PACKAGES[@]}" > /dev/null 2>&1; then
  $SUDO apt-get update -q
  DEBIAN_FRONTEND=noninteractive $SUDO apt-get install -y -q --no-install-recommends "${PACKAGES[@]}"
fi

# /usr/bin/python3 is Debian's, the one that sees ParaView's VTK (not a pyenv python on PATH).
cmake -S . -B build -G Ninja -DCMAKE_BUILD_TYPE=Release -DPython3_EXECUTABLE=/usr/bin/python3 -Wno-dev
cmake --build build

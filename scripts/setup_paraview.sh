#!/usr/bin/env bash
# Set-up for the ParaView plugin on Debian 12 (called by `make paraview`). Idempotent.
#  1. Debian's ParaView 5.11 and Open MPI, with --no-install-recommends: a plain install
#     pulls python3-paraview, which conflicts with python3-vtk9 (both own vtkmodules)
#     and would remove libvtk9-dev, which the main build needs.
#  2. python3-paraview's files, which ParaView's CMake package and pvpython still need
#     (its vtkmodules/paraview Python packages, the wrapping hierarchy files used by the
#     client-server wrapping, pvpython itself), unpacked into a private prefix
#     build-paraview/python3-paraview with `apt-get download` + `dpkg -x`, not installed.
set -euo pipefail
cd "$(dirname "$0")/.."

APT_PACKAGES=(paraview paraview-dev openmpi-bin libopenmpi-dev xvfb xauth)
missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "[setup_paraview] installing Debian packages: ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

PREFIX=build-paraview/python3-paraview
if [ ! -x "$PREFIX/usr/bin/pvpython" ]; then
  echo "[setup_paraview] unpacking python3-paraview into $PREFIX"
  version=$(dpkg-query -W -f='${Version}' paraview)
  tmp=$(mktemp -d)
  # apt-get download writes into the current folder; _apt cannot write to a private
  # mktemp folder, which only costs a warning.
  (cd "$tmp" && apt-get download -qq "python3-paraview=$version" 2>/dev/null \
     || apt-get download -qq "python3-paraview=$version")
  mkdir -p "$PREFIX"
  dpkg -x "$tmp"/python3-paraview_*.deb "$PREFIX"
  rm -rf "$tmp"
fi

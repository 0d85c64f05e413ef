#!/usr/bin/env bash
# Set-up for HOEmbed on Debian 12: system packages (when missing) and the .venv.
# Idempotent: each step is skipped when already done. Called by `make build`.
set -euo pipefail
cd "$(dirname "$0")/.."

APT_PACKAGES=(build-essential cmake ninja-build pkg-config
  libvtk9-dev python3-vtk9 libeigen3-dev libsuitesparse-dev libcgal-dev
  python3 python3-dev python3-venv python3-pip python3-numpy python3-scipy python3-matplotlib
  python3-pil xvfb xauth patch clang-format libceres-dev)

missing=()
for p in "${APT_PACKAGES[@]}"; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing+=("$p")
done
if ((${#missing[@]})); then
  echo "[setup] installing Debian packages: ${missing[*]}"
  SUDO=""
  if [ "$(id -u)" != 0 ]; then SUDO="sudo"; fi
  export DEBIAN_FRONTEND=noninteractive
  $SUDO apt-get update -qq
  $SUDO apt-get install -y -qq --no-install-recommends "${missing[@]}"
fi

# The venv sees Debian's VTK, numpy, scipy and matplotlib (--system-site-packages).
# pip packages go in without their dependencies, and numpy is pinned to Debian's, so
# nothing replaces the numpy 1.x that VTK 9.1 was built against.
PY=.venv/bin/python
STAMP=.venv/.hoembed-setup-v1
if [ ! -x "$PY" ]; then
  echo "[setup] creating .venv"
  /usr/bin/python3 -m venv --system-site-packages .venv
fi
if [ ! -f "$STAMP" ]; then
  echo "[setup] installing Python packages into .venv"
  NUMPY=$($PY -c 'import numpy; print(numpy.__version__)')
  echo "numpy==$NUMPY" > .venv/constraints.txt
  PIP=("$PY" -m pip install -q --disable-pip-version-check -c .venv/constraints.txt)
  "${PIP[@]}" --no-deps "pyvista==0.46.5" "scikit-fem==12.0.2"
  "${PIP[@]}" "scooby>=0.5.1" "pooch>=1.8" "typing-extensions>=4.10" "pytest>=7.2" "tqdm"
  touch "$STAMP"
fi
# ruff: the Python half of the house style (make format, ctest's house.style)
if [ ! -x .venv/bin/ruff ]; then
  echo "[setup] installing ruff into .venv"
  "$PY" -m pip install -q --disable-pip-version-check --no-deps "ruff==0.17.5"
fi
# gmsh: the external mesher of Examples/Python/lagrange_fe_result.py (curved P2 meshes from
# CAD; its test skips with a reason without it)
if ! "$PY" -c "import gmsh" 2>/dev/null; then
  echo "[setup] installing gmsh into .venv"
  "$PY" -m pip install -q --disable-pip-version-check --no-deps "gmsh==4.15.2" \
    || echo "[setup] gmsh could not be installed: the Lagrange-cell example's test will skip"
fi
# nanobind (headers and CMake files only) for the package's compiled module, hoembed._hoembed
# (Wrapping/Python/CMakeLists.txt); the same version the wheel's build resolves.
if ! "$PY" -c "import nanobind" 2>/dev/null; then
  echo "[setup] installing nanobind into .venv"
  "$PY" -m pip install -q --disable-pip-version-check --no-deps "nanobind==3.1.0"
fi

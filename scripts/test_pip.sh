#!/usr/bin/env bash
# make test-pip / test-pip-vtk95: the pip package against the VTK build, on a pip VTK.
#   scripts/test_pip.sh VTK_VERSION
# 1. builds the wheel from this checkout with `pip wheel` (scikit-build-core + nanobind
#    from the package index; object files kept in build-pip/, ccache when
#    CMAKE_CXX_COMPILER_LAUNCHER says so), its stepper kernels with -march=native as
#    `make build` compiles them (HOEMBED_SIMULATION_NATIVE), for bitwise equal frames,
# 2. creates a fresh venv WITHOUT system site packages (no Debian VTK) and installs the
#    wheel, vtk==VTK_VERSION, pyvista and pytest from the package index,
# 3. writes reference outputs of the VTK build (.venv/bin/python, Debian VTK 9.1) on the
#    same inputs (Testing/Pip/generate_reference.py), and
# 4. runs Testing/Pip (test_pip.py, test_pip_mesher.py) in the fresh venv against them.
set -euo pipefail
vtk_version="${1:?usage: test_pip.sh VTK_VERSION}"
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
tag="vtk${vtk_version//./}"
venv="build-pip/venv-$tag"
ref="build-pip/reference"
data="${HOEMBED_DATA_DIR:-$root/../shared/data/meshes}"

echo "[test-pip] building the wheel"
rm -rf build-pip/dist
# the TetGen sources the VTK build fetched (pinned, hash-checked), when there: no second
# download for the wheel's copy of the mesher
tetgen=()
for src in build/_deps/tetgen/tetgen-*/src; do
  [ -f "$src/tetgen.cxx" ] && tetgen=(--config-settings=cmake.define.HOEMBED_TETGEN_SOURCE_DIR="$root/$src")
done
.venv/bin/python -m pip wheel . --no-deps -w build-pip/dist -q \
  --config-settings=cmake.define.HOEMBED_SIMULATION_NATIVE=ON "${tetgen[@]}"
wheel="$(ls build-pip/dist/hoembed-*.whl)"
echo "[test-pip] $wheel"

echo "[test-pip] fresh venv $venv (no system site packages) with vtk==$vtk_version"
rm -rf "$venv"
/usr/bin/python3 -m venv "$venv"
"$venv/bin/python" -m pip install -q "$wheel" "vtk==$vtk_version" pyvista pytest
"$venv/bin/python" -c "import sys, vtkmodules, hoembed; assert sys.prefix != sys.base_prefix; \
print('[test-pip] vtk', vtkmodules.__version__, 'from', vtkmodules.__file__)"

echo "[test-pip] reference outputs of the VTK build"
rm -rf "$ref"
HOEMBED_DATA_DIR="$data" .venv/bin/python Testing/Pip/generate_reference.py "$ref"

echo "[test-pip] tests"
HOEMBED_PIP_REFERENCE="$root/$ref" HOEMBED_DATA_DIR="$data" \
  "$venv/bin/python" -m pytest -v -p no:cacheprovider Testing/Pip

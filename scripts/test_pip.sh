#!/usr/bin/env bash
# make test-pip: the binary wheels of `make wheel` (dist/) in fresh venvs, against the VTK
# build, on a matrix of CPython x pip VTK x pyvista.
#   scripts/test_pip.sh CELL...      CELL = PYTHON:VTK:PYVISTA[:REQUIREMENT], e.g.
#                                     3.11:9.4.2:0.46.5; VTK or PYVISTA "newest": what the
#                                     index serves; REQUIREMENT: one more for the user's
#                                     side (numpy<2 for the oldest VTK and pyvista)
# Per cell:
# 1. a fresh venv WITHOUT system site packages (no Debian VTK) from that CPython (pyenv's,
#    as scripts/build_wheel.sh finds it), with the user's side first: vtk, pyvista and
#    pytest from the package index;
# 2. `pip install --only-binary=:all:` of the wheel for that CPython (cp3X, or the abi3
#    wheel for 3.12+): no compiler, no build; the user's VTK must stay the same version;
# 3. `auditwheel show` of that wheel (a manylinux policy, nothing outside it), and the
#    imported module's GMP and MPFR must be the wheel's own copies (hoembed.libs);
# 4. Testing/Pip against the VTK build's outputs (.venv/bin/python, Debian VTK 9.1, on the
#    same inputs: Testing/Pip/generate_reference.py, written once): embedding, transfer
#    and series bitwise; the stepper's frames within round-off (the portable wheel's
#    kernels are not compiled with -march=native as the VTK build's); the mesher valid
#    and close to the VTK build's (pip VTK's decimation and locators differ);
# 5. the console script: `hoembed --help`, `hoembed live --help`, `hoembed run` on a sphere.
# Then the bitwise test build: the first cell's CPython builds the wheel with the stepper
# kernels compiled as `make build` compiles them (build_wheel.sh --native; only those
# sources recompile), installed over the first cell's venv, where the stepper's frames
# must equal the VTK build's bit for bit (HOEMBED_PIP_NATIVE=1).
set -euo pipefail
(($#)) || { echo "usage: test_pip.sh PYTHON:VTK:PYVISTA..." >&2; exit 2; }
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"
ref="build-pip/reference"
data="${HOEMBED_DATA_DIR:-$root/../shared/data/meshes}"
auditwheel="build-pip/tools/bin/auditwheel"
source <(sed -n '/^find_python()/,/^}/p' scripts/build_wheel.sh)
start=$SECONDS

echo "[test-pip] reference outputs of the VTK build"
rm -rf "$ref"
HOEMBED_DATA_DIR="$data" .venv/bin/python Testing/Pip/generate_reference.py "$ref"

# the dist/ wheel a CPython installs: its own cp3X tag, or the abi3 one for 3.12+
wheel_for() {
  local tag
  tag="$("$1" -c 'import sys; v = sys.version_info
print("cp312-abi3" if v >= (3, 12) else "cp%d%d-cp%d%d" % (v[:2] * 2))')"
  ls -t dist/hoembed-*-"$tag"-manylinux*.whl 2>/dev/null | head -1 | grep . \
    || { echo "[test-pip] no $tag wheel in dist/ (make wheel)" >&2; return 1; }
}

first_venv=""
for cell in "$@"; do
  IFS=: read -r pyver vtk pv extra <<<"$cell"
  py="$(find_python "$pyver")"
  wheel="$(wheel_for "$py")"
  venv="build-pip/venv-py${pyver//./}-vtk${vtk//./}-pv${pv//./}"  # (REQUIREMENT not in the name)
  [ -n "$first_venv" ] || first_venv="$venv"
  want_vtk="vtk"; [ "$vtk" = newest ] || want_vtk="vtk==$vtk"
  want_pv="pyvista"; [ "$pv" = newest ] || want_pv="pyvista==$pv"
  echo "[test-pip] === cell $cell: $(basename "$wheel") in $venv"
  rm -rf "$venv"
  "$py" -m venv "$venv"
  vpy="$venv/bin/python"
  "$vpy" -m pip install -q --only-binary=:all: "$want_vtk" "$want_pv" pytest ${extra:+"$extra"}
  before="$("$vpy" -m pip list --format=freeze | grep -i '^vtk==')"
  "$vpy" -m pip install -q --only-binary=:all: "$wheel"
  after="$("$vpy" -m pip list --format=freeze | grep -i '^vtk==')"
  if [ "$before" != "$after" ]; then
    echo "[test-pip] installing the wheel changed the user's VTK: $before -> $after" >&2
    exit 1
  fi
  show="$("$auditwheel" show "$wheel" | tr -s ' \n' '  ')"  # one line: it wraps its text
  if ! grep -q 'consistent with the following platform tag: "manylinux_' <<<"$show" \
      || grep -q "need to be eliminated" <<<"$show"; then
    echo "$show" >&2; echo "[test-pip] $wheel is not self-contained" >&2; exit 1
  fi
  echo "[test-pip] auditwheel: $(grep -o 'platform tag: "manylinux[^"]*"' <<<"$show" | head -1)"
  "$vpy" - <<'EOF'
import os, sys, platform
import vtkmodules, pyvista
import hoembed
from hoembed import _hoembed  # noqa: F401  (the compiled module, loaded)
assert sys.prefix != sys.base_prefix and not any("dist-packages" in p for p in sys.path)
libs = os.path.join(os.path.dirname(os.path.dirname(hoembed.__file__)), "hoembed.libs")
maps = [line.split()[-1] for line in open("/proc/self/maps") if ".so" in line]
for name in ("libgmp", "libmpfr"):
    where = sorted({m for m in maps if os.path.basename(m).startswith(name)})
    assert where and all(m.startswith(libs) for m in where), (name, where)
print("[test-pip] CPython", platform.python_version(), "vtk", vtkmodules.__version__,
      "pyvista", pyvista.__version__, "hoembed from", os.path.dirname(hoembed.__file__),
      "with its own GMP/MPFR")
EOF
  # the console script: its help, and `hoembed run` end to end on a small surface
  "$venv/bin/hoembed" --help > /dev/null
  "$venv/bin/hoembed" live --help > /dev/null
  run_dir="$(mktemp -d)"
  "$vpy" -c "import pyvista, sys; pyvista.Sphere(theta_resolution=24, phi_resolution=24).save(sys.argv[1])" "$run_dir/sphere.stl"
  "$venv/bin/hoembed" run "$run_dir/sphere.stl" --elements 300 --steps 2 --no-picture \
    --output "$run_dir/out" > "$run_dir/log" 2>&1 || { cat "$run_dir/log" >&2; exit 1; }
  test -s "$run_dir/out/surface.pvd" && test -s "$run_dir/out/fe_mesh.pvd"
  rm -rf "$run_dir"
  echo "[test-pip] console script: hoembed --help, hoembed live --help, hoembed run (sphere, 300 tet10)"
  HOEMBED_PIP_REFERENCE="$root/$ref" HOEMBED_DATA_DIR="$data" \
    "$vpy" -m pytest -q -p no:cacheprovider Testing/Pip
done

echo "[test-pip] === the bitwise test build (stepper kernels with -march=native)"
IFS=: read -r pyver _ <<<"$1"
rm -rf build-pip/native
bash scripts/build_wheel.sh --native "$pyver"
"$first_venv/bin/python" -m pip install -q --no-deps --force-reinstall build-pip/native/hoembed-*.whl
HOEMBED_PIP_NATIVE=1 HOEMBED_PIP_REFERENCE="$root/$ref" HOEMBED_DATA_DIR="$data" \
  "$first_venv/bin/python" -m pytest -q -p no:cacheprovider Testing/Pip/test_pip.py -k stepper
HOEMBED_PIP_NATIVE=1 HOEMBED_PIP_REFERENCE="$root/$ref" HOEMBED_DATA_DIR="$data" \
  "$first_venv/bin/python" -m pytest -q -p no:cacheprovider Testing/Pip/test_pip_live.py
echo "[test-pip] done in $((SECONDS - start)) s"

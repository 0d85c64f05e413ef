#!/usr/bin/env bash
# The sanitizer suite (`make test-sanitize`, part of `make test`): the C++ tests and a
# subset of the Python tests on the AddressSanitizer + UndefinedBehaviorSanitizer build.
# Any report in HOEmbed's code fails the run (ASan halts, UBSan halts on error); known
# reports in third-party code are suppressed by Testing/sanitizers/*.supp, each entry
# with its reason.
#   usage: scripts/test_sanitize.sh [BUILD_DIR] [PYTHON_TEST_REGEX]
set -uo pipefail
root="$(cd "$(dirname "$0")/.." && pwd)"
dir="$(cd "${1:-build-asan}" && pwd)"
pyre="${2:-^py\.}"
sup="$root/Testing/sanitizers"
export ASAN_OPTIONS="halt_on_error=1:detect_leaks=1:detect_odr_violation=0:suppressions=$sup/asan.supp"
export LSAN_OPTIONS="suppressions=$sup/lsan.supp:print_suppressions=0"
export UBSAN_OPTIONS="halt_on_error=1:print_stacktrace=1:suppressions=$sup/ubsan.supp"
XVFB=(xvfb-run -a -s "-screen 0 1280x1024x24 -noreset")
cd "$dir"
start=$(date +%s)
# The find_package example builds and installs a second copy: it tests packaging, not
# memory, and is run by the unsanitized suite.
"${XVFB[@]}" ctest --output-on-failure -j 1 -R '^cxx\.' -E 'ExampleFindPackage'
rc_cxx=$?
# The Python interpreter and numpy leak by design at exit: leak checking is for the C++
# tests. The ASan runtime is preloaded into Python by the tests' environment
# (HOEMBED_TEST_PYTHON_PRELOAD), and inherited by the subprocesses the tests start.
# The fuzz test runs fewer cases under the sanitizers (each is several times slower).
HOEMBED_FUZZ_CASES="${HOEMBED_FUZZ_CASES:-120}" \
ASAN_OPTIONS="$ASAN_OPTIONS:detect_leaks=0" "${XVFB[@]}" ctest --output-on-failure -j 1 -R "$pyre"
rc_py=$?
echo "[test-sanitize] C++ rc=$rc_cxx, Python rc=$rc_py, $(( $(date +%s) - start )) s"
[ "$rc_cxx" = 0 ] && [ "$rc_py" = 0 ]

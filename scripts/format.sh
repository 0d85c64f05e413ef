#!/usr/bin/env bash
# make format: the house style on every tracked source file (.clang-format for C++, the
# [tool.ruff] table of pyproject.toml for Python). With --check it changes nothing and
# exits non-zero when a file differs (ctest's house.style runs that; it is skipped, exit
# 77, outside a git checkout, where the tracked files are unknown).
# TetGen's sources (fetched at configure time) are not tracked, so never touched.
set -euo pipefail
cd "$(dirname "$0")/.."
RUFF=${RUFF:-.venv/bin/ruff}
CLANG_FORMAT=${CLANG_FORMAT:-clang-format}
if ! git rev-parse --is-inside-work-tree >/dev/null 2>&1; then
  echo "format.sh: not a git checkout, the tracked files are unknown" >&2
  exit 77
fi
mapfile -t cxx < <(git ls-files '*.cxx' '*.h')
if [ "${1:-}" = "--check" ]; then
  status=0
  "$CLANG_FORMAT" --dry-run --Werror "${cxx[@]}" || status=1
  "$RUFF" format --check --quiet . || status=1
  "$RUFF" check --quiet . || status=1
  exit $status
fi
"$CLANG_FORMAT" -i "${cxx[@]}"
"$RUFF" format --quiet .
"$RUFF" check --fix --quiet .

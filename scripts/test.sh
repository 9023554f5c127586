#!/usr/bin/env bash
# Quick-start command 2: install what is missing, build, and run the test suite with ctest.
# The default runs the `unit` and `verification` labels; `scripts/test.sh --all` adds `slow`.
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$repo/scripts/setup.sh"
jobs=$(nproc 2>/dev/null || echo 2)
if [ "${1:-}" = "--all" ]; then
  exec ctest --test-dir "$repo/build" --output-on-failure -j "$jobs"
fi
exec ctest --test-dir "$repo/build" --output-on-failure -j "$jobs" -LE slow

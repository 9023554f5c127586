#!/usr/bin/env bash
# Quick-start command 1: install what is missing, build, and run the fast verification tier.
# Extra arguments go to `talus verify` (e.g. --tier full).
set -euo pipefail
repo="$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)"
"$repo/scripts/setup.sh"
cd "$repo"
exec "$repo/build/talus" verify --tier fast "$@"

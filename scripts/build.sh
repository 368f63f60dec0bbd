#!/usr/bin/env bash
# Configures (once) and builds splatkit incrementally. Usage: scripts/build.sh [BUILD_DIR] [cmake args]
# Used by demo.sh and test.sh; BUILD_DIR defaults to build/ at the top of the repository.
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
dir=${1:-$top/build}
shift || true
if [ ! -f "$dir/build.ninja" ]; then
  cmake -S "$top" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
fi
jobs=${SPLATKIT_JOBS:-$(nproc)}
cmake --build "$dir" -j "$jobs"

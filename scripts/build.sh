#!/usr/bin/env bash
# Configures and builds splatkit incrementally. Usage: scripts/build.sh [BUILD_DIR] [cmake args]
# Used by demo.sh and test.sh; BUILD_DIR defaults to build/ at the top of the repository. The first
# run configures (Ninja, Release unless the arguments say otherwise); a later run with cmake args
# re-runs cmake on the existing directory so that new options (e.g. -DSPLATKIT_BUILD_BENCH=ON)
# take effect, and the build stays incremental.
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
dir=${1:-$top/build}
shift || true
if [ ! -f "$dir/build.ninja" ]; then
  cmake -S "$top" -B "$dir" -G Ninja -DCMAKE_BUILD_TYPE=Release "$@" >/dev/null
elif [ $# -gt 0 ]; then
  cmake -S "$top" -B "$dir" "$@" >/dev/null
fi
jobs=${SPLATKIT_JOBS:-$(nproc)}
cmake --build "$dir" -j "$jobs"

#!/usr/bin/env bash
# kNN of every point (k = 16, 1M points, 2 threads): splatkit::SpatialIndex vs nanoflann vs PCL
# KdTreeFLANN, build and queries timed separately, with ratios.
# usage: scripts/bench/knn.sh [points] [k] [threads] [repeats]   (build dir: $BUILD_DIR)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-bench}
# A new build dir gets no tests; an existing one keeps its SPLATKIT_BUILD_TESTS (as graph.sh).
options=(-DCMAKE_BUILD_TYPE=Release -DSPLATKIT_BUILD_BENCH=ON)
[ -f "$build/CMakeCache.txt" ] || options+=(-DSPLATKIT_BUILD_TESTS=OFF)
cmake -S "$root" -B "$build" -G Ninja "${options[@]}" >/dev/null
ninja -C "$build" -j2 bench_knn >/dev/null
"$build/scripts/bench/bench_knn" "${1:-1000000}" "${2:-16}" "${3:-2}" "${4:-2}"

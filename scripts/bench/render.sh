#!/usr/bin/env bash
# Rendering speed: splat-view's frame renderer (tile-binned local ray casting, bounded A-buffer,
# Z-threshold blending, deferred Phong, 8-bit sRGB) against a naive two-pass software splatter
# (one thread, no tiles), on a sphere of N splats about 2.5 px across at 1920x1080. Prints
# ms/frame, the split by stage, M splats/s and the ratio. End to end per frame = from the splats
# in memory to the finished 8-bit image in memory (file encoding is not part of a frame).
# usage: scripts/bench/render.sh [splats=1000000] [threads=2] [frames=7] [runs=3]
#        (build dir: $BUILD_DIR, default build-bench)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-bench}
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSPLATKIT_BUILD_BENCH=ON \
  -DSPLATKIT_BUILD_TESTS=OFF >/dev/null
ninja -C "$build" -j2 bench_render >/dev/null
# The machine may be shared: run several times and keep the best splatkit frame.
best=""
best_rate=0
for _ in $(seq "${4:-3}"); do
  out=$("$build/scripts/bench/bench_render" "${1:-1000000}" 1920 1080 "${2:-2}" "${3:-7}" 2.5)
  rate=$(awk '/^splatkit:/ {print $4}' <<<"$out")
  if awk -v a="$rate" -v b="$best_rate" 'BEGIN {exit !(a > b)}'; then
    best=$out
    best_rate=$rate
  fi
done
echo "$best"

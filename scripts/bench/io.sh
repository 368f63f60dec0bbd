#!/usr/bin/env bash
# PLY reading speed: splatkit::read_ply against PCL's pcl::PLYReader (into PointNormal), on one
# binary little-endian file of N points (x y z nx ny nz radius as float, red green blue as uchar)
# read from the page cache. Each reader runs in its own process (peak RSS is its own) REPEATS
# times; the best wall time counts. Prints MB/s (wall and per CPU second: the machine may be
# shared), peak RSS and the ratios.
# usage: scripts/bench/io.sh [points=10000000] [repeats=3]   (build dir: $BUILD_DIR)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-bench}
points=${1:-10000000}
repeats=${2:-3}

tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSPLATKIT_BUILD_BENCH=ON \
  -DSPLATKIT_BUILD_TESTS=OFF >"$tmp/build.log" 2>&1 &&
  ninja -C "$build" -j2 bench_read_ply >>"$tmp/build.log" 2>&1 || { cat "$tmp/build.log"; exit 1; }
bench=$build/scripts/bench/bench_read_ply

file=$tmp/points.ply
"$bench" --make "$points" "$file"
cat "$file" >/dev/null  # warm the page cache

# best_of READER ARGS...: the run with the highest MB/s, as printed by bench_read_ply.
best_of() {
  local best="" line
  for _ in $(seq "$repeats"); do
    line=$("$bench" "$@")
    if [[ -z $best ]] || (($(field "$line" mb_per_s) > $(field "$best" mb_per_s))); then
      best=$line
    fi
  done
  echo "$best"
}
field() { sed -E "s/.*$2=([0-9.]+).*/\1/" <<<"$1"; }

ours=$(best_of "$file")
peer=$(best_of --pcl "$file")
echo "$ours"
echo "$peer"
awk -v a="$(field "$ours" mb_per_s)" -v b="$(field "$peer" mb_per_s)" \
    -v ca="$(field "$ours" mb_per_cpu_s)" -v cb="$(field "$peer" mb_per_cpu_s)" \
    -v ra="$(field "$ours" peak_rss_mib)" -v rb="$(field "$peer" peak_rss_mib)" \
    'BEGIN { printf "splatkit/pcl: wall speed %.2fx, CPU speed %.2fx, peak RSS %.2f\n", a / b, ca / cb, ra / rb }'

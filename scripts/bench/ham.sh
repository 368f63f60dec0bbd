#!/usr/bin/env bash
# HAM speed and memory, build-ham against the same computation done with OpenCV (cv::Sobel 3x3
# in x and y with BORDER_REPLICATE, cv::magnitude, twice; per-tile maxima by cv::minMaxLoc),
# whole processes with I/O: read an uncompressed float32 TIFF (in the page cache), write the tile
# records. Prints the best wall time of RUNS for each, M samples/s and the ratio (goal: >= 2x).
# Then build-ham's peak RSS on a SIZE_RSS^2 map (goal: <= 256 MB), the projected time and RSS for
# 65536^2, and, with BIG > 0, one real run on a BIG^2 map streamed from the generator through a
# pipe (RAW float32 on stdin: no file, no memory for the map).
#   ours:   build-ham IN.tif OUT.exr --threads T
#   opencv: bench_ham_opencv IN.tif OUT.bin 64 T
# usage: scripts/bench/ham.sh [size=8192] [threads=2] [runs=3] [size_rss=16384] [big=0]
#        (build dir: $BUILD_DIR, default build-bench; OpenCV needed for the side-by-side part)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-bench}
size=${1:-8192} threads=${2:-2} runs=${3:-3} size_rss=${4:-16384} big=${5:-0}
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSPLATKIT_BUILD_BENCH=ON \
  -DSPLATKIT_BUILD_TESTS=OFF >/dev/null
targets=(make_heightmap build-ham)
have_opencv=0
if grep -q '^build bench_ham_opencv\|bench_ham_opencv:' "$build/build.ninja"; then
  targets+=(bench_ham_opencv)
  have_opencv=1
fi
ninja -C "$build" -j2 "${targets[@]}" >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
gen=$build/scripts/bench/make_heightmap

# best_of CMD...: the best wall time (s) and its peak RSS (KB) over $runs runs: "WALL RSS".
best_of() {
  local best="" rss="" t
  for _ in $(seq "$runs"); do
    /usr/bin/time -f "%e %M" -o "$work/time" "$@" >/dev/null 2>&1
    t=$(tail -1 "$work/time")
    if [ -z "$best" ] || awk -v a="${t% *}" -v b="$best" 'BEGIN {exit !(a < b)}'; then
      best=${t% *}
      rss=${t#* }
    fi
  done
  echo "$best $rss"
}

"$gen" "$size" "$size" "$work/h.tif"
cat "$work/h.tif" >/dev/null  # into the page cache
samples=$((size * size))
read -r ours ours_rss <<<"$(best_of "$build/tools/build-ham" "$work/h.tif" "$work/t.exr" --threads "$threads" -q)"
ours_rate=$(awk -v n="$samples" -v t="$ours" 'BEGIN {printf "%.1f", n / t / 1e6}')
echo "ours:   build-ham h.tif t.exr --threads $threads (${size}x${size} float32 TIFF):" \
  "$ours s, $ours_rate M samples/s, peak RSS $((ours_rss / 1024)) MB"
if [ "$have_opencv" = 1 ]; then
  read -r peer peer_rss <<<"$(best_of "$build/scripts/bench/bench_ham_opencv" "$work/h.tif" "$work/t.bin" 64 "$threads")"
  peer_rate=$(awk -v n="$samples" -v t="$peer" 'BEGIN {printf "%.1f", n / t / 1e6}')
  echo "opencv: bench_ham_opencv h.tif t.bin 64 $threads: $peer s, $peer_rate M samples/s," \
    "peak RSS $((peer_rss / 1024)) MB"
  ratio=$(awk -v a="$peer" -v b="$ours" 'BEGIN {printf "%.2f", a / b}')
  verdict=$(awk -v r="$ratio" 'BEGIN {if (r + 0 >= 2) print "met"; else print "NOT met"}')
  echo "ratio (opencv time / ours): ${ratio}x, goal >= 2x: $verdict"
else
  echo "opencv: not found (install libopencv-dev for the side-by-side run)"
fi

# Memory: a SIZE_RSS^2 TIFF, and the projection to 65536^2 (rows held grow with the width only).
"$gen" "$size_rss" "$size_rss" "$work/r.tif"
rm -f "$work/h.tif"
read -r rss_time rss_kb <<<"$(runs=1 best_of "$build/tools/build-ham" "$work/r.tif" "$work/r.exr" --threads "$threads" -q)"
echo "memory: build-ham r.tif (${size_rss}x${size_rss} float32 TIFF) --threads $threads:" \
  "$rss_time s, peak RSS $((rss_kb / 1024)) MB, goal <= 256 MB:" \
  "$( [ "$rss_kb" -le $((256 * 1024)) ] && echo met || echo NOT met)"
rm -f "$work/r.tif"
projected_s=$(awk -v t="$ours" -v n="$samples" 'BEGIN {printf "%.0f", t / n * 65536 * 65536}')
projected_mb=$(awk -v r8="$ours_rss" -v r16="$rss_kb" -v s8="$size" -v s16="$size_rss" \
  'BEGIN {printf "%.0f", (r16 + (r16 - r8) * (65536 - s16) / (s16 - s8)) / 1024}')
echo "projected for 65536x65536 (4.3 G samples): $projected_s s at the ${size}^2 speed," \
  "peak RSS about $projected_mb MB (linear in the width from the two runs above)"

if [ "$big" -gt 0 ]; then
  /usr/bin/time -f "%e %M" -o "$work/time" bash -c \
    "'$gen' $big $big - | '$build/tools/build-ham' - '$work/big.exr' --raw $big,$big,float32 --threads $threads -q"
  read -r t kb <<<"$(tail -1 "$work/time")"
  echo "real run: make_heightmap $big $big - | build-ham - big.exr --raw $big,$big,float32" \
    "--threads $threads: $t s (generator included), peak RSS $((kb / 1024)) MB (the larger process)"
fi

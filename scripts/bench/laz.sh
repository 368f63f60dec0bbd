#!/usr/bin/env bash
# LAZ decoding: splatkit's LASzip decoder against laz-perf (LASzip's models compiled to
# WebAssembly, npm "laz-perf", under node) and against splatkit's own LAS reader on the same
# points uncompressed, in one run. Input: splat-synth cad with scan lines, colours and intensity
# as a scanner records them (--texture; point format 2), written as LAZ and LAS by splat-convert;
# and the same points as LAS 1.4 point format 7 (LASzip's layered chunks), decoded by both.
#   decode:  laz_records dump IN.laz /dev/null T  (records only: header, chunk table, decoding)
#   laz-perf: node tests/laz/lazperf_dump.js IN.laz OUT.bin (records, same bytes; checked)
#   whole:   splat-convert --threads T IN.laz OUT.splk  vs  splat-convert IN.las OUT.splk
# Prints points/s and the ratios, and what the range decoder's serial chain alone costs these
# points on this machine (laz_floor.cpp: an estimate of the least time a decoder that runs one
# chain per chunk needs, not a bound); exits 1 when decoding is below the goal of 20 M points/s.
# usage: scripts/bench/laz.sh [points] [threads] [repeats]
#   (build dir: $BUILD_DIR, default build/, configured with tests for laz_records;
#    laz-perf: $SPLATKIT_LAZ_PERF_DIR, a node_modules directory holding laz-perf)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build}
points=${1:-3000000} threads=${2:-2} repeats=${3:-3}
lazperf=${SPLATKIT_LAZ_PERF_DIR:-$build/node/node_modules}
export NODE_PATH=$lazperf  # (the format 7 runs call node directly: their CPU times apart)
ninja -C "$build" -j2 splat-synth splat-convert laz_records >/dev/null
bin=$build/tools
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin/splat-synth" -q cad "$work/in.ply" -n "$points" --scan-lines 4 --seed=1 --texture
"$bin/splat-convert" -q "$work/in.ply" "$work/in.laz"
"$bin/splat-convert" -q "$work/in.laz" "$work/in.las"
"$bin/splat-convert" -q --las-format 7 "$work/in.ply" "$work/in7.laz"
rm "$work/in.ply"
echo "input: $points points (textured colours, intensity), point format 2, $(stat -c%s "$work/in.laz") bytes LAZ," \
  "$(stat -c%s "$work/in.las") bytes LAS, threads $threads"

seconds() {  # seconds CMD...: wall time of one run; its CPU time (user + system) goes to $work/cpu
  local t0 t1
  t0=$(date +%s.%N)
  /usr/bin/time -f "%U %S" -o "$work/time" "$@" >/dev/null
  t1=$(date +%s.%N)
  awk '{ printf "%.4f\n", $1 + $2 }' "$work/time" >>"$work/cpu.$(basename "$1")"
  awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.4f\n", b - a }'
}
cpu() { sort -g "$work/cpu.$(basename "$1")" | head -1; }  # least CPU seconds of the runs of program $1
best() { printf '%s\n' "$@" | sort -g | head -1; }
rate() { awk -v n="$points" -v s="$1" 'BEGIN { printf "%.2f", n / s / 1e6 }'; }

dec=() lp=() wlaz=() wlas=() dec7=() lp7=()
cp "$build/tests/laz_records" "$work/laz_records7"  # its own name: its CPU times apart
for r in $(seq "$repeats"); do
  dec+=("$(seconds "$build/tests/laz_records" dump "$work/in.laz" /dev/null "$threads")")
  dec7+=("$(seconds "$work/laz_records7" dump "$work/in7.laz" /dev/null "$threads")")
  wlaz+=("$(seconds "$bin/splat-convert" -q --threads "$threads" "$work/in.laz" "$work/a.splk")")
  wlas+=("$(seconds "$bin/splat-convert" -q --threads "$threads" "$work/in.las" "$work/b.splk")")
  if command -v node >/dev/null && [ -d "$lazperf/laz-perf" ]; then
    lp+=("$(seconds env NODE_PATH="$lazperf" node "$root/tests/laz/lazperf_dump.js" "$work/in.laz" "$work/lp.bin")")
    lp7+=("$(seconds node "$root/tests/laz/lazperf_dump.js" "$work/in7.laz" "$work/lp7.bin")")
  fi
done
cmp -s "$work/a.splk" "$work/b.splk" || echo "note: the .splk files differ (header JSON: LAS vs LAZ)"
d=$(best "${dec[@]}")
echo "decode (ours, $threads threads):   $(rate "$d") M points/s  ($d s wall;" \
  "$(cpu "$build/tests/laz_records") s CPU = $(rate "$(cpu "$build/tests/laz_records")") M points/s per busy core)"
uptime | sed 's/.*load/machine load/' 
if [ ${#lp[@]} -gt 0 ]; then
  "$build/tests/laz_records" dump "$work/in.laz" "$work/ours.bin" >/dev/null
  cmp -s "$work/ours.bin" "$work/lp.bin" || { echo "laz-perf decodes other records"; exit 1; }
  l=$(best "${lp[@]}")
  echo "decode (laz-perf, node, 1 thread): $(rate "$l") M points/s  ($l s wall, $(cpu env) s CPU; same records)"
  echo "ratio ours / laz-perf: $(awk -v a="$l" -v b="$d" 'BEGIN { printf "%.1f", a / b }')x"
fi
d7=$(best "${dec7[@]}")
echo "format 7 (LAS 1.4, layered), $(stat -c%s "$work/in7.laz") bytes LAZ:"
echo "decode (ours, $threads threads):   $(rate "$d7") M points/s  ($d7 s wall;" \
  "$(cpu "$work/laz_records7") s CPU = $(rate "$(cpu "$work/laz_records7")") M points/s per busy core)"
if [ ${#lp7[@]} -gt 0 ]; then
  "$build/tests/laz_records" dump "$work/in7.laz" "$work/ours7.bin" >/dev/null
  cmp -s "$work/ours7.bin" "$work/lp7.bin" || { echo "laz-perf decodes other format 7 records"; exit 1; }
  l7=$(best "${lp7[@]}")
  echo "decode (laz-perf, node, 1 thread): $(rate "$l7") M points/s  ($l7 s wall, $(cpu node) s CPU; same records)"
  echo "ratio ours / laz-perf: $(awk -v a="$l7" -v b="$d7" 'BEGIN { printf "%.1f", a / b }')x"
else
  echo "laz-perf: not found in $lazperf (npm install --prefix $build/node laz-perf); skipped"
fi
a=$(best "${wlaz[@]}") b=$(best "${wlas[@]}")
echo "whole splat-convert .laz -> .splk: $(rate "$a") M points/s ($a s);" \
  ".las -> .splk: $(rate "$b") M points/s ($b s); LAZ / LAS time: $(awk -v a="$a" -v b="$b" 'BEGIN { printf "%.2f", a / b }')"
# The chain alone (scripts/bench/src/laz_floor.cpp), timed on random bytes, times the
# operations a point of the format 2 input takes: 15.84 symbols of tabled models and 3.52 raw
# reads per point, counted once with counters in ArithmeticDecoder for the default 3 M points
# (other point counts change the point spacing, and so these counts, a little). Its streams
# average 6 bits per operation, the chain's model 3.6: the estimate errs towards speed.
"${CXX:-c++}" -O3 -std=c++20 -I"$root/lib" "$root/scripts/bench/src/laz_floor.cpp" -o "$work/laz_floor"
"$work/laz_floor" 15.84 3.52 "$threads" | tee "$work/floor.txt"
f=$(sed -n 's/^chain alone.*, \([0-9.]*\) M points\/s on .*/\1/p' "$work/floor.txt")
echo "format 2, ours / chain alone: $(awk -v a="$(rate "$d")" -v b="$f" 'BEGIN { printf "%.2f", a / b }')" \
  "(the goal of 20 M points/s: $(awk -v b="$f" 'BEGIN { printf "%.2f", 20 / b }') of the chain alone)"
awk -v r="$(rate "$d")" 'BEGIN { exit !(r >= 20) }' && echo "goal >= 20 M points/s: met" ||
  { echo "goal >= 20 M points/s: MISSED"; exit 1; }

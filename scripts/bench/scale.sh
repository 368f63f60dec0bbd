#!/usr/bin/env bash
# Scaling: whole commands as a user runs them on i.i.d. random tori (splat-synth torus --random,
# shuffled like a merged scan), 2 threads, at several sizes: estimate-normals (read .splk ->
# write .splk, MST orientation included) with its orient phase (kNN rows included),
# build-splat-graph, segment-surfaces and splat-view's load (a 64x36 frame, so the time is the read and the scene set-up). Prints
# seconds, microseconds per point, and peak RSS per point (bytes), then each tool's time per
# point at the largest size over the smallest (the target: at most 1.3).
# With OUT_OF_CORE=M (and MAX_MEMORY, default 2G), then one out-of-core run: estimate-normals
# --max-memory on M million points (its output then through build-spt --max-memory), printing
# time per point, peak RSS against the limit, and the temporary disk used (the spill file's peak,
# from the report), and its time per point over the in-memory one at the largest size above.
# usage: [OUT_OF_CORE=200 MAX_MEMORY=2G] scripts/bench/scale.sh [millions of points...]
#        (default sizes: 1 4 16; build dir: $BUILD_DIR, default build; temporary files, the
#        spill file included, in $TMPDIR)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build}
ninja -C "$build" -j2 splat-synth estimate-normals build-splat-graph segment-surfaces \
  splat-view build-spt >/dev/null
bin=$build/tools
sizes=("$@")
[ ${#sizes[@]} -gt 0 ] || sizes=(1 4 16)
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

# run NAME POINTS COMMAND...: times the command with GNU time, prints a row, records us/point.
# Clouds of up to 4M points run three times and keep the fastest run (a run of under a second
# varies by a third on a shared machine; the larger ones, run once, are not favoured by this);
# the peak RSS is the largest of the runs. estimate-normals' report is kept from its fastest run.
declare -A first
run() {
  local name=$1 n=$2
  shift 2
  local repeats=1 secs="" kb=0 s k
  [ "$n" -gt 4000000 ] || repeats=3
  for _ in $(seq "$repeats"); do
    /usr/bin/time -f "%e %M" -o "$work/time" "$@"
    read -r s k <"$work/time"
    [ "$k" -le "$kb" ] || kb=$k
    if [ -z "$secs" ] || awk -v a="$s" -v b="$secs" 'BEGIN {exit !(a < b)}'; then
      secs=$s
      [ "$name" != estimate-normals ] || cp "$work/normals.json" "$work/best-normals.json"
    fi
  done
  local us rss
  us=$(awk -v s="$secs" -v n="$n" 'BEGIN {printf "%.3f", s / n * 1e6}')
  rss=$(awk -v k="$kb" -v n="$n" 'BEGIN {printf "%.0f", k * 1024 / n}')
  printf "%-18s %6dM %8.2f s %8s us/point %6s B/point peak\n" "$name" $((n / 1000000)) "$secs" \
    "$us" "$rss"
  [ -n "${first[$name]:-}" ] || first[$name]=$us
  last[$name]=$us
}
declare -A last
orient_first="" orient_last=""
for m in "${sizes[@]}"; do
  n=$((m * 1000000))
  "$bin/splat-synth" -q torus "$work/in.splk" -n "$n" --random --no-color
  run estimate-normals "$n" "$bin/estimate-normals" -q "$work/in.splk" "$work/normals.splk" \
    --threads 2 --report "$work/normals.json"
  # The orientation's time with its kNN rows (found before the radius bound, which reads them).
  phase() { tr -d '\n ' <"$work/best-normals.json" | grep -o "\"$1\":[0-9.e+-]*" | cut -d: -f2; }
  orient=$(awk -v a="$(phase orient)" -v b="$(phase knn_rows)" 'BEGIN {print a + b}')
  us=$(awk -v s="$orient" -v n="$n" 'BEGIN {printf "%.3f", s / n * 1e6}')
  printf "%-18s %6dM %8.2f s %8s us/point\n" "  of which orient" "$m" "$orient" "$us"
  [ -n "$orient_first" ] || orient_first=$us
  orient_last=$us
  run build-splat-graph "$n" "$bin/build-splat-graph" -q "$work/normals.splk" "$work/graph.splk" \
    --threads 2
  run segment-surfaces "$n" "$bin/segment-surfaces" -q "$work/graph.splk" "$work/surf.splk" \
    --threads 2
  run "splat-view load" "$n" "$bin/splat-view" -q "$work/surf.splk" -o "$work/v.png" \
    --width 64 --height 36 --threads 2
  rm -f "$work"/*.splk "$work"/*.json
done
echo "time per point, largest size over smallest (target <= 1.3):"
for name in estimate-normals build-splat-graph segment-surfaces "splat-view load"; do
  awk -v a="${first[$name]}" -v b="${last[$name]}" -v t="$name" \
    'BEGIN {printf "  %-18s %.2fx\n", t, b / a}'
done
awk -v a="$orient_first" -v b="$orient_last" 'BEGIN {printf "  %-18s %.2fx\n", "orient", b / a}'

[ -n "${OUT_OF_CORE:-}" ] || exit 0
limit=${MAX_MEMORY:-2G}
n=$((OUT_OF_CORE * 1000000))
echo "out of core: $OUT_OF_CORE M points, --max-memory $limit"
"$bin/splat-synth" -q torus "$work/in.splk" -n "$n" --random --no-color
rm -f "$work/normals.splk"
limit_bytes=$(numfmt --from=iec "$limit")
for tool in estimate-normals build-spt; do
  if [ $tool = estimate-normals ]; then
    args=("$work/in.splk" "$work/normals.splk")
  else
    rm -f "$work/in.splk"  # (disk: only what the next command reads)
    args=("$work/normals.splk" "$work/out.spt")
  fi
  /usr/bin/time -f "%e %M" -o "$work/time" "$bin/$tool" -q "${args[@]}" --threads 2 \
    --max-memory "$limit" --report "$work/ooc.json"
  read -r s k <"$work/time"
  spill=$(tr -d '\n ' <"$work/ooc.json" | grep -o '"temporary_peak_bytes":[0-9]*' | cut -d: -f2)
  awk -v s="$s" -v n="$n" -v k="$k" -v l="$limit_bytes" -v d="$spill" -v t="$tool" 'BEGIN {
    printf "%-18s %8.1f s %8.3f us/point  peak RSS %.0f MiB (%.2f of the limit)  temporary disk %.1f GiB (%.0f B/point)\n",
      t, s, s / n * 1e6, k / 1024, k * 1024 / l, d / 2^30, d / n }'
  if [ $tool = estimate-normals ]; then
    awk -v s="$s" -v n="$n" -v b="${last[estimate-normals]}" \
      'BEGIN {printf "  time per point over the in-memory one: %.2fx (target <= 2)\n", s / n * 1e6 / b}'
  fi
done

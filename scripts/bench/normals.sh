#!/usr/bin/env bash
# estimate-normals --method pca --orient none against PCL's NormalEstimationOMP on a 1M-point torus
# (splat-synth, area-uniform), k = 16, 2 threads; both programs time their work after reading the
# file (ours: duplicate merge + kd-tree + PCA normals + radii, from its --report; PCL: kd-tree
# build + normals inside compute()), and the whole commands are timed too. Prints the ratios, the
# peak RSS per point and the agreement of the normals (within 0.5°, up to sign), and exits 1 when a
# target is missed (>= 3x faster, <= 250 bytes/point, >= 99.9 % agree). Ours runs with --keep-order:
# the normals are compared point by point in the input's order.
# usage: scripts/bench/normals.sh [points] [k] [threads] [repeats] [synth options...]
#   (build dir: $BUILD_DIR; e.g. 'normals.sh 1000000 16 2 3 --random' for an i.i.d. sample)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-bench}
points=${1:-1000000} k=${2:-16} threads=${3:-2} repeats=${4:-3}
shift $(($# < 4 ? $# : 4))
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSPLATKIT_BUILD_BENCH=ON \
  -DSPLATKIT_BUILD_TESTS=OFF >/dev/null
ninja -C "$build" -j2 estimate-normals splat-synth bench_normals_pcl >/dev/null
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/tools/splat-synth" -q torus "$work/torus.ply" -n "$points" "$@"

# json_value KEY FILE: the number after the first "KEY": in a JSON file (compact or pretty).
json_value() { grep -o "\"$1\": *[-0-9.e+]*" "$2" | head -1 | sed 's/.*: *//'; }
# json_timing KEY FILE: seconds of phase KEY in an estimate-normals --report.
json_timing() {
  tr -d '\n ' < "$2" | grep -o '"timings_s":{[^}]*}' | grep -o "\"$1\":[-0-9.e+]*" | cut -d: -f2
}
min() { printf '%s\n' "$@" | sort -g | head -1; }

ours=() ours_cmd=() pcl=() pcl_cmd=() rss=()
for _ in $(seq "$repeats"); do
  /usr/bin/time -f "%e %M" -o "$work/time" "$build/tools/estimate-normals" -q "$work/torus.ply" \
    "$work/ours.ply" --method pca --orient none -k "$k" --threads "$threads" --keep-order \
    --report "$work/r.json"
  ours+=("$(json_timing total "$work/r.json")")
  ours_cmd+=("$(cut -d' ' -f1 "$work/time")")
  rss+=("$(json_value peak_rss_bytes_per_point "$work/r.json")")
  /usr/bin/time -f "%e %M" -o "$work/time" "$build/scripts/bench/bench_normals_pcl" \
    "$work/torus.ply" -k "$k" --threads "$threads" --compare "$work/ours.ply" > "$work/pcl.json"
  pcl+=("$(json_value pcl_s "$work/pcl.json")")
  pcl_cmd+=("$(cut -d' ' -f1 "$work/time")")
done
# The same run with the default orientation (mst): what orientation adds.
"$build/tools/estimate-normals" -q "$work/torus.ply" "$work/ours-mst.ply" --method pca -k "$k" \
  --threads "$threads" --report "$work/r-mst.json"
orient_s=$(json_timing orient "$work/r-mst.json")
n=$(json_value output_points "$work/r.json")
agree=$(json_value agree_fraction "$work/pcl.json")
t_ours=$(min "${ours[@]}") t_pcl=$(min "${pcl[@]}")
c_ours=$(min "${ours_cmd[@]}") c_pcl=$(min "${pcl_cmd[@]}")
bpp=$(min "${rss[@]}")
echo "normals: torus, $n points, k = $k, $threads threads, best of $repeats (synth options: ${*:-none})"
echo "  phases of ours, last run: $(tr -d '\n ' < "$work/r.json" | grep -o '"timings_s":{[^}]*}')"
awk -v to="$t_ours" -v tp="$t_pcl" -v co="$c_ours" -v cp="$c_pcl" -v n="$n" -v bpp="$bpp" \
  -v agree="$agree" -v os="$orient_s" -v maxdeg="$(json_value max_deg "$work/pcl.json")" 'BEGIN {
  printf "  %-46s %9s %9s %7s\n", "", "ours_s", "pcl_s", "x_ours"
  printf "  %-46s %9.3f %9.3f %7.2f\n", "after reading: kNN build + normals (+ radii)", to, tp, tp / to
  printf "  %-46s %9.3f %9.3f %7.2f\n", "whole command (read, compute, ours writes)", co, cp, cp / co
  printf "  ours: %.0f points/s, peak RSS %.1f bytes/point; --orient mst adds %.3f s\n", n / to, bpp, os
  printf "  agreement with PCL: %.4f %% of points within 0.5 deg (max %.3f deg)\n", agree * 100, maxdeg
  ok = (tp / to >= 3) && (bpp <= 250) && (agree >= 0.999)
  printf "  targets (>= 3x, <= 250 B/point, >= 99.9 %%): %s\n", ok ? "met" : "NOT met"
  exit !ok }'

#!/usr/bin/env bash
# Segmentation quality on the CAD-like part with known smooth patches: splat-synth cad
# (9 patches, patch_id ground truth; stratified and --random sampling, clean and with Gaussian
# noise of 0.125 % of the bounding-box diagonal) -> estimate-normals --method robust ->
# build-splat-graph -> segment-surfaces, then per true patch the best-matching surface by IoU
# (bench_segmentation_iou). Three ways of segmenting the same graph:
#   refined     the defaults: robust surfaces, borders refined by fitted primitives, fragments
#               merged, coplanar surfaces joined (--refine-rounds 8 --merge-below 50
#               --coplanar-scales 3)
#   robust      the robust surfaces alone (--refine-rounds 0 --merge-below 1 --coplanar-scales 0)
#   components  the method of [IvoMSc] §5.4 (docs/references.md) alone (--method components
#               --refine-rounds 0 --merge-below 1 --coplanar-scales 0)
# Columns: segments, patches with IoU >= 0.95, the lowest IoU, segment-surfaces' phase times
# (segment, refine, merge; from --report) and the normals' noise it measured.
# Targets (refined, every size, sampling and noise): every patch with IoU >= 0.95 and at most
# 1.5 × as many segments as patches. Exits 1 when a target is missed.
# usage: scripts/bench/segmentation-quality.sh [sizes] [threads]
#   sizes: a quoted list, default "100000 1000000"; build dir: $BUILD_DIR (default build-bench)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-bench}
sizes=${1:-100000 1000000} threads=${2:-2}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
# (PCL's CMake files warn about optional io features on stderr: shown only when the build fails)
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSPLATKIT_BUILD_BENCH=ON \
  >"$work/build.log" 2>&1 || { cat "$work/build.log" >&2; exit 1; }
ninja -C "$build" -j2 splat-synth estimate-normals build-splat-graph segment-surfaces \
  bench_segmentation_iou >"$work/build.log" 2>&1 || { cat "$work/build.log" >&2; exit 1; }
bin=$build/tools

# json FILE KEY...: a number from segment-surfaces' report ("-" when absent).
json() {
  python3 - "$@" <<'PY'
import json, sys
v = json.load(open(sys.argv[1]))
for k in sys.argv[2:]:
    v = v.get(k, {}) if isinstance(v, dict) else {}
print(f"{v:.4f}" if isinstance(v, float) else (v if v != {} else "-"))
PY
}

status=0
printf '%-8s %-6s %-7s %-10s %8s %9s %8s %8s %8s %8s %s\n' splats sample noise method segments \
  recovered min_iou seg_s refine_s merge_s noise_deg
for n in $sizes; do
  for sampling in stratified random; do
    for noise in 0 0.00125; do
      random=$([ "$sampling" = random ] && echo --random || true)
      "$bin/splat-synth" -q cad "$work/in.ply" -n "$n" --noise "$noise" --no-color $random
      "$bin/estimate-normals" -q "$work/in.ply" "$work/n.ply" --method robust \
        --threads "$threads" 2>/dev/null
      "$bin/build-splat-graph" -q "$work/n.ply" "$work/g.splk" --threads "$threads"
      for method in refined robust components; do
        case $method in
          refined) args=() ;;
          robust) args=(--refine-rounds 0 --merge-below 1 --coplanar-scales 0) ;;
          components) args=(--method components --refine-rounds 0 --merge-below 1
            --coplanar-scales 0) ;;
        esac
        "$bin/segment-surfaces" -q "$work/g.splk" "$work/s.ply" --threads "$threads" \
          --report "$work/s.json" "${args[@]}"
        "$build/scripts/bench/bench_segmentation_iou" "$work/s.ply" >"$work/iou.txt"
        if [ "$method" = refined ] && [ "$noise" != 0 ] && [ "$n" = "${sizes##* }" ]; then
          echo "  per patch, $n splats, $sampling, noise $noise, refined:"
          sed -n 's/^patch/    patch/p' "$work/iou.txt"
        fi
        read -r ok total < <(awk '/^recovered/{print $2, $4}' "$work/iou.txt")
        segments=$(awk '/^segments/{print $2}' "$work/iou.txt")
        printf '%-8s %-6s %-7s %-10s %8s %6s/%-2s %8s %8s %8s %8s %s\n' "$n" "${sampling:0:6}" \
          "$noise" "$method" "$segments" "$ok" "$total" \
          "$(awk '/^min_iou/{print $2}' "$work/iou.txt")" \
          "$(json "$work/s.json" timings_s segment)" "$(json "$work/s.json" timings_s refine)" \
          "$(json "$work/s.json" timings_s merge)" "$(json "$work/s.json" normal_noise_degrees)"
        if [ "$method" = refined ]; then
          [ "$ok" = "$total" ] || status=1
          [ $((segments * 2)) -le $((total * 3)) ] || status=1
        fi
      done
    done
  done
done
echo "targets (refined: every patch IoU >= 0.95, segments <= 1.5 x patches):" \
  "$([ $status = 0 ] && echo met || echo NOT met)"
exit $status

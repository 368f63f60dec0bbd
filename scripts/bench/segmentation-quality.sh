#!/usr/bin/env bash
# Segmentation quality on the CAD-like part with known smooth patches: splat-synth cad
# (9 patches, patch_id ground truth) -> estimate-normals --method robust -> build-splat-graph ->
# segment-surfaces (robust surfaces, the default; and --method components, the method of
# [IvoMSc] §5.4 (docs/references.md), for
# comparison), then per true patch the best-matching surface by IoU (bench_segmentation_iou).
# Targets: clean, every patch with IoU >= 0.95; with Gaussian noise of 0.125 % of the bounding-box
# diagonal, >= 80 % of the patches. Exits 1 when a target is missed at any size.
# usage: scripts/bench/segmentation-quality.sh [sizes] [threads]
#   sizes: a quoted list, default "50000 200000 1000000"; build dir: $BUILD_DIR
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-bench}
sizes=${1:-50000 200000 1000000} threads=${2:-2}
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSPLATKIT_BUILD_BENCH=ON \
  >/dev/null
ninja -C "$build" -j2 splat-synth estimate-normals build-splat-graph segment-surfaces \
  bench_segmentation_iou >/dev/null
bin=$build/tools
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT

status=0
printf '%-9s %-7s %-10s %8s %8s %9s %8s %s\n' splats noise method segments recovered fraction \
  min_iou noise_deg
for n in $sizes; do
  for noise in 0 0.00125; do
    "$bin/splat-synth" -q cad "$work/in.ply" -n "$n" --noise "$noise" --no-color
    "$bin/estimate-normals" -q "$work/in.ply" "$work/n.ply" --method robust --threads "$threads" \
      2>/dev/null
    "$bin/build-splat-graph" -q "$work/n.ply" "$work/g.splk" --threads "$threads"
    for method in robust components; do
      "$bin/segment-surfaces" -q "$work/g.splk" "$work/s.ply" --method "$method" \
        --report "$work/s.json"
      "$build/scripts/bench/bench_segmentation_iou" "$work/s.ply" >"$work/iou.txt"
      if [ "$method" = robust ] && [ "$n" = "${sizes##* }" ]; then
        echo "  per patch, $n splats, noise $noise, robust:"
        sed -n 's/^patch/    patch/p' "$work/iou.txt"
      fi
      read -r ok total < <(awk '/^recovered/{print $2, $4}' "$work/iou.txt")
      noise_deg=$(grep -o '"normal_noise_degrees": *[-0-9.e+]*' "$work/s.json" | sed 's/.*: *//' || true)
      awk -v n="$n" -v noise="$noise" -v m="$method" -v ok="$ok" -v total="$total" \
        -v seg="$(awk '/^segments/{print $2}' "$work/iou.txt")" \
        -v min="$(awk '/^min_iou/{print $2}' "$work/iou.txt")" -v nd="${noise_deg:--}" \
        'BEGIN { printf "%-9s %-7s %-10s %8s %5s/%-2s %9.3f %8s %s\n", n, noise, m, seg, ok, total,
                 ok / total, min, nd }'
      if [ "$method" = robust ]; then
        if [ "$noise" = 0 ] && [ "$ok" != "$total" ]; then status=1; fi
        if [ "$noise" != 0 ] && [ $((ok * 10)) -lt $((total * 8)) ]; then status=1; fi
      fi
    done
  done
done
echo "targets (robust: clean every patch IoU >= 0.95, noisy >= 80 % of patches):" \
  "$([ $status = 0 ] && echo met || echo NOT met)"
exit $status

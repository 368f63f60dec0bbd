#!/usr/bin/env bash
# Segmentation of a real photogrammetry scan with labelled planes: CGAL's building.ply (100 k
# points, facades and roofs, sparse vegetation; segment_index labels 19 planes, -1 the rest;
# scripts/fetch-cgal-scans.sh) -> estimate-normals -> build-splat-graph -> segment-surfaces, all
# with their defaults (the input's own normals are replaced: they flip in places), then per
# labelled plane the best-matching surface by IoU over the labelled points
# (bench_segmentation_iou --unlabelled -1). Side by side: pcl::RegionGrowing with its defaults on
# PCL's own normals (bench_segmentation_pcl).
# Columns per label: points, then for each method its best surface and IoU. Then the mean IoU,
# the labels with IoU >= 0.8 and the number of segments (over all points).
# Target (segment-surfaces' defaults): every labelled plane with IoU >= 0.8. Exits 1 when missed.
# usage: scripts/bench/segmentation-real.sh [threads]
#   build dir: $BUILD_DIR (default build-bench); the scan is fetched into $SCAN_DIR (default
#   $BUILD_DIR/cgal-scans) unless already there; extra options for the stages (experiments):
#   $NORMALS_ARGS (estimate-normals), $GRAPH_ARGS (build-splat-graph), $SEGMENT_ARGS
#   (segment-surfaces); $KEEP_DIR: keep the intermediate files there.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-bench}
threads=${1:-2}
scans=${SCAN_DIR:-$build/cgal-scans}
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSPLATKIT_BUILD_BENCH=ON \
  >"$work/build.log" 2>&1 || { cat "$work/build.log" >&2; exit 1; }
ninja -C "$build" -j2 estimate-normals build-splat-graph segment-surfaces \
  bench_segmentation_iou bench_segmentation_pcl >"$work/build.log" 2>&1 ||
  { cat "$work/build.log" >&2; exit 1; }
bin=$build/tools
[ -f "$scans/building.ply" ] || "$root/scripts/fetch-cgal-scans.sh" "$scans" >/dev/null
out=${KEEP_DIR:-$work}
mkdir -p "$out"

# shellcheck disable=SC2086  # the *_ARGS are word lists
{
  "$bin/estimate-normals" -q "$scans/building.ply" "$out/n.ply" --threads "$threads" \
    ${NORMALS_ARGS:-}
  "$bin/build-splat-graph" -q "$out/n.ply" "$out/g.splk" --threads "$threads" ${GRAPH_ARGS:-}
  "$bin/segment-surfaces" -q "$out/g.splk" "$out/s.ply" --threads "$threads" \
    --report "$out/s.json" ${SEGMENT_ARGS:-}
} 2>"$work/stages.log" || { cat "$work/stages.log" >&2; exit 1; }
"$build/scripts/bench/bench_segmentation_pcl" "$scans/building.ply" "$out/pcl.ply" 2>/dev/null
score() {
  "$build/scripts/bench/bench_segmentation_iou" "$1" --truth segment_index --unlabelled -1 \
    --threshold 0.8
}
score "$out/s.ply" >"$out/ours.txt"
score "$out/pcl.ply" >"$out/pcl.txt"

printf '%-6s %7s   %-22s %-22s\n' label points "segment-surfaces" "pcl RegionGrowing"
printf '%-6s %7s   %-8s %-13s %-8s %-13s\n' "" "" surface iou surface iou
# Both list every label once, ascending.
paste <(awk '/^patch/ { print $2, $4, $6, $10 }' "$out/ours.txt") \
  <(awk '/^patch/ { print $6, $10 }' "$out/pcl.txt") |
  while read -r label points surface iou pcl_surface pcl_iou; do
    printf '%-6s %7s   %-8s %-13s %-8s %-13s\n' "$label" "$points" "$surface" "$iou" \
      "$pcl_surface" "$pcl_iou"
  done
for m in ours pcl; do
  printf '%-5s mean_iou %s, recovered (>= 0.8) %s of %s, min_iou %s, segments %s\n' "$m" \
    "$(awk '/^mean_iou/ { print $2 }' "$out/$m.txt")" \
    "$(awk '/^recovered/ { print $2 }' "$out/$m.txt")" \
    "$(awk '/^recovered/ { print $4 }' "$out/$m.txt")" \
    "$(awk '/^min_iou/ { print $2 }' "$out/$m.txt")" \
    "$(awk '/^segments/ { print $2 }' "$out/$m.txt")"
done
read -r ok total < <(awk '/^recovered/ { print $2, $4 }' "$out/ours.txt")
echo "target (segment-surfaces' defaults: every labelled plane IoU >= 0.8):" \
  "$([ "$ok" = "$total" ] && echo met || echo NOT met)"
[ "$ok" = "$total" ]

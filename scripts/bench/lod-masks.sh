#!/usr/bin/env bash
# Level-of-detail silhouettes: do the QSplat (.qs) and Sequential Point Tree (.spt) renders of a
# point file cover the pixels its plain render covers? Runs estimate-normals (defaults; skipped
# when the input already is a .splk), build-qsplat and build-spt, then renders the plain .splk,
# the .qs and the .spt at WIDTHxHEIGHT from four orbit views (azimuth 0, 90, 180, 270 at
# elevation EL) over a magenta background the models never show, and prints per view and model
# the mask IoU against the plain render, the pixels lost and grown, the PSNR (8-bit RGB) over
# the pixels both cover, and the regions of 20 or more of those pixels differing by more than 40
# levels (scripts/bench/mask_iou.py).
# usage: scripts/bench/lod-masks.sh POINTS [OUT_DIR]
#   env: BUILD_DIR (default build), EL (20), WIDTH (1280), HEIGHT (720), THREADS (2),
#        VIEW_ARGS (extra splat-view options for all three renders, e.g. "--blend zbuffer"),
#        QS_ARGS / SPT_ARGS (extra options for the .qs / .spt render, e.g. "--qsplat-threshold 4")
#   OUT_DIR keeps the models and images (default: a temporary directory, removed at the end).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build}
in=${1:?usage: lod-masks.sh POINTS [OUT_DIR]}
ninja -C "$build" -j2 estimate-normals build-qsplat build-spt splat-view >/dev/null
bin=$build/tools
if [ -n "${2:-}" ]; then
  work=$2
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
el=${EL:-20} width=${WIDTH:-1280} height=${HEIGHT:-720} threads=${THREADS:-2}
case $in in
  *.splk) cp "$in" "$work/model.splk" ;;
  *) "$bin/estimate-normals" -q "$in" "$work/model.splk" --threads "$threads" ;;
esac
"$bin/build-qsplat" -q "$work/model.splk" "$work/model.qs" --threads "$threads"
"$bin/build-spt" -q "$work/model.splk" "$work/model.spt" --threads "$threads"
# shellcheck disable=SC2086  # the *_ARGS are lists of options
view() {
  "$bin/splat-view" -q "$1" -o "$2" --width "$width" --height "$height" --view "$3,$el" \
    --background 1,0,1 --threads "$threads" ${VIEW_ARGS:-} "${@:4}"
}
printf "%-5s %-4s %7s %8s %8s %9s %7s %7s\n" view lod iou lost grown ref_px psnr_db regions
for az in 0 90 180 270; do
  view "$work/model.splk" "$work/plain-$az.png" "$az"
  # shellcheck disable=SC2086
  view "$work/model.qs" "$work/qs-$az.png" "$az" ${QS_ARGS:-}
  # shellcheck disable=SC2086
  view "$work/model.spt" "$work/spt-$az.png" "$az" ${SPT_ARGS:-}
  /usr/bin/python3 "$root/scripts/bench/mask_iou.py" 255,0,255 "$work/plain-$az.png" \
    "$work/qs-$az.png" "$work/spt-$az.png" |
    awk -v az="$az" '{
      lod = $1; sub(/.*\//, "", lod); sub(/-.*/, "", lod)
      printf "%-5s %-4s %7.4f %8d %8d %9d %7.2f %7d\n", az, lod, $3, $5, $7, $9, $11, $13 }'
done

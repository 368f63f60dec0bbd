#!/usr/bin/env bash
# Merged level-of-detail files against the whole survey's: a city from splat-synth (its own
# normals and radii) cut by splat-tile, each tile's .spt built from its own points and merged
# (build-spt --merge), against the .spt built over the whole city in one process. Renders both
# at WIDTHxHEIGHT from the orbit views 0,20 / 120,35 / 45,60 over a magenta background and
# prints per view the mask IoU and the PSNR over the pixels both cover (scripts/bench/mask_iou.py)
# (docs/design/tiles.md, "Merged level-of-detail files").
# usage: scripts/bench/lod-merge.sh [OUT_DIR]
#   env: BIN (default build/tools), POINTS (1000000), TILE (64), TILE_ARGS (extra splat-tile
#        options), WIDTH (1280), HEIGHT (720), THREADS (2)
#   OUT_DIR keeps the models and images (default: a temporary directory, removed at the end).
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
bin=${BIN:-$root/build/tools}
if [ -n "${1:-}" ]; then
  work=$1
  mkdir -p "$work"
else
  work=$(mktemp -d)
  trap 'rm -rf "$work"' EXIT
fi
points=${POINTS:-1000000} tile=${TILE:-64} threads=${THREADS:-2}
width=${WIDTH:-1280} height=${HEIGHT:-720}
cd "$work"
[ -e city.splk ] || "$bin/splat-synth" -q city city.splk -n "$points"
rm -rf tiled lod
# shellcheck disable=SC2086  # TILE_ARGS is a list of options
"$bin/splat-tile" -q city.splk -o tiled --tile-size "$tile" ${TILE_ARGS:-}
mkdir -p lod
for t in tiled/tiles/*.splk; do
  "$bin/build-spt" -q "$t" "lod/$(basename "$t" .splk).spt" --threads "$threads"
done
"$bin/build-spt" -q --merge lod/*.spt merged.spt --report merged.json
"$bin/build-spt" -q city.splk whole.spt --threads "$threads"
tiles=(lod/*.spt)
echo "tiles: ${#tiles[@]}, merged entries $(jq .entries merged.json)"
for view in 0,20 120,35 45,60; do
  for m in merged whole; do
    "$bin/splat-view" -q "$m.spt" -o "$m-${view/,/_}.png" --width "$width" --height "$height" \
      --view "$view" --background 1,0,1 --threads "$threads"
  done
  echo "view $view: $(/usr/bin/python3 "$root/scripts/bench/mask_iou.py" 255,0,255 \
    "whole-${view/,/_}.png" "merged-${view/,/_}.png")"
done

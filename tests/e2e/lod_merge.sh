# build-spt --merge and build-qsplat --merge on a survey cut by splat-tile: each tile's .spt and
# .qs built from its own points, then merged into one; the merged files render as those built over
# the whole survey in one process (splat-view at two orbit views, 960x540, mask IoU and PSNR over
# the pixels both cover, scripts/bench/mask_iou.py); the same bytes for any order of the tiles and
# on a second run; inputs that cannot be merged are refused with one line naming the file.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
cd "$WORK"
python=/usr/bin/python3  # mask_iou.py's numpy
$python -c 'import numpy' 2>/dev/null || { fail "numpy is missing (scripts/install-deps.sh)"; finish; }
bash "$SRC/scripts/make-test-survey.sh" "$WORK" "$BIN" 40000
"$BIN/splat-tile" -q scans/*.laz -o tiled --tile-size 12 --threads 1
mkdir -p lod
for tile in tiled/tiles/*.splk; do
  name=$(basename "$tile" .splk)
  "$BIN/estimate-normals" -q "$tile" "lod/$name.splk" --threads 2
  "$BIN/build-spt" -q "lod/$name.splk" "lod/$name.spt" --threads 2
  "$BIN/build-qsplat" -q "lod/$name.splk" "lod/$name.qs" --threads 2
done
tiles=$(ls lod/*.spt | wc -l)
[ "$tiles" -ge 4 ] && pass || fail "only $tiles tiles"
# A tile's files hold its own points only: together, each point once.
own=$(jq '[.tiles[].own_points] | add' tiled/tiles.json)
expect_exit 0 "$BIN/build-spt" -q --merge lod/*.spt merged.spt --report spt.json
expect_eq "merged .spt points" "$(jq .input_points spt.json)" "$own"
expect_exit 0 "$BIN/build-qsplat" -q --merge lod/*.qs merged.qs --report qs.json
expect_eq "merged .qs leaves" "$(jq .leaves qs.json)" "$own"
# The whole survey in one process, over the same splats (the tiles' own points).
"$BIN/splat-convert" -q lod/*.splk whole.splk
"$BIN/build-spt" -q whole.splk whole.spt --threads 2
"$BIN/build-qsplat" -q whole.splk whole.qs --threads 2
# PSNR and IoU of the merged renders against the whole ones. .spt: each tile's octree is built
# in the survey's Morton cube and coded over its box (splat-tile's survey_box), so the tiles'
# entries are the whole list's but for the cells across the tiles' borders, the r values rounded
# on the tiles' scales, and the nodes above the tiles' roots (measured 62.3 and 56.2 dB, IoU
# 1.0000; 41.9-49.8 dB, IoU 0.9991-0.9995 with each tile in its own cube). .qs: each leaf quantised twice, in its tile's frame
# and again under its new parent (docs/design/tiles.md: measured 28.7-31.1 dB, IoU 0.969-0.980;
# the whole .qs against the plain render gives 33-36 dB).
render() {
  "$BIN/splat-view" -q "$1" -o "$2" --width 960 --height 540 --view "$3" --background 1,0,1 \
    --threads 2
}
for view in 0,20 120,35; do
  for m in merged whole; do
    render "$m.spt" "$m-spt-${view/,/_}.png" "$view"
    render "$m.qs" "$m-qs-${view/,/_}.png" "$view"
  done
  for kind in spt:50:0.9995 qs:27:0.96; do
    IFS=: read -r ext db iou <<<"$kind"
    line=$($python "$SRC/scripts/bench/mask_iou.py" 255,0,255 "whole-$ext-${view/,/_}.png" \
      "merged-$ext-${view/,/_}.png")
    echo "$ext view $view: $line" >&2
    awk -v db="$db" -v iou="$iou" '{ exit !($3 >= iou && $11 >= db) }' <<<"$line" && pass ||
      fail "merged .$ext at --view $view: $line (want IoU >= $iou, PSNR >= $db dB)"
  done
done
# Tiles cut at the Morton cells of the survey's cube (--morton-grid; the lod tiles cut again:
# their own points, normals kept): the merge gives the whole list but for the r values' rounding
# and the new nodes.
"$BIN/splat-tile" -q lod/*.splk -o morton --tile-size 12 --morton-grid --threads 1
expect_eq "--morton-grid tile side" "$(jq '.tile_size < 12 and .tile_size > 6' morton/tiles.json)" true
for tile in morton/tiles/*.splk; do
  "$BIN/build-spt" -q "$tile" "${tile%.splk}.spt" --threads 2
done
expect_exit 0 "$BIN/build-spt" -q --merge morton/tiles/*.spt morton.spt
for view in 0,20 120,35; do
  render morton.spt "morton-${view/,/_}.png" "$view"
  line=$($python "$SRC/scripts/bench/mask_iou.py" 255,0,255 "whole-spt-${view/,/_}.png" \
    "morton-${view/,/_}.png")
  echo "spt --morton-grid view $view: $line" >&2
  awk '{ exit !($3 >= 0.9995 && $11 >= 50) }' <<<"$line" && pass ||
    fail "merged .spt of --morton-grid tiles at --view $view: $line (want IoU >= 0.9995, 50 dB)"
done
# The same bytes in any order of the tiles and on a second run.
"$BIN/build-spt" -q --merge $(ls lod/*.spt | sort -r) reversed.spt
cmp -s merged.spt reversed.spt && pass || fail "the .spt depends on the order of the tiles"
"$BIN/build-spt" -q --merge lod/*.spt again.spt
cmp -s merged.spt again.spt && pass || fail "a second .spt merge gave other bytes"
"$BIN/build-qsplat" -q --merge lod/*.qs again.qs
cmp -s merged.qs again.qs && pass || fail "a second .qs merge gave other bytes"
# Refused: a file of the other format, tiles of another epsilon, several inputs without --merge,
# a build option with --merge; nothing written.
first=$(ls lod/*.spt | head -1)
expect_exit 2 "$BIN/build-spt" -q --merge "$first" lod/"$(basename "$first" .spt)".qs bad.spt
expect_stderr "^build-spt: lod/[^:]*\.qs: byte 0: .*magic"
"$BIN/build-spt" -q "${first%.spt}.splk" other-eps.spt --epsilon 0.002
expect_exit 2 "$BIN/build-spt" -q --merge lod/*.spt other-eps.spt bad.spt
expect_stderr "^build-spt: other-eps\.spt: epsilon 0\.002 differs from lod/"
expect_exit 1 "$BIN/build-spt" -q lod/*.spt bad.spt
expect_stderr "build-spt: .*--merge"
expect_exit 1 "$BIN/build-spt" -q --merge --epsilon 0.002 lod/*.spt bad.spt
expect_stderr "build-spt: --epsilon does not apply to --merge"
expect_exit 2 "$BIN/build-qsplat" -q --merge "${first%.spt}.qs" "$first" bad.qs
expect_stderr "^build-qsplat: lod/[^:]*\.spt: byte 0: "
"$BIN/splat-synth" -q sphere -n 2000 coloured.splk  # the survey's tiles have no colours
"$BIN/build-qsplat" -q coloured.splk coloured.qs
expect_exit 2 "$BIN/build-qsplat" -q --merge lod/*.qs coloured.qs bad.qs
expect_stderr "^build-qsplat: coloured\.qs: colour present differs"
[ ! -e bad.spt ] && [ ! -e bad.qs ] && pass || fail "a refused merge left an output"
expect_exit 1 "$BIN/splat-tile" -q - -o bad-tiles --tile-size 12 --morton-grid </dev/null
expect_stderr "splat-tile: --morton-grid reads the inputs twice: not with '-'"
finish

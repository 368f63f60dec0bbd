# splat-view occlusion culling end to end: a small city from splat-synth with its walkthrough
# path, rendered with --path in every --occlusion mode: every frame byte-identical to
# --occlusion none, the report's counts consistent (something culled, fewer splats drawn), and
# one-line errors for bad paths and unsupported combinations.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
V=$BIN/splat-view
Y=$BIN/splat-synth

expect_exit 0 "$Y" -q city "$WORK/city.splk" -n 150000 --blocks 4 --walkthrough "$WORK/walk.json" \
  --walk-frames 5
python3 -c "import json,sys; p=json.load(open(sys.argv[1])); assert len(p)==5 and 'eye' in p[0]" \
  "$WORK/walk.json" && pass || fail "walkthrough path is not 5 cameras"

# The city: same seed, same bytes; another seed, another city; bad sizes refused.
expect_exit 0 "$Y" -q city "$WORK/city2.splk" -n 150000 --blocks 4
cmp -s "$WORK/city.splk" "$WORK/city2.splk" && pass || fail "city: same seed gave other bytes"
expect_exit 0 "$Y" -q city "$WORK/city3.splk" -n 150000 --blocks 4 --seed 2
cmp -s "$WORK/city.splk" "$WORK/city3.splk" && fail "city: seed 2 gave the same bytes" || pass
expect_exit 1 "$Y" city "$WORK/x.splk" --blocks 1
expect_stderr "--blocks must be in 2..64"

for mode in none frustum hierarchical chc chc++; do
  mkdir -p "$WORK/$mode"
  extra=()
  [ "$mode" = "chc++" ] && extra=(--count-visible)
  expect_exit 0 "$V" -q "$WORK/city.splk" -o "$WORK/$mode/f_%02d.png" --path "$WORK/walk.json" \
    --width 192 --height 108 --occlusion "$mode" --stats "$WORK/$mode.json" "${extra[@]}"
  [ -f "$WORK/$mode/f_04.png" ] && pass || fail "$mode: frame 4 missing"
done
for mode in frustum hierarchical chc chc++; do
  for f in 00 01 02 03 04; do
    cmp -s "$WORK/none/f_$f.png" "$WORK/$mode/f_$f.png" && pass || fail "$mode: frame $f differs from none"
  done
done
for mode in hierarchical chc chc++; do
  python3 - "$WORK/$mode.json" "$WORK/none.json" <<'PY' && pass || fail "$mode: report counts"
import json, sys
j = json.load(open(sys.argv[1])); n = json.load(open(sys.argv[2]))
t = j["occlusion_total"]
assert j["occlusion"] in ("hierarchical", "chc", "chc++")
assert t["nodes_culled_occlusion"] > 0 and t["queries"] > 0
assert len(j["frames"]) == 5
assert sum(f["splats_in"] for f in j["frames"]) == t["splats_drawn"]
assert t["splats_drawn"] < sum(f["splats_in"] for f in n["frames"])
PY
done
python3 -c "import json,sys; j=json.load(open(sys.argv[1])); assert j['occlusion_total']['multiqueries'] >= 0 and j['bvh']['leaves'] > 1" \
  "$WORK/chc++.json" && pass || fail "chc++ report"
# --count-visible: the splats shown and the floor (those rendered alone) per frame; the splat
# test culled splats inside drawn leaves.
python3 - "$WORK/chc++.json" <<'PY' && pass || fail "chc++: --count-visible report"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["occlusion_total"]["splats_culled"] > 0
for f in j["frames"]:
    o = f["occlusion"]
    assert 0 < o["splats_visible"] and o["floor_ms"] > 0 and o["splats_drawn"] == f["splats_in"]
PY

# The SAH split gives the same images.
expect_exit 0 "$V" -q "$WORK/city.splk" -o "$WORK/sah_%02d.png" --path "$WORK/walk.json" \
  --width 192 --height 108 --occlusion chc++ --bvh-split sah --bvh-leaf 512
cmp -s "$WORK/none/f_03.png" "$WORK/sah_03.png" && pass || fail "sah: frame 3 differs from none"

# Bad paths and combinations.
echo '[{"eye": [0, 0, 1]}]' >"$WORK/bad1.json"
expect_exit 2 "$V" "$WORK/city.splk" -o "$WORK/x_%02d.png" --path "$WORK/bad1.json"
expect_stderr "needs \"eye\" and \"target\""
echo '[{"eye": [0, 0, 1], "target": [1, 0, 1], "fvo": 30}]' >"$WORK/bad2.json"
expect_exit 2 "$V" "$WORK/city.splk" -o "$WORK/x_%02d.png" --path "$WORK/bad2.json"
expect_stderr "unknown key"
echo 'not json' >"$WORK/bad3.json"
expect_exit 2 "$V" "$WORK/city.splk" -o "$WORK/x_%02d.png" --path "$WORK/bad3.json"
expect_exit 2 "$V" "$WORK/city.splk" -o "$WORK/x_%02d.png" --path "$WORK/missing.json"
expect_exit 1 "$V" "$WORK/city.splk" -o "$WORK/x.png" --path "$WORK/walk.json"
expect_exit 1 "$V" "$WORK/city.splk" -o "$WORK/x_%02d.png" --path "$WORK/walk.json" --view 10,10
expect_exit 1 "$V" "$WORK/city.splk" -o "$WORK/x.png" --occlusion chc++ --blend zbuffer
expect_exit 1 "$V" "$WORK/city.splk" -o "$WORK/x.png" --occlusion magic
# A careless user's inputs: --bvh-leaf at its extremes (1), one splat and 100 identical splats
# under chc++ (an image), an empty cloud (2), a camera path that is empty or looks nowhere (2),
# frames into a missing directory (4); nothing left behind.
sweep_ply "$WORK/empty.ply" 0; sweep_ply "$WORK/one.ply" 1; sweep_ply "$WORK/dup.ply" 100
for v in 0 -1 1e12 nan inf; do
  expect_exit 1 "$BIN/splat-view" -q "$WORK/dup.ply" -o "$WORK/x.png" --occlusion chc++ --bvh-leaf "$v"
  grep -q "^splat-view: --bvh-leaf: " "$WORK/stderr" && pass || fail "--bvh-leaf $v: $(head -1 "$WORK/stderr")"
done
for f in one dup; do
  expect_exit 0 "$BIN/splat-view" -q "$WORK/$f.ply" -o "$WORK/$f.png" --occlusion chc++ --width 32 --height 24
done
expect_exit 2 "$BIN/splat-view" -q "$WORK/empty.ply" -o "$WORK/x.png" --occlusion chc++
expect_stderr "empty.ply: the cloud has no points"
echo '[]' >"$WORK/empty-path.json"
echo '[{"eye": [0, 0, 0], "target": [0, 0, 0]}]' >"$WORK/same-path.json"
expect_exit 2 "$BIN/splat-view" -q "$WORK/dup.ply" -o "$WORK/p-%04d.png" --path "$WORK/empty-path.json"
expect_stderr "empty-path.json: a camera path must be a non-empty JSON array"
expect_exit 2 "$BIN/splat-view" -q "$WORK/dup.ply" -o "$WORK/p-%04d.png" --path "$WORK/same-path.json"
expect_stderr "same-path.json: camera 0: eye and target are the same point"
expect_exit 4 "$BIN/splat-view" -q "$WORK/dup.ply" -o "$WORK/no/such/p-%04d.png" --path "$WORK/walk.json" \
  --width 32 --height 24
expect_stderr "no/such/p-0000.png: cannot create"
[ ! -e "$WORK/x.png" ] && [ ! -e "$WORK/p-0000.png" ] && pass || fail "a refused run left an image"

finish

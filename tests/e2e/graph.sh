# build-splat-graph and segment-surfaces on the real samples: exit codes, the 9 true patches of
# cad.ply recovered (IoU per patch against its patch_id attribute), the error without a graph,
# surface_id and class in PLY output, the same bytes for any thread count.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
S=$SRC/data-samples

for shape in cad cube; do
  expect_exit 0 "$BIN/build-splat-graph" "$S/$shape.ply" "$WORK/$shape-g.splk" -q \
    --report "$WORK/$shape-g.json"
  expect_exit 0 "$BIN/segment-surfaces" "$WORK/$shape-g.splk" "$WORK/$shape-s.splk" -q \
    --report "$WORK/$shape-s.json"
  expect_exit 0 "$BIN/segment-surfaces" "$WORK/$shape-g.splk" "$WORK/$shape-s.ply" -q
  expect_exit 0 "$BIN/splat-info" "$WORK/$shape-s.splk"
  for c in GRPH CLAS CLIP SURF; do
    grep -q "$c" "$WORK/stdout" && pass || fail "$shape: splat-info shows no $c chunk"
  done
  expect_exit 0 "$BIN/splat-info" "$WORK/$shape-s.ply"
  grep -q surface_id "$WORK/stdout" && pass || fail "$shape .ply: no surface_id property"
  grep -q class "$WORK/stdout" && pass || fail "$shape .ply: no class property"
done
echo "build-splat-graph cad.ply: $(tr -d ' \n' <"$WORK/cad-g.json" | grep -o '"edges":[0-9]*'),"\
" $(tr -d ' \n' <"$WORK/cad-g.json" | grep -o '"bytes_per_edge":[0-9.]*'),"\
" $(tr -d ' \n' <"$WORK/cad-g.json" | grep -o '"time_s":[0-9.e-]*')"

# Every true patch recovered with IoU >= 0.95 (cad.ply: 9 patches, cube.ply: 6).
for shape in cad:9 cube:6; do
  name=${shape%:*} want=${shape#*:}
  patch_iou "$WORK/$name-s.ply" >"$WORK/iou.txt" || fail "$name: IoU script failed"
  echo "$name.ply:"; cat "$WORK/iou.txt"
  expect_eq "$name.ply segments" "$(awk '/^segments/{print $2}' "$WORK/iou.txt")" "$want"
  expect_eq "$name.ply patches" "$(grep -c '^patch' "$WORK/iou.txt")" "$want"
  expect_eq "$name.ply patches with IoU < 0.95" \
    "$(awk '/^patch/ && $8 < 0.95' "$WORK/iou.txt" | wc -l)" 0
done

# No graph: exit 2, one line naming build-splat-graph.
expect_exit 2 "$BIN/segment-surfaces" "$S/cad.ply" "$WORK/x.splk"
expect_stderr "no neighbour graph; run build-splat-graph first"
# No normals: exit 2, naming estimate-normals.
printf '0 0 0\n1 0 0\n0 1 0\n' >"$WORK/bare.xyz"
expect_exit 2 "$BIN/build-splat-graph" "$WORK/bare.xyz" "$WORK/x.splk"
expect_stderr "run estimate-normals first"
# Radii far larger than the spacing (every sphere overlaps every other): refused in about a
# second, not after filling the memory.
expect_exit 0 "$BIN/splat-synth" -q torus "$WORK/t20k.ply" -n 20000 --random --ascii
awk 'p { $7 = $7 * 1e30 } { print } /^end_header/ { p = 1 }' "$WORK/t20k.ply" >"$WORK/huge.ply"
expect_exit 2 "$BIN/build-splat-graph" "$WORK/huge.ply" "$WORK/x.splk"
expect_stderr "huge.ply: the bounding spheres overlap more than .* radii far larger than the spacing"
[ ! -e "$WORK/x.splk" ] && pass || fail "a refused graph left OUT behind"
# (radii x30: every splat overlaps thousands, found on the grid rather than by the kd-tree)
awk 'p { $7 = $7 * 30 } { print } /^end_header/ { p = 1 }' "$WORK/t20k.ply" >"$WORK/wide.ply"
expect_exit 2 "$BIN/build-splat-graph" "$WORK/wide.ply" "$WORK/x.splk"
expect_stderr "wide.ply: the bounding spheres overlap more than"
# OUT must be .splk.
expect_exit 1 "$BIN/build-splat-graph" "$S/cube.ply" "$WORK/x.ply"

# The same bytes for --threads 1 and 2, through stdout too.
expect_exit 0 "$BIN/build-splat-graph" "$S/cad.ply" "$WORK/t1.splk" -q --threads 1
expect_exit 0 "$BIN/build-splat-graph" "$S/cad.ply" "$WORK/t2.splk" -q --threads 2
cmp -s "$WORK/t1.splk" "$WORK/t2.splk" && pass || fail "build-splat-graph --threads 1 and 2 differ"
"$BIN/build-splat-graph" "$S/cad.ply" - --threads 2 >"$WORK/t3.splk" 2>/dev/null
cmp -s "$WORK/t1.splk" "$WORK/t3.splk" && pass || fail "build-splat-graph to stdout differs"
# (stdin: the provenance records the input's name)
"$BIN/segment-surfaces" - "$WORK/u1.splk" -q <"$WORK/t1.splk" && pass || fail "segment-surfaces t1"
"$BIN/segment-surfaces" - "$WORK/u2.splk" -q <"$WORK/t2.splk" && pass || fail "segment-surfaces t2"
cmp -s "$WORK/u1.splk" "$WORK/u2.splk" && pass || fail "segment-surfaces outputs differ"
# segment-surfaces itself (refinement included) on one and two threads, on a noisy cloud of
# several parallel chunks.
expect_exit 0 "$BIN/splat-synth" -q cad "$WORK/noisy.ply" -n 20000 --random --noise 0.00125
expect_exit 0 "$BIN/estimate-normals" -q "$WORK/noisy.ply" "$WORK/noisy-n.ply" --method robust
expect_exit 0 "$BIN/build-splat-graph" "$WORK/noisy-n.ply" "$WORK/noisy.splk" -q
for t in 1 2; do
  expect_exit 0 "$BIN/segment-surfaces" "$WORK/noisy.splk" "$WORK/v$t.splk" -q --threads $t
done
cmp -s "$WORK/v1.splk" "$WORK/v2.splk" && pass || fail "segment-surfaces --threads 1 and 2 differ"

# --min-size: small surfaces lose their id; the report lists the kept ones.
expect_exit 0 "$BIN/segment-surfaces" "$WORK/cad-g.splk" "$WORK/m.splk" -q --min-size 1000 \
  --report "$WORK/m.json"
expect_eq "segments of >= 1000 splats" "$(tr -d ' \n' <"$WORK/m.json" | grep -o '"segments":[0-9]*')" \
  '"segments":8'
expect_eq "splats of the one smaller surface" \
  "$(tr -d ' \n' <"$WORK/m.json" | grep -o '"unassigned_splats":[0-9]*')" '"unassigned_splats":605'
expect_exit 0 "$BIN/segment-surfaces" "$WORK/cad-g.splk" "$WORK/m.ply" -q --min-size 1000
expect_exit 0 "$BIN/splat-info" "$WORK/m.ply"
grep -Eq 'surface_id +uint32 +\[0, 4294967295\]' "$WORK/stdout" && pass ||
  fail "--min-size .ply: no surface_id 0xFFFFFFFF: $(grep surface_id "$WORK/stdout")"
finish

# build-qsplat, splat-info and splat-view on .qs files: exit codes and messages for bad input
# (no normals, too few points, wrong extension, a malformed .qs), splats and meshes, dropped
# vertices, the same bytes for any thread count and for a repeated run, no partial output.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
S=$SRC/data-samples

# Splats (with colour), a mesh (OFF with faces), and the report's counts.
expect_exit 0 "$BIN/build-qsplat" "$S/torus.ply" "$WORK/torus.qs" -q --report "$WORK/torus.json"
expect_exit 0 "$BIN/build-qsplat" "$S/nefertiti.off" "$WORK/nef.qs" -q --report "$WORK/nef.json"
expect_eq "nefertiti leaves" "$(tr -d ' \n' <"$WORK/nef.json" | grep -o '"leaves":[0-9]*' | head -1)" \
  '"leaves":299'
tr -d ' \n' <"$WORK/torus.json" | grep -Eq '"bytes_per_leaf":[5-9]\.' && pass ||
  fail "torus: bytes_per_leaf missing"

# Same bytes: 1 and 2 threads, and a second run.
expect_exit 0 "$BIN/build-qsplat" "$S/torus.ply" "$WORK/t1.qs" -q --threads 1
expect_exit 0 "$BIN/build-qsplat" "$S/torus.ply" "$WORK/t2.qs" -q --threads 2
cmp -s "$WORK/t1.qs" "$WORK/t2.qs" && pass || fail "1 and 2 threads give different .qs bytes"
cmp -s "$WORK/t1.qs" "$WORK/torus.qs" && pass || fail "two runs give different .qs bytes"

# A mesh with an unused vertex and a degenerate face: dropped and counted.
cat >"$WORK/degenerate.off" <<'END_OFF'
OFF
8 5 0
0 0 0
1 0 0
0 1 0
1 1 0
2 0 0
2 1 0
9 9 9
5 5 5
3 0 1 2
3 1 3 2
3 1 4 3
3 4 5 3
3 7 7 7
END_OFF
expect_exit 0 "$BIN/build-qsplat" "$WORK/degenerate.off" "$WORK/m.qs" -q --report "$WORK/m.json"
tr -d ' \n' <"$WORK/m.json" | grep -q '"dropped_unused":1' && pass || fail "unused vertex not counted"
tr -d ' \n' <"$WORK/m.json" | grep -q '"dropped_zero_radius":1' && pass ||
  fail "degenerate-only vertex not counted"

# The input's PLY comments go into the comment fragment as the original qsplat_make puts them:
# the text after the keyword, a line each; one that looks like splatkit's provenance does not
# move the model (the run's own line, last, says where it is).
{ printf 'ply\nformat ascii 1.0\ncomment scanned by hand\n'
  printf 'comment splatkit {"origin": [1000000, 0, 0]}\nelement vertex 6\n'
  printf 'property float %s\n' x y z nx ny nz radius; printf 'end_header\n'
  for i in 0 1 2 3 4 5; do echo "$i 0 0 0 0 1 0.6"; done; } >"$WORK/commented.ply"
expect_exit 0 "$BIN/build-qsplat" "$WORK/commented.ply" "$WORK/commented.qs" -q
grep -aq "scanned by hand$" "$WORK/commented.qs" && pass || fail "PLY comment not carried over"
grep -aq "comment scanned" "$WORK/commented.qs" && fail "PLY comment keeps its keyword" || pass
expect_exit 0 "$BIN/splat-info" --json "$WORK/commented.qs"
grep -q '"origin"' "$WORK/stdout" && fail "a PLY comment moved the model" || pass

# splat-info describes .qs.
expect_exit 0 "$BIN/splat-info" "$WORK/torus.qs"
grep -q "^Leaves: 12001" "$WORK/stdout" && pass || fail "splat-info .qs: $(head -8 "$WORK/stdout")"
grep -q "^Colour: no" "$WORK/stdout" && pass || fail "splat-info .qs: no colour line"
expect_exit 0 "$BIN/build-qsplat" "$S/two-spheres.ply" "$WORK/two.qs" -q
expect_exit 0 "$BIN/splat-info" "$WORK/two.qs"
grep -q "^Colour: yes" "$WORK/stdout" && pass || fail "splat-info two-spheres .qs: no colour"
expect_exit 0 "$BIN/build-qsplat" "$S/two-spheres.ply" "$WORK/two-nc.qs" -q --no-color
expect_exit 0 "$BIN/splat-info" "$WORK/two-nc.qs"
grep -q "^Colour: no" "$WORK/stdout" && pass || fail "--no-color .qs still has colour"
expect_exit 0 "$BIN/splat-info" --json "$WORK/nef.qs"
grep -q '"format": "qs"' "$WORK/stdout" && pass || fail "splat-info --json .qs: no format"

# splat-view renders .qs at several thresholds, with the traversal's counts in --stats.
for px in 1 4 16; do
  expect_exit 0 "$BIN/splat-view" "$WORK/torus.qs" -o "$WORK/t$px.png" -q --width 320 \
    --height 240 --qsplat-threshold "$px" --stats "$WORK/v$px.json"
  tr -d ' \n' <"$WORK/v$px.json" | grep -q '"nodes_visited":[1-9]' && pass ||
    fail "splat-view --stats: no qsplat counts"
done
# The z-buffer fast path: the same bytes on 1 and 2 threads, for a .qs and for plain splats, and
# fewer splats drawn at 16 px than at 1 px.
for t in 1 2; do
  expect_exit 0 "$BIN/splat-view" "$WORK/torus.qs" -o "$WORK/z$t.png" -q --width 320 \
    --height 240 --blend zbuffer --threads "$t" --stats "$WORK/z$t.json"
  expect_exit 0 "$BIN/splat-view" "$S/torus.ply" -o "$WORK/zp$t.png" -q --width 320 \
    --height 240 --blend zbuffer --threads "$t"
done
cmp -s "$WORK/z1.png" "$WORK/z2.png" && pass || fail "--blend zbuffer .qs differs across threads"
cmp -s "$WORK/zp1.png" "$WORK/zp2.png" && pass || fail "--blend zbuffer .ply differs across threads"
expect_exit 0 "$BIN/splat-view" "$WORK/torus.qs" -o "$WORK/z16.png" -q --width 320 \
  --height 240 --blend zbuffer --qsplat-threshold 16 --stats "$WORK/z16.json"
drawn() { tr -d ' \n' <"$1" | grep -o '"splats_drawn":[0-9]*' | head -1 | cut -d: -f2; }
[ "$(drawn "$WORK/z16.json")" -lt "$(drawn "$WORK/z1.json")" ] && pass ||
  fail "--blend zbuffer: 16 px draws no fewer splats than 1 px"
tr -d ' \n' <"$WORK/z1.json" | grep -q '"blend":"zbuffer"' && pass || fail "--stats: no blend mode"

# Bad input: exit codes and one-line messages; no output left behind.
printf '0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 2 2\n3 3 3\n' >"$WORK/bare.xyz"
expect_exit 2 "$BIN/build-qsplat" "$WORK/bare.xyz" "$WORK/x.qs"
expect_stderr "run estimate-normals first"
[ ! -e "$WORK/x.qs" ] && pass || fail "a failed run left $WORK/x.qs"
printf '0 0 0 0 0 1 0.1\n1 0 0 0 0 1 0.1\n0 1 0 0 0 1 0.1\n1 1 0 0 0 1 0.1\n' >"$WORK/four.xyz"
expect_exit 3 "$BIN/build-qsplat" "$WORK/four.xyz" "$WORK/x.qs" --columns x,y,z,nx,ny,nz,radius
expect_stderr "4 usable points; a QSplat file needs at least 5"
expect_exit 1 "$BIN/build-qsplat" "$S/torus.ply" "$WORK/x.splk"
expect_stderr "OUT must end in .qs"
head -c 60 "$WORK/torus.qs" >"$WORK/cut.qs"
expect_exit 2 "$BIN/splat-info" "$WORK/cut.qs"
expect_stderr "cut.qs: byte"
expect_exit 2 "$BIN/splat-view" "$WORK/cut.qs" -o "$WORK/cut.png"
expect_stderr "cut.qs: byte"
# A careless user's inputs: an empty cloud (2), one splat (3: the original viewer needs 5
# leaves), 100 identical splats (a valid tree), a heightmap or a .qs (3), a missing directory (4);
# nothing left behind.
sweep_ply "$WORK/empty.ply" 0; sweep_ply "$WORK/one.ply" 1; sweep_ply "$WORK/dup.ply" 100
expect_exit 2 "$BIN/build-qsplat" -q "$WORK/empty.ply" "$WORK/x.qs"
expect_stderr "empty.ply: the file has no points"
expect_exit 3 "$BIN/build-qsplat" -q "$WORK/one.ply" "$WORK/x.qs"
expect_stderr "one.ply: 1 usable points; a QSplat file needs at least 5"
expect_exit 0 "$BIN/build-qsplat" -q "$WORK/dup.ply" "$WORK/dup.qs"
expect_exit 0 "$BIN/splat-view" -q "$WORK/dup.qs" -o "$WORK/dup.png" --width 32 --height 24
expect_exit 3 "$BIN/build-qsplat" -q "$S/rainier-srtm.tif" "$WORK/x.qs"
expect_stderr "rainier-srtm.tif: a heightmap .* splat-view --terrain renders it"
expect_exit 3 "$BIN/build-qsplat" -q "$WORK/dup.qs" "$WORK/x.qs"
expect_stderr "dup.qs: a QSplat hierarchy \\(.qs\\), not a point cloud"
expect_exit 4 "$BIN/build-qsplat" -q "$WORK/dup.ply" "$WORK/no/such/x.qs"
expect_stderr "no/such/x.qs: cannot create"
[ ! -e "$WORK/x.qs" ] && pass || fail "a refused run left x.qs"

finish

# build-spt, splat-info and splat-view on .spt files: the report's counts, the same bytes for any
# thread count and for a repeated run, both precisions, stdin/stdout, exit codes and messages for
# bad input (no normals, wrong extension, a malformed .spt), no partial output, and the drawn
# count falling as the camera recedes.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
S=$SRC/data-samples

expect_exit 0 "$BIN/build-spt" "$S/torus.ply" "$WORK/torus.spt" -q --report "$WORK/torus.json"
j=$(tr -d ' \n' <"$WORK/torus.json")
grep -q '"input_points":12001' <<<"$j" && pass || fail "torus report: input_points"
grep -Eq '"entries_per_input_point":1\.[0-9]' <<<"$j" && pass || fail "torus report: entries per point"
grep -Eq '"depth":[1-9]' <<<"$j" && pass || fail "torus report: depth"
grep -Eq '"points_per_second":[1-9]' <<<"$j" && pass || fail "torus report: points/s"
grep -Eq '"peak_rss_bytes_per_point":[1-9]' <<<"$j" && pass || fail "torus report: peak RSS"
grep -Eq '"tree":[0-9.e-]+' <<<"$j" && pass || fail "torus report: tree phase time"

# Same bytes: 1 and 2 threads, a second run, and through stdin and stdout.
expect_exit 0 "$BIN/build-spt" "$S/two-spheres.ply" "$WORK/t1.spt" -q --threads 1
expect_exit 0 "$BIN/build-spt" "$S/two-spheres.ply" "$WORK/t2.spt" -q --threads 2
cmp -s "$WORK/t1.spt" "$WORK/t2.spt" && pass || fail "1 and 2 threads give different .spt bytes"
"$BIN/build-spt" - - -q <"$S/two-spheres.ply" >"$WORK/pipe.spt" && pass || fail "build-spt - -"
cmp -s "$WORK/t1.spt" "$WORK/pipe.spt" && pass || fail "stdin/stdout gives different .spt bytes"
size=$(stat -c %s "$WORK/t1.spt")
entries=$("$BIN/splat-info" --json "$WORK/t1.spt" | tr -d ' \n' | grep -o '"entries":[0-9]*' | cut -d: -f2)
expect_eq "compact entry size" "$((size - 128))" "$((entries * 16))"

# splat-info describes both precisions.
expect_exit 0 "$BIN/splat-info" "$WORK/t1.spt"
grep -q "^Format: spt (Sequential Point Tree version 1, compact, 16 bytes per entry)" "$WORK/stdout" &&
  pass || fail "splat-info .spt: $(head -3 "$WORK/stdout")"
grep -q "^Colour: yes" "$WORK/stdout" && pass || fail "splat-info .spt: no colour"
expect_exit 0 "$BIN/build-spt" "$S/torus.ply" "$WORK/full.spt" -q --precision full
expect_exit 0 "$BIN/splat-info" "$WORK/full.spt"
grep -q "^Format: spt (.*, full, 40 bytes per entry)" "$WORK/stdout" && pass || fail "splat-info: full precision"

# splat-view: the drawn count falls as the camera recedes; the stats name the prefix.
prev=999999999
for d in 6 12 24; do
  expect_exit 0 "$BIN/splat-view" "$WORK/torus.spt" -o "$WORK/t$d.png" -q --width 320 \
    --height 240 --view 30,30,$d --spt-error 1 --stats "$WORK/v$d.json"
  s=$(tr -d ' \n' <"$WORK/v$d.json")
  grep -Eq '"spt":\{"culled_fraction":[0-9.e-]+,"culled_in_prefix":[0-9]+,"prefix":[1-9]' <<<"$s" &&
    pass || fail "splat-view --stats: no spt counts ($s)"
  n=$(grep -o '"splats_selected":[0-9]*' <<<"$s" | head -1 | cut -d: -f2)
  [ "$n" -lt "$prev" ] && pass || fail "distance $d: $n splats drawn, not fewer than $prev"
  prev=$n
done
# The z-buffer fast path draws the same selection (the stats' prefix) with the same bytes on 1
# and 2 threads.
for t in 1 2; do
  expect_exit 0 "$BIN/splat-view" "$WORK/torus.spt" -o "$WORK/z$t.png" -q --width 320 \
    --height 240 --blend zbuffer --threads "$t" --stats "$WORK/z$t.json"
done
cmp -s "$WORK/z1.png" "$WORK/z2.png" && pass || fail "--blend zbuffer .spt differs across threads"
tr -d ' \n' <"$WORK/z1.json" | grep -q '"spt":{[^}]*"prefix":[1-9]' && pass ||
  fail "--blend zbuffer .spt: no spt counts"
expect_exit 1 "$BIN/splat-view" "$WORK/torus.spt" -o "$WORK/x.png" --spt-error 0
[ ! -e "$WORK/x.png" ] && pass || fail "a rejected --spt-error left an image"

# Bad input: exit codes and one-line messages; no output left behind.
printf '0 0 0\n1 0 0\n0 1 0\n1 1 0\n2 2 2\n3 3 3\n' >"$WORK/bare.xyz"
expect_exit 2 "$BIN/build-spt" "$WORK/bare.xyz" "$WORK/x.spt"
expect_stderr "run estimate-normals first"
[ ! -e "$WORK/x.spt" ] && pass || fail "a failed run left $WORK/x.spt"
expect_exit 1 "$BIN/build-spt" "$S/torus.ply" "$WORK/x.qs"
expect_stderr "OUT must end in .spt"
# Numeric options at their extremes are refused naming the option and the value (1e300 is inf
# in float: the message says so, not "must be positive").
for v in 0 -1 1e300 nan inf; do
  expect_exit 1 "$BIN/build-spt" -q "$S/torus.ply" "$WORK/x.spt" --epsilon "$v"
  expect_stderr "^build-spt: --epsilon must be a positive number of radians within float range, got"
done
for v in -1 1e300 nan inf; do
  expect_exit 1 "$BIN/build-spt" -q "$S/torus.ply" "$WORK/x.spt" --color-weight "$v"
  expect_stderr "^build-spt: --color-weight must be zero or positive and within float range, got"
done
# One splat, 100 identical splats: a valid tree; an empty cloud, a .spt or a heightmap: refused.
printf 'ply\nformat ascii 1.0\nelement vertex 100\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float radius\nend_header\n' >"$WORK/dup.ply"
for i in $(seq 100); do echo "1 2 3 0 0 1 0.1"; done >>"$WORK/dup.ply"
expect_exit 0 "$BIN/build-spt" -q "$WORK/dup.ply" "$WORK/dup.spt"
expect_exit 0 "$BIN/splat-info" "$WORK/dup.spt"
expect_exit 3 "$BIN/build-spt" -q "$WORK/dup.spt" "$WORK/x.spt"
expect_stderr "dup.spt: a Sequential Point Tree \(.spt\), not a point cloud"
expect_exit 3 "$BIN/build-spt" -q "$SRC/data-samples/rainier-srtm.tif" "$WORK/x.spt"
expect_stderr "rainier-srtm.tif: a heightmap .* splat-view --terrain renders it"
expect_exit 4 "$BIN/build-spt" -q "$WORK/dup.ply" "$WORK/no/such/x.spt"
expect_stderr "^build-spt: .*no/such/x.spt: cannot create"
[ ! -e "$WORK/x.spt" ] && pass || fail "a refused run left $WORK/x.spt"
head -c 300 "$WORK/torus.spt" >"$WORK/cut.spt"
expect_exit 2 "$BIN/splat-info" "$WORK/cut.spt"
expect_stderr "cut.spt: byte 24: .*truncated"
expect_exit 2 "$BIN/splat-view" "$WORK/cut.spt" -o "$WORK/cut.png"
expect_stderr "cut.spt: byte 24"
finish

#!/usr/bin/env bash
# The checks every stage makes before its work, through the real binaries: paths compared by
# identity (any spelling of the input, OUT or the report), outputs checked before the work, a
# failing report that leaves OUT alone, numbers validated, one rule for splats across tools, and
# splat-info going on past a bad file.
source "$(dirname "$0")/common.bash"
S=$SRC/data-samples
cd "$WORK" || exit 1
cp "$S/sphere.ply" m.ply
ln -s m.ply alias.ply
ln m.ply hard.ply
sum=$(cksum < m.ply)

# --report (or --stats) naming the input or OUT, in any spelling: usage error before any work.
for spelling in m.ply ./m.ply alias.ply hard.ply "$WORK/m.ply"; do
  expect_exit 1 "$BIN/estimate-normals" -q m.ply o.ply --report "$spelling"
  expect_stderr "^estimate-normals: --report must not be the input file"
  expect_exit 1 "$BIN/estimate-normals" -q m.ply "$spelling"
  expect_stderr "an input is never overwritten"
  expect_exit 1 "$BIN/splat-view" -q m.ply -o x.png --stats "$spelling"
  expect_stderr "^splat-view: --stats must not be the input file"
done
expect_exit 1 "$BIN/build-splat-graph" -q m.ply g.splk --report ./g.splk
expect_stderr "--report must not be OUT"
expect_exit 1 "$BIN/segment-surfaces" -q m.ply ./m.ply
expect_eq "the input after the refused runs" "$(cksum < m.ply)" "$sum"
[ ! -e o.ply ] && [ ! -e x.png ] && pass || fail "a refused run wrote an output"

# OUT and the report checked before the work: a failing report leaves no OUT.
expect_exit 4 "$BIN/estimate-normals" -q m.ply o.ply --report no/such/dir/r.json
expect_stderr "r.json: cannot create"
[ ! -e o.ply ] && pass || fail "a failing --report left OUT written"
expect_exit 4 "$BIN/splat-view" -q m.ply -o no/such/dir/x.png
expect_stderr "x.png: cannot create"
expect_exit 4 "$BIN/splat-view" -q m.ply -o x.png --stats no/such/dir/s.json
[ ! -e x.png ] && pass || fail "a failing --stats left the image written"

# Numbers: NaN, infinity and out-of-range values are usage errors with their own message.
for bg in nan,0,0 2,0,0 -1,0,0 inf,0,0 0.5; do
  expect_exit 1 "$BIN/splat-view" -q m.ply -o x.png --background "$bg"
  expect_stderr "^splat-view: --background must be three"
done
for fov in 0 180 nan; do
  expect_exit 1 "$BIN/splat-view" -q m.ply -o x.png --fov "$fov"
  expect_stderr "^splat-view: --fov must be in \(0, 180\) degrees"
done
expect_exit 1 "$BIN/splat-view" -q m.ply -o x.png --eye nan,1,1
expect_stderr "--eye must be three finite numbers"
expect_exit 1 "$BIN/splat-view" -q m.ply -o x.png --blend zthreshold=inf
expect_exit 1 "$BIN/estimate-normals" -q m.ply o.ply --radius-scale nan
expect_exit 1 "$BIN/build-splat-graph" -q m.ply g.splk --sharp nan
expect_exit 1 "$BIN/build-splat-graph" -q m.ply g.splk --core inf
expect_exit 1 "$BIN/splat-synth" -q sphere s.ply --noise nan

# One rule for splats: a zero normal or a negative radius is refused by every consumer, naming
# the file and the splat.
"$BIN/splat-convert" -q --ascii "$S/torus-ascii.ply" t.ply
python3 - <<'PY'
lines = open("t.ply").read().split("\n")
body = lines.index("end_header") + 1
v = lines[body + 17].split()
v[3:6] = ["0", "0", "0"]  # nx ny nz of splat 17
lines[body + 17] = " ".join(v)
open("zero-normal.ply", "w").write("\n".join(lines))
v = lines[body + 3].split()
v[6] = "-1"  # radius of splat 3
lines[body + 3] = " ".join(v)
open("negative-radius.ply", "w").write("\n".join(lines))
PY
expect_exit 2 "$BIN/build-splat-graph" -q zero-normal.ply g.splk
expect_stderr "^build-splat-graph: zero-normal.ply: splat 17: normal is zero$"
expect_exit 2 "$BIN/splat-view" -q zero-normal.ply -o x.png
expect_stderr "^splat-view: zero-normal.ply: splat 17: normal is zero$"
expect_exit 2 "$BIN/build-splat-graph" -q negative-radius.ply g.splk
expect_stderr "^build-splat-graph: negative-radius.ply: splat 3: radius -1 is negative$"

# splat-info goes on past a bad file: the good ones as a JSON array, the bad one on stderr.
head -c 300 m.ply > bad.ply  # truncated
"$BIN/splat-info" --json m.ply bad.ply t.ply > inventory.json 2> info.err
expect_eq "splat-info exit code with a bad file" "$?" 2
expect_eq "files described" "$(python3 -c 'import json; print(len(json.load(open("inventory.json"))))')" 2
grep -q "bad.ply" info.err && pass || fail "the bad file is not named: $(cat info.err)"

finish

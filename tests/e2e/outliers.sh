# estimate-normals --outliers: the points removed are counted in the report, written aside with
# --outliers-out (all passes' of a chain), and are exactly the ones missing from the output; bad
# specs exit 1.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
cd "$WORK"
"$BIN/splat-synth" -q cad scan.xyz -n 20000 --random --seed 5 --no-color
# 1 % stray points far off the part (above it).
awk '!/^#/ { print $1, $2, $3 }' scan.xyz >points.xyz
awk 'NR % 100 == 0 { printf "%s %s %.4f\n", $1, $2, $3 + 3 + (NR % 7) }' points.xyz >stray.xyz
cat points.xyz stray.xyz >in.xyz
strays=$(wc -l <stray.xyz)
for spec in sor sor:8,1 radius sor:16,2+sor:8,3; do
  expect_exit 0 "$BIN/estimate-normals" -q in.xyz out.splk --outliers "$spec" --outliers-out removed.ply \
    --report r.json
  removed=$(jq .outliers.removed r.json)
  passes=$(jq '[.outliers.passes[].removed] | add' r.json)
  expect_eq "$spec: report: all passes' sum" "$passes" "$removed"
  got=$("$BIN/splat-info" removed.ply | sed -n 's/^Points: //p')
  expect_eq "$spec: report vs --outliers-out" "$got" "$removed"
  [ "$removed" -ge "$strays" ] && pass || fail "$spec: removed $removed of $strays stray points"
  [ "$removed" -le $((strays + 100)) ] && pass || fail "$spec: removed $removed (only $strays strays)"
  out=$("$BIN/splat-info" out.splk | sed -n 's/^Points: //p')
  in=$(grep -cv '^#' in.xyz)
  [ $((out + removed)) -le "$in" ] && pass || fail "$spec: $out kept + $removed removed > $in"
done
# Every stray point (z above the part) is in the removed file.
"$BIN/splat-convert" -q removed.ply removed.xyz
above=$(awk '!/^#/ && $3 > 2.5' removed.xyz | wc -l)
expect_eq "strays in --outliers-out" "$above" "$strays"
# The default chain on a 100 000-point i.i.d. torus with 1 % uniform outliers in its box (tagged
# by a fourth column): >= 95 % of them removed, <= 0.5 % of the torus.
"$BIN/splat-synth" -q torus torus.xyz -n 100000 --random --seed 1 --no-color
python3 - torus.xyz tagged.xyz <<'PY'
import random, sys
p = [[float(v) for v in l.split()[:3]] for l in open(sys.argv[1]) if l.strip() and l[0] != "#"]
lo = [min(q[a] for q in p) for a in range(3)]; hi = [max(q[a] for q in p) for a in range(3)]
rng = random.Random(7)
with open(sys.argv[2], "w") as f:
    for q in p: f.write("%.7g %.7g %.7g 0\n" % tuple(q))
    for _ in range(len(p) // 100):
        f.write("%.7g %.7g %.7g 1\n" % tuple(lo[a] + (hi[a] - lo[a]) * rng.random() for a in range(3)))
PY
expect_exit 0 "$BIN/estimate-normals" -q --columns x,y,z,tag tagged.xyz torus.splk --outliers sor \
  --outliers-out torus-removed.xyz --orient none --report torus.json
expect_eq "sor: passes" "$(jq -c '[.outliers.passes[].rule]' torus.json)" '["sor","sor","plane"]'
read -r strays_out true_out <<<"$(awk '!/^#/ { if ($NF == 1) s++; else t++ } END { print s + 0, t + 0 }' torus-removed.xyz)"
[ "$strays_out" -ge 950 ] && pass || fail "--outliers sor removed $strays_out of 1000 uniform outliers"
[ "$true_out" -le 500 ] && pass || fail "--outliers sor removed $true_out of 100000 torus points"
expect_exit 1 "$BIN/estimate-normals" -q in.xyz out.splk --outliers plane:2,6
expect_stderr "K must be 3..1024 and T positive"
expect_exit 1 "$BIN/estimate-normals" -q in.xyz out.splk --outliers sor:8
expect_stderr "give both parameters"
expect_exit 1 "$BIN/estimate-normals" -q in.xyz out.splk --outliers median
expect_stderr "--outliers must be none, sor"
expect_exit 1 "$BIN/estimate-normals" -q in.xyz out.splk --outliers sor+
expect_stderr "--outliers must be none, sor"
expect_exit 1 "$BIN/estimate-normals" -q in.xyz out.splk --outliers sor+sor+sor+sor+sor+sor+sor+sor+sor
expect_stderr "at most 8 passes"
expect_exit 1 "$BIN/estimate-normals" -q in.xyz out.splk --outliers-out x.ply
expect_stderr "--outliers-out needs --outliers"
finish

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

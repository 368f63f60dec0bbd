# splat-info describes every kind of file with one layout: the same first lines (File, Format,
# Bytes, Points or Entries, Bounds, CRS) and the same JSON keys (file, format, bytes, points or
# entries, bounds, crs), numbers at the precision their source holds (never 17 digits), and
# bounds in the file's coordinates for clouds, .qs, .spt, heightmaps and tile EXRs alike.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
S=$SRC/data-samples
cd "$WORK" || exit 1

# too_long: the first number on stdin with more than 12 significant digits, if any.
too_long() {
  grep -Eo '[0-9]+\.[0-9]+' | awk '{ d = $0; sub(/\./, "", d); sub(/^0+/, "", d);
                                      if (length(d) > 12) { print $0; exit } }'
}

"$BIN/estimate-normals" -q "$S/torus.ply" torus.splk || fail "setup: torus.splk"
"$BIN/build-qsplat" -q torus.splk torus.qs || fail "setup: torus.qs"
"$BIN/build-spt" -q torus.splk torus.spt || fail "setup: torus.spt"
cp "$S/rainier-srtm.tif" dem.tif
"$BIN/build-ham" -q dem.tif tiles.exr || fail "setup: tiles.exr"
files="$S/torus.ply $S/cad-utm-las14.las $S/torus-las12.laz torus.splk torus.qs torus.spt dem.tif tiles.exr"

for f in $files; do
  name=$(basename "$f")
  expect_exit 0 "$BIN/splat-info" "$f"
  # The first lines, in this order, for every kind.
  got=$(sed -n '1,7p' "$WORK/stdout" | sed -E 's/^(File|Format|Bytes|Points|Entries|Bounds|CRS):.*/\1/; s/^ +max .*/max/' | tr '\n' ' ')
  case "$got" in
    "File Format Bytes Points Bounds max CRS " | "File Format Bytes Entries Bounds max CRS ") pass ;;
    *) fail "$name: text layout: $got" ;;
  esac
  # No number printed with more than 12 significant digits (float32 values print as float32);
  # a .qs file's comment lines are quoted as they are.
  long=$(sed '/^Comments:/,$d' "$WORK/stdout" | too_long)
  expect_eq "$name: text digits" "$long" ""
  expect_exit 0 "$BIN/splat-info" --json "$f"
  keys=$(jq -r '[has("file"), has("format"), has("bytes"), (has("points") or has("entries")),
                 (.bounds.min | length), (.bounds.max | length), has("crs")] | map(tostring) | join(" ")' \
           "$WORK/stdout")
  expect_eq "$name: JSON keys" "$keys" "true true true true 3 3 true"
  long=$(jq '.. | numbers' "$WORK/stdout" | too_long)
  expect_eq "$name: JSON digits" "$long" ""
done

# .spt had no bounds, .qs a root sphere only: both now give the box of the cloud they were built
# from, within the quantisation (the .qs box is the root sphere's, so it holds the cloud's).
"$BIN/splat-info" --json torus.splk > c.json
"$BIN/splat-info" --json torus.spt > t.json
"$BIN/splat-info" --json torus.qs > q.json
near=$(jq -s '[.[0].bounds.min, .[0].bounds.max, .[1].bounds.min, .[1].bounds.max] |
              [range(3) as $k | ((.[0][$k] - .[2][$k]) | fabs) < 0.01, ((.[1][$k] - .[3][$k]) | fabs) < 0.01]
              | all' c.json t.json)
expect_eq ".spt bounds near the cloud's" "$near" true
holds=$(jq -s '[range(3) as $k | .[1].bounds.min[$k] <= .[0].bounds.min[$k] and .[1].bounds.max[$k] >= .[0].bounds.max[$k]]
               | all' c.json q.json)
expect_eq ".qs bounds hold the cloud's" "$holds" true

# GeoTIFF corners and the CRS appear in the text, not only in the JSON.
expect_exit 0 "$BIN/splat-info" dem.tif
grep -q '^CRS: EPSG:4326' "$WORK/stdout" && pass || fail "heightmap text: no CRS line"
grep -Eq '^Bounds: min \(-12[12]\.[0-9]+, 46\.[0-9]+, [0-9]+\)' "$WORK/stdout" && pass ||
  fail "heightmap text: bounds $(grep Bounds "$WORK/stdout")"
expect_eq "heightmap points are its samples" "$("$BIN/splat-info" --json dem.tif | jq '.points == .width * .height')" true

# Size on a Bytes line for every kind, equal to the file's size.
for f in $files; do
  expect_eq "$(basename "$f"): Bytes" "$("$BIN/splat-info" "$f" | sed -n 's/^Bytes: //p')" "$(stat -c %s "$f")"
done

# --json keys: the same set of shared keys whatever the kind (one object per file in an array).
"$BIN/splat-info" --json $files > all.json
expect_eq "shared keys across kinds" \
  "$(jq -c '[.[] | [has("file"), has("format"), has("bytes"), has("bounds"), has("crs")] | all] | unique' all.json)" \
  "[true]"

finish

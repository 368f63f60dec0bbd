# The promises every tool keeps: exit codes by class, one-line errors naming the file, atomic
# outputs, '-' for stdin/stdout, --help/--version.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
S=$SRC/data-samples

# Every tool built (each folder under tools/ is one executable).
tools=()
for d in "$SRC"/tools/*/; do t=$(basename "$d"); [ -x "$BIN/$t" ] && tools+=("$t"); done
[ ${#tools[@]} -ge 5 ] && pass || fail "expected at least 5 tools in $BIN, found ${#tools[@]}"
for t in "${tools[@]}"; do
  expect_exit 0 "$BIN/$t" --version
  grep -q "(splatkit)" "$WORK/stdout" && pass || fail "$t --version output"
  expect_exit 0 "$BIN/$t" --help
  grep -q "Examples:" "$WORK/stdout" && pass || fail "$t --help has no examples"
  expect_exit 1 "$BIN/$t" --no-such-option
  # An unknown option is named, before any missing argument.
  head -1 "$WORK/stderr" | grep -q "^$t: unknown option --no-such-option" && pass ||
    fail "$t --no-such-option: $(head -1 "$WORK/stderr")"
done

# Missing file: exit 2, one line naming the tool and the file.
expect_exit 2 "$BIN/splat-info" "$WORK/missing.ply"
expect_stderr "^splat-info: .*missing.ply: cannot open"

# Unknown content: exit 3.
printf 'hello\n' > "$WORK/what.bin"
expect_exit 3 "$BIN/splat-info" "$WORK/what.bin"
expect_stderr "what.bin: unknown file format"

# A zeroed LAS header named .laz: an unsupported LAS version (exit 3), named.
printf 'LASF' > "$WORK/scan.laz"; head -c 400 /dev/zero >> "$WORK/scan.laz"
expect_exit 3 "$BIN/splat-info" "$WORK/scan.laz"
expect_stderr "LAS version 0.0"

# A good sample and conversions through pipes.
sample=$S/sphere.ply
expect_exit 0 "$BIN/splat-info" --json "$sample"
points=$(grep -m1 '"points"' "$WORK/stdout" | tr -dc 0-9)
[ -n "$points" ] && [ "$points" -gt 0 ] && pass || fail "no point count for $sample"
"$BIN/splat-convert" -q "$sample" - | "$BIN/splat-info" --json - > "$WORK/piped.json" 2>"$WORK/stderr"
expect_eq "pipe exit" "$?" 0
expect_eq "points through a pipe" "$(grep -m1 '"points"' "$WORK/piped.json" | tr -dc 0-9)" "$points"
cat "$sample" | "$BIN/splat-convert" -q - "$WORK/from-stdin.splk"
expect_eq "stdin input" "$?" 0

# Same input and options: byte-identical outputs.
"$BIN/splat-convert" -q "$sample" "$WORK/a.splk"
"$BIN/splat-convert" -q "$sample" "$WORK/b.splk"
cmp -s "$WORK/a.splk" "$WORK/b.splk" && pass || fail "two runs differ"

# Atomic output: a failing run leaves no file and does not clobber a good one.
cp "$WORK/a.splk" "$WORK/keep.splk"
head -c 300 "$sample" > "$WORK/truncated.ply"
expect_exit 2 "$BIN/splat-convert" -q "$WORK/truncated.ply" "$WORK/keep.splk"
cmp -s "$WORK/a.splk" "$WORK/keep.splk" && pass || fail "failed run clobbered the output"
expect_exit 2 "$BIN/splat-convert" -q "$WORK/truncated.ply" "$WORK/new.splk"
[ ! -e "$WORK/new.splk" ] && pass || fail "failed run left a partial output"
ls "$WORK" | grep -q '\.tmp\.' && fail "temporary file left behind" || pass

# Output failure: exit 4 naming the output.
expect_exit 4 "$BIN/splat-convert" -q "$sample" "$WORK/no/such/dir/out.splk"
expect_stderr "out.splk: cannot create"
# Writing PCD is not supported: exit 3 before any work.
expect_exit 3 "$BIN/splat-convert" -q "$sample" "$WORK/out.pcd"

# A report that cannot be written out (a full disk: /dev/full) fails the run before OUT is put
# in place: no new OUT, an old one kept.
if [ -w /dev/full ]; then
  expect_exit 4 "$BIN/estimate-normals" -q "$sample" "$WORK/full.splk" --report /dev/full
  [ ! -e "$WORK/full.splk" ] && pass || fail "OUT put in place although its report failed"
  cp "$WORK/a.splk" "$WORK/kept.splk"
  expect_exit 4 "$BIN/estimate-normals" -q "$sample" "$WORK/kept.splk" --report /dev/full
  cmp -s "$WORK/a.splk" "$WORK/kept.splk" && pass || fail "OUT replaced although its report failed"
fi

# An output name near the file name limit (255 bytes) can be written: its temporary name is
# shorter then.
long=$(printf 'a%.0s' $(seq 245)).splk
expect_exit 0 "$BIN/splat-convert" -q "$sample" "$WORK/$long"
cmp -s "$WORK/a.splk" "$WORK/$long" && pass || fail "a 250-byte output name"

# Side outputs never name the input, OUT, the report or each other, whatever the spelling.
cp "$sample" "$WORK/in.ply"
ln -sf in.ply "$WORK/link.ply"
for side in "$WORK/./in.ply" "$WORK/link.ply"; do
  expect_exit 1 "$BIN/estimate-normals" -q "$WORK/in.ply" "$WORK/o.splk" --outliers sor \
    --outliers-out "$side"
  expect_stderr "--outliers-out must not be the input file"
done
cmp -s "$sample" "$WORK/in.ply" && pass || fail "the input was overwritten"
expect_exit 1 "$BIN/estimate-normals" -q "$WORK/in.ply" "$WORK/o.ply" --outliers sor \
  --outliers-out "$WORK/./o.ply"
expect_stderr "--outliers-out must not be OUT"
expect_exit 1 "$BIN/estimate-normals" -q "$WORK/in.ply" "$WORK/o.splk" --outliers sor \
  --outliers-out "$WORK/r.ply" --report "$WORK/./r.ply"
expect_stderr "--outliers-out must not be the report"
expect_exit 1 "$BIN/splat-synth" -q city "$WORK/c.splk" -n 20000 --walkthrough "$WORK/./c.splk"
expect_stderr "--walkthrough must not be OUT"
# Options that would be ignored are refused; so is an extension that names no format.
expect_exit 1 "$BIN/splat-synth" -q sphere "$WORK/s.splk" --walkthrough "$WORK/w.json"
expect_stderr "apply to the city only"
expect_exit 1 "$BIN/splat-synth" -q sphere "$WORK/s.bar"
expect_stderr "extension names no format"
expect_exit 1 "$BIN/estimate-normals" -q "$WORK/in.ply" "$WORK/o.splk" --outliers sor \
  --outliers-out "$WORK/o.foo"
expect_stderr "extension names no format"
# Removing every point is bad input, not an empty file.
expect_exit 2 "$BIN/estimate-normals" -q "$WORK/in.ply" "$WORK/none.splk" --outliers sor:12,-100
expect_stderr "removed every one of its"
[ ! -e "$WORK/none.splk" ] && pass || fail "an empty output was written"
# A stream without an extension: .splk for clouds, PNG for images (e.g. only the stats wanted).
"$BIN/estimate-normals" -q "$sample" "$WORK/n.splk"
expect_exit 0 "$BIN/splat-view" -q "$WORK/n.splk" /dev/null --stats "$WORK/stats.json" \
  --width 64 --height 48
grep -q '"splats_drawn"\|"splats"' "$WORK/stats.json" && pass || fail "no stats with -o /dev/null"
expect_exit 0 "$BIN/build-splat-graph" -q "$WORK/n.splk" /dev/null
# --max-memory takes fractional sizes and binary units; the output is the in-memory one.
expect_exit 0 "$BIN/estimate-normals" -q "$sample" "$WORK/m.splk" --max-memory 1.5G
cmp -s "$WORK/n.splk" "$WORK/m.splk" && pass || fail "--max-memory 1.5G changed the output"
expect_exit 0 "$BIN/build-spt" -q "$WORK/n.splk" "$WORK/m.spt" --max-memory 0.25GiB
for bad in 1.5X -1G nan inf 1e30G; do
  expect_exit 1 "$BIN/estimate-normals" -q "$sample" "$WORK/m2.splk" --max-memory "$bad"
  head -1 "$WORK/stderr" | grep -q "^estimate-normals: --max-memory: SIZE" && pass ||
    fail "--max-memory $bad: $(head -1 "$WORK/stderr")"
done
[ ! -e "$WORK/m2.splk" ] && pass || fail "a refused --max-memory wrote OUT"

# One name for the JSON report everywhere: --report, with --stats accepted as the same option.
# Every tool but splat-info (whose output is its description) takes both, and --threads.
for t in "${tools[@]}"; do
  [ "$t" = splat-info ] && continue
  help=$("$BIN/$t" --help)  # whole: grep -q stopping early would fail a pipeline
  grep -q -- "--report,--stats" <<<"$help" && pass || fail "$t: no --report,--stats"
  grep -q -- "--threads" <<<"$help" && pass || fail "$t: no --threads"
done
expect_exit 0 "$BIN/estimate-normals" -q "$S/cube.ply" "$WORK/st.splk" --stats "$WORK/st.json"
expect_eq "estimate-normals --stats" "$(jq -r .tool "$WORK/st.json")" estimate-normals
expect_exit 0 "$BIN/splat-view" -q "$WORK/st.splk" "$WORK/st.png" --report "$WORK/sv.json"
jq -e .timings_s "$WORK/sv.json" >/dev/null && pass || fail "splat-view --report wrote no report"
# The summary line counts the splats drawn: a QSplat tree seen from afar draws a few of its leaves.
expect_exit 0 "$BIN/build-qsplat" -q "$S/sphere.ply" "$WORK/far.qs"
"$BIN/splat-view" "$WORK/far.qs" "$WORK/far.png" --view 0,20,400 --stats "$WORK/far.json" \
  2>"$WORK/far.err"
drawn=$(jq .splats_drawn "$WORK/far.json")
leaves=$(sed -n 's/.* frame(s) of \([0-9]*\) splats.*/\1/p' "$WORK/far.err")
grep -q "^splat-view: $drawn splats drawn in " "$WORK/far.err" && [ "$leaves" = "$(grep -a -m1 "^element vertex" "$S/sphere.ply" | cut -d" " -f3)" ] &&
  [ "$drawn" -lt "$leaves" ] && pass ||
  fail "splat-view's summary of a far .qs: $(cat "$WORK/far.err") (drawn $drawn)"
expect_exit 0 "$BIN/splat-view" -q "$WORK/st.splk" "$WORK/st2.png" --stats "$WORK/sv2.json"
jq -e .timings_s "$WORK/sv2.json" >/dev/null && pass || fail "splat-view --stats wrote no report"
# splat-view takes IN OUT like every tool; -o OUT is the same (one of them, not both).
expect_exit 0 "$BIN/splat-view" -q "$WORK/st.splk" -o "$WORK/st3.png"
cmp -s "$WORK/st2.png" "$WORK/st3.png" && pass || fail "splat-view IN OUT and IN -o OUT differ"
expect_exit 1 "$BIN/splat-view" -q "$WORK/st.splk" "$WORK/st4.png" -o "$WORK/st5.png"
expect_stderr "OUT given twice"
expect_exit 1 "$BIN/splat-view" -q "$WORK/st.splk"
expect_stderr "^splat-view: OUT is required"
help=$("$BIN/splat-view" --help)
grep -q "IN OUT\|IN \[OUT\]\|\[IN\] \[OUT\]" <<<"$help" && pass ||
  fail "splat-view --help does not show IN OUT"

# Usage errors take one line, with where to look; a heightmap given as a cloud is named as one.
for t in "${tools[@]}"; do
  expect_exit 1 "$BIN/$t" --no-such-option
  expect_stderr "^$t: unknown option --no-such-option \(see $t --help\)$"
done
expect_exit 1 "$BIN/splat-convert" only-one.ply
expect_stderr "^splat-convert: .*\(see splat-convert --help\)$"
printf '\x89PNG\r\n\x1a\n' >"$WORK/map.png"
expect_exit 3 "$BIN/estimate-normals" -q "$WORK/map.png" "$WORK/map.splk"
expect_stderr "map.png: a heightmap .*splat-view --terrain renders it"

expect_exit 0 "$BIN/splat-synth" -q torus "$WORK/synth.splk" -n 1000 --report "$WORK/synth.json"
expect_eq "splat-synth --report" "$(jq -c '[.tool, .shape, .points]' "$WORK/synth.json")" \
  '["splat-synth","torus",1002]'

expect_exit 0 "$BIN/splat-convert" -q "$WORK/synth.splk" "$WORK/synth.splk" "$WORK/both.ply" \
  --stats "$WORK/convert.json"
expect_eq "splat-convert --stats" \
  "$(jq -c '[.tool, .points, .output_format, [.inputs[].points], (.timings_s.read > 0)]' \
    "$WORK/convert.json")" '["splat-convert",2004,"ply",[1002,1002],true]'

finish

# splat-synth as a user runs it: exit codes and messages, determinism of the bytes, '-' output,
# every output format read back, and data-samples/ still equal to what make-samples.sh makes.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
T=$BIN/splat-synth

expect_exit 0 "$T" --version
grep -q "(splatkit)" "$WORK/stdout" && pass || fail "splat-synth --version output"
expect_exit 0 "$T" --help
grep -q "Examples:" "$WORK/stdout" && pass || fail "splat-synth --help has no examples"

# Usage errors (exit 1) are rejected before any work, with one line.
expect_exit 1 "$T" blob "$WORK/x.ply"
expect_exit 1 "$T" sphere "$WORK/x.ply" --keep-inside
expect_stderr "^splat-synth: --keep-inside applies to two-spheres only"
expect_exit 1 "$T" sphere "$WORK/x.ply" -n 0
expect_exit 1 "$T" sphere "$WORK/x.ply" --noise -1
expect_exit 1 "$T" torus "$WORK/x.ply" --ascii --big-endian
[ ! -e "$WORK/x.ply" ] && pass || fail "a rejected run left an output file"

# Output failures: exit 4, unsupported output formats: exit 3.
expect_exit 4 "$T" -q cube "$WORK/no/such/dir/cube.ply"
expect_exit 3 "$T" -q cube "$WORK/cube.pcd"

# Same seed, same bytes; another seed, other bytes.
"$T" -q cad "$WORK/a.ply" -n 3000 --seed 9 --noise 0.001
"$T" -q cad "$WORK/b.ply" -n 3000 --seed 9 --noise 0.001
"$T" -q cad "$WORK/c.ply" -n 3000 --seed 10 --noise 0.001
cmp -s "$WORK/a.ply" "$WORK/b.ply" && pass || fail "same seed gave different files"
cmp -s "$WORK/a.ply" "$WORK/c.ply" && fail "another seed gave the same file" || pass

# Every output format reads back with the point count and the patch labels; '-' is .splk.
for out in t.ply t.xyz t.off t.splk; do
  expect_exit 0 "$T" -q --random two-spheres "$WORK/$out" -n 500
  expect_exit 0 "$BIN/splat-info" --json "$WORK/$out"
  grep -Eq '"points": ?500' "$WORK/stdout" && pass || fail "$out: not 500 points"
done
"$T" -q torus - -n 700 --random | "$BIN/splat-info" - > "$WORK/piped.txt" 2>&1
grep -q "Points: 700" "$WORK/piped.txt" && pass || fail "'-' output: $(head -3 "$WORK/piped.txt")"
grep -q "patch_id" "$WORK/piped.txt" && pass || fail "'-' output has no patch_id"
grep -q '"tool":"splat-synth"' "$WORK/piped.txt" && pass || fail "no splat-synth metadata in .splk"

# The checked-in samples are exactly what the generator makes today.
if [ -x "$SRC/scripts/make-samples.sh" ]; then
  mkdir -p "$WORK/regen/scripts"
  cp "$SRC/scripts/make-samples.sh" "$SRC"/scripts/make-las-samples.py "$WORK/regen/scripts/"
  if "$WORK/regen/scripts/make-samples.sh" "$BIN" > /dev/null 2>"$WORK/stderr"; then
    for f in "$WORK"/regen/data-samples/*; do
      name=$(basename "$f")
      cmp -s "$f" "$SRC/data-samples/$name" && pass ||
        fail "data-samples/$name differs from make-samples.sh output (rerun scripts/make-samples.sh)"
    done
  else
    fail "make-samples.sh failed: $(head -3 "$WORK/stderr")"
  fi
fi

finish

# An allocation that fails is exit 6 with "out of memory", not a crash or an internal error. The
# input is valid and as large as it says (a sparse file: 400 million points of zeros, 4.8 GB that
# take no disk), so no reader rejects it as bad input; the address space is capped with ulimit -v
# below what the points need but well above what the tools need to start.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
# ASan reserves terabytes of shadow address space, which no ulimit -v leaves room for: this test
# runs in the release build only.
if grep -q __asan_init "$BIN/splat-info" 2>/dev/null; then
  echo "skipped: a sanitizer build cannot run under ulimit -v"
  finish
fi
limit_kb=1500000
n=400000000
printf 'ply\nformat binary_little_endian 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\nend_header\n' \
  "$n" > "$WORK/huge.ply"
truncate -s $(($(stat -c %s "$WORK/huge.ply") + n * 12)) "$WORK/huge.ply"

# Control: under the same cap, a small file works (the cap alone does not break the tools).
(ulimit -v $limit_kb && exec "$BIN/splat-info" "$SRC/data-samples/torus.ply") >/dev/null 2>"$WORK/stderr"
expect_eq "small file under the cap: exit" "$?" 0

for tool in splat-info splat-convert; do
  args=("$WORK/huge.ply")
  [ "$tool" = splat-convert ] && args+=("$WORK/huge.splk")
  (ulimit -v $limit_kb && exec timeout 120 "$BIN/$tool" -q "${args[@]}") >/dev/null 2>"$WORK/stderr"
  expect_eq "$tool: exit" "$?" 6
  expect_stderr "^$tool: (.*: )?out of memory"
done
[ ! -e "$WORK/huge.splk" ] && pass || fail "splat-convert left an output"
ls "$WORK" | grep -q '\.tmp\.' && fail "temporary file left behind" || pass

finish

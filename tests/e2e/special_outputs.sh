# OUT that is not a plain new file, through the real binaries: FIFOs, process substitution and
# device nodes are written directly (they stay what they are); a symlink is followed as `cp` does;
# a directory and a write-protected file are refused with exit 4 and a message naming OUT; a
# replaced file keeps its mode.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
S=$SRC/data-samples
in=$S/torus.ply
"$BIN/splat-convert" -q "$in" "$WORK/want.splk" --format splk  # the options are in the metadata
want=$(cksum < "$WORK/want.splk")
no_temp() {  # no_temp DIR WHAT
  if ls -a "$1" | grep -q '\.tmp\.'; then fail "$2: temporary file left in $1"; else pass; fi
}

# FIFO: a reader gets every byte; the FIFO stays a FIFO.
mkfifo "$WORK/fifo"
cat "$WORK/fifo" > "$WORK/from-fifo" &
reader=$!
expect_exit 0 timeout 60 "$BIN/splat-convert" -q "$in" "$WORK/fifo" --format splk
if [ -p "$WORK/fifo" ]; then
  pass
  wait "$reader"
  expect_eq "FIFO: bytes the reader got" "$(cksum < "$WORK/from-fifo")" "$want"
else
  fail "the FIFO was replaced by a $(stat -c %F "$WORK/fifo")"
  kill "$reader"
fi
no_temp "$WORK" "FIFO"

# Process substitution (/dev/fd/N), for an output and a side output.
expect_exit 0 "$BIN/splat-convert" -q "$in" >(cat > "$WORK/from-procsub") --format splk
wait $!  # the substituted process finishes after the tool
expect_eq "process substitution" "$(cksum < "$WORK/from-procsub")" "$want"
expect_exit 0 "$BIN/estimate-normals" -q "$in" "$WORK/n.splk" --orient none \
  --report >(cat > "$WORK/report-procsub")
wait $!
grep -q '"k"' "$WORK/report-procsub" && pass || fail "report through >(...) missing"

# Standard output by its /dev/fd name, appended to a log: the log keeps its head.
printf 'head\n' > "$WORK/log"
"$BIN/splat-convert" -q "$in" /dev/fd/1 --format splk >> "$WORK/log"
expect_eq "/dev/fd/1 >> log" "$(tail -c +6 "$WORK/log" | cksum)" "$want"
expect_eq "/dev/fd/1 >> log: head" "$(head -n 1 "$WORK/log")" "head"

# Character devices: private nodes like /dev/null (1,3) and /dev/full (1,7) first, so that a
# regression cannot replace the system's; then /dev/null itself.
if mknod "$WORK/null" c 1 3 2>/dev/null && mknod "$WORK/full" c 1 7 2>/dev/null; then
  expect_exit 0 "$BIN/splat-convert" -q "$in" "$WORK/null" --format splk
  if [ -c "$WORK/null" ]; then
    pass
    expect_exit 0 "$BIN/splat-convert" -q "$in" /dev/null --format splk
    [ -c /dev/null ] && pass || fail "/dev/null is no longer a device"
  else
    fail "the device node was replaced by a $(stat -c %F "$WORK/null")"
  fi
  # A full device: the write error is an output failure naming OUT; the node stays.
  expect_exit 4 "$BIN/splat-convert" -q "$in" "$WORK/full" --format splk
  expect_stderr "^splat-convert: .*/full: write failed: No space left on device"
  [ -c "$WORK/full" ] && pass || fail "the full device node was replaced"
  no_temp "$WORK" "device"
fi

# Symlink: followed like cp; the link stays, the target (elsewhere) gets the bytes and keeps
# its mode, no temporary file anywhere.
mkdir "$WORK/real" "$WORK/links"
printf 'old\n' > "$WORK/real/target.splk"
chmod 640 "$WORK/real/target.splk"
ln -s ../real/target.splk "$WORK/links/link.splk"
expect_exit 0 "$BIN/splat-convert" -q "$in" "$WORK/links/link.splk" --format splk
[ -L "$WORK/links/link.splk" ] && pass || fail "the symlink was replaced"
expect_eq "symlink target" "$(cksum < "$WORK/real/target.splk")" "$want"
expect_eq "symlink target mode" "$(stat -c %a "$WORK/real/target.splk")" 640
no_temp "$WORK/real" "symlink"
no_temp "$WORK/links" "symlink"
ln -s nowhere.splk "$WORK/links/dangling.splk"
expect_exit 4 "$BIN/splat-convert" -q "$in" "$WORK/links/dangling.splk"
expect_stderr "^splat-convert: .*/dangling.splk: is a dangling symbolic link"
[ -L "$WORK/links/dangling.splk" ] && [ ! -e "$WORK/links/nowhere.splk" ] && pass ||
  fail "the dangling link was written through or replaced"

# A directory: exit 4.
mkdir "$WORK/dir.splk"
expect_exit 4 "$BIN/splat-convert" -q "$in" "$WORK/dir.splk"
expect_stderr "^splat-convert: .*/dir.splk: is a directory"

# A write-protected file (root included): exit 4, the file untouched.
printf 'precious\n' > "$WORK/ro.splk"
precious=$(cksum < "$WORK/ro.splk")
chmod 444 "$WORK/ro.splk"
expect_exit 4 "$BIN/splat-convert" -q "$in" "$WORK/ro.splk"
expect_stderr "^splat-convert: .*/ro.splk: is write-protected"
expect_eq "write-protected: contents" "$(cksum < "$WORK/ro.splk")" "$precious"
expect_eq "write-protected: mode" "$(stat -c %a "$WORK/ro.splk")" 444
no_temp "$WORK" "write-protected"

# Replacing a regular file keeps its mode (not 0644 less the umask).
printf 'old\n' > "$WORK/mode.splk"
chmod 600 "$WORK/mode.splk"
(umask 022 && "$BIN/splat-convert" -q "$in" "$WORK/mode.splk" --format splk)
expect_eq "replaced file: mode" "$(stat -c %a "$WORK/mode.splk")" 600
expect_eq "replaced file: bytes" "$(cksum < "$WORK/mode.splk")" "$want"

finish

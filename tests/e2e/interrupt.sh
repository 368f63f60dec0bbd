# A run killed by Ctrl-C (SIGINT), SIGTERM or SIGHUP in the middle of writing its output leaves no
# temporary file, keeps the existing output byte for byte, and dies of the signal (exit status
# 128 + N as the shell reports it). The same for the spill file of a PCD read from standard input.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
# Job control: a background job of a script would otherwise start with SIGINT ignored, and a
# signal ignored from the start stays ignored (as under nohup).
set -m

# waits up to 60 s for a file matching GLOB that holds at least one byte; prints its name.
wait_for_file() {
  local i f
  for i in $(seq 1 6000); do
    for f in $1; do
      [ -s "$f" ] && { echo "$f"; return 0; }
    done
    sleep 0.01
  done
  return 1
}

# One input large enough that writing it as text takes a while.
"$BIN/splat-synth" -q sphere "$WORK/big.splk" -n 1000000 --no-color
printf 'the previous output\n' > "$WORK/out.xyz"
before=$(cksum < "$WORK/out.xyz")

for sig in INT TERM HUP; do
  "$BIN/splat-convert" -q "$WORK/big.splk" "$WORK/out.xyz" &
  pid=$!
  tmp=$(wait_for_file "$WORK/out.xyz.tmp.*")
  kill -STOP "$pid"  # hold it in the middle of the write while we look
  if [ -n "$tmp" ] && [ -e "$tmp" ]; then pass; else fail "SIG$sig: no temporary output seen"; fi
  kill -"$sig" "$pid"
  kill -CONT "$pid"
  # Under job control, wait also returns when the job stops (status 128 + SIGSTOP): the stop may be
  # reported only now, after the CONT, and until the shell has taken note of the CONT the job
  # still counts as stopped, so wait returns at once again. Wait again (up to 10 s) until the
  # process has ended.
  for _ in $(seq 1 1000); do
    wait "$pid"
    status=$?
    [ "$status" -ne $((128 + $(kill -l STOP))) ] && break
    sleep 0.01
  done
  expect_eq "SIG$sig: exit status" "$status" $((128 + $(kill -l "$sig")))
  left=$(ls "$WORK" | grep -c '\.tmp\.')
  expect_eq "SIG$sig: temporary files left" "$left" 0
  expect_eq "SIG$sig: previous output" "$(cksum < "$WORK/out.xyz")" "$before"
  rm -f "$WORK"/out.xyz.tmp.*  # so that the next round sees only its own
done

# PCD on standard input is spilled to $TMPDIR for PCL: removed after a good read, after a bad one,
# and on a signal while the input is still coming.
mkdir "$WORK/tmp"
TMPDIR=$WORK/tmp "$BIN/splat-info" - < "$SRC/data-samples/cad-pcl.pcd" > /dev/null 2>&1
expect_eq "PCD on stdin: exit" "$?" 0
expect_eq "PCD on stdin: spill files left" "$(ls "$WORK/tmp" | wc -l)" 0
pcd_header='VERSION 0.7\nFIELDS x y z\nSIZE 4 4 4\nTYPE F F F\nCOUNT 1 1 1\nWIDTH 100000\nHEIGHT 1\nVIEWPOINT 0 0 0 1 0 0 0\nPOINTS 100000\nDATA binary\n'
{ printf "$pcd_header"; head -c 1000 /dev/zero; } | TMPDIR=$WORK/tmp "$BIN/splat-info" - > /dev/null 2>&1
expect_eq "truncated PCD on stdin: exit" "$?" 2
expect_eq "truncated PCD on stdin: spill files left" "$(ls "$WORK/tmp" | wc -l)" 0

mkfifo "$WORK/feed"
for sig in INT TERM HUP; do
  TMPDIR=$WORK/tmp "$BIN/splat-info" - < "$WORK/feed" > /dev/null 2>&1 &
  pid=$!
  exec 3> "$WORK/feed"
  { printf "$pcd_header"; head -c 4096 /dev/zero; } >&3
  spill=$(wait_for_file "$WORK/tmp/splatkit-pcd-*")
  [ -n "$spill" ] && pass || fail "SIG$sig: no PCD spill file seen"
  kill -"$sig" "$pid"
  wait "$pid"
  expect_eq "SIG$sig while spilling: exit status" "$?" $((128 + $(kill -l "$sig")))
  exec 3>&-
  expect_eq "SIG$sig while spilling: spill files left" "$(ls "$WORK/tmp" | wc -l)" 0
  rm -f "$WORK"/tmp/*
done

finish

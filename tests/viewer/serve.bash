# start_server FILE...: runs `splat-view --serve FILE... --port 0` in the background; sets
# SERVER_PID and URL (from the line it prints). Sourced after tests/e2e/common.bash.
start_server() {
  "$BIN/splat-view" --serve "$@" --port 0 >"$WORK/serve.out" 2>"$WORK/serve.err" &
  SERVER_PID=$!
  URL=
  for _ in $(seq 100); do
    URL=$(grep -o 'http://127\.0\.0\.1:[0-9]*/' "$WORK/serve.out" 2>/dev/null)
    [ -n "$URL" ] && return 0
    kill -0 "$SERVER_PID" 2>/dev/null || break
    sleep 0.05
  done
  fail "splat-view --serve printed no URL: $(cat "$WORK/serve.err")"
  return 1
}

# stop_server SIGNAL: sends SIGNAL and checks that the server exits 0 within 5 s.
stop_server() {
  kill "-$1" "$SERVER_PID"
  for _ in $(seq 100); do
    kill -0 "$SERVER_PID" 2>/dev/null || break
    sleep 0.05
  done
  if kill -0 "$SERVER_PID" 2>/dev/null; then
    fail "splat-view --serve still runs 5 s after SIG$1"
    kill -KILL "$SERVER_PID"
  fi
  wait "$SERVER_PID"
  expect_eq "exit status after SIG$1" "$?" 0
}

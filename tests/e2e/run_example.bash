# How the example tests run a documented command (tests/e2e/examples.sh, doc_examples.sh); sourced
# after common.bash.
# A sanitizer build (ASan, detected from the binary) leaves out the examples of the 10M-point
# city: its walkthrough render is two thirds of this test's CPU there (53 of 81 s), and its
# occlusion culling runs under the sanitizers in e2e.occlusion (150k points). A release build
# runs every example.
sanitized=0
grep -q __asan_init "$BIN/splat-info" 2>/dev/null && sanitized=1
left_out() {  # left_out COMMAND: true (and a note) for an example this build does not run
  [ $sanitized = 1 ] && [[ $1 == *city.splk* ]] || return 1
  echo "note: not run in a sanitizer build: $1"
}

run_example() {  # run_example SOURCE COMMAND
  local cmd=$2 code
  bash -o pipefail -c "$cmd" >"$WORK/ex.out" 2>"$WORK/ex.err"
  code=$?
  if [ "$code" -ne 0 ]; then
    fail "$1: exit $code: $cmd"; sed 's/^/  stderr: /' "$WORK/ex.err" | head -5 >&2
  elif grep -v -E '^[a-z-]+: [0-9]+ (points|splats|splats drawn|samples|triangles) in ' "$WORK/ex.err" | grep -q .; then
    fail "$1: unexpected stderr: $cmd: $(head -3 "$WORK/ex.err")"
  else
    pass
  fi
}

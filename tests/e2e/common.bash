# Shared helpers for the end-to-end tests. Each test script is run by ctest as
#   bash tests/e2e/<name>.sh BIN_DIR SOURCE_DIR
# and sources this file. Work happens in a private temp dir, removed on exit.
set -uo pipefail
BIN=${1:?bin dir}
SRC=${2:?source dir}
WORK=$(mktemp -d)
trap 'rm -rf "$WORK"' EXIT
FAILS=0
CHECKS=0

fail() { echo "FAIL: $*" >&2; FAILS=$((FAILS + 1)); }
pass() { CHECKS=$((CHECKS + 1)); }

# expect_exit CODE CMD...: runs CMD, checks the exit code; stderr kept in $WORK/stderr.
expect_exit() {
  local want=$1; shift
  "$@" >"$WORK/stdout" 2>"$WORK/stderr"
  local got=$?
  if [ "$got" -ne "$want" ]; then
    fail "exit $got (want $want): $*"; sed 's/^/  stderr: /' "$WORK/stderr" | head -5 >&2
  else
    pass
  fi
}

# expect_stderr REGEX: the last command's stderr matches REGEX and is a single line.
expect_stderr() {
  if ! grep -Eq -- "$1" "$WORK/stderr"; then
    fail "stderr does not match /$1/: $(head -3 "$WORK/stderr")"
  elif [ "$(wc -l <"$WORK/stderr")" -ne 1 ]; then
    fail "stderr is not one line: $(cat "$WORK/stderr")"
  else
    pass
  fi
}

expect_eq() {  # expect_eq WHAT GOT WANT
  if [ "$2" != "$3" ]; then fail "$1: got '$2', want '$3'"; else pass; fi
}

finish() {
  echo "$CHECKS checks passed, $FAILS failed"
  [ "$FAILS" -eq 0 ]
  exit $?
}

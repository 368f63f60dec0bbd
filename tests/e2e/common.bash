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

# patch_iou PLY: the IoU of every true patch (patch_id) with its best surface (surface_id) in a
# binary little-endian PLY, as "segments N" then "patch P splats N surface S IoU X" per patch
# (X at full precision, so that a comparison with a threshold is exact).
patch_iou() {
  python3 - "$1" <<'PY'
import struct, sys
data = open(sys.argv[1], "rb").read()
end = data.index(b"end_header\n") + len(b"end_header\n")
props, n = [], 0
for line in data[:end].decode().splitlines():
    w = line.split()
    if w[:2] == ["element", "vertex"]: n = int(w[2])
    if w[0] == "property": props.append((w[1], w[2]))
fmt = {"float": "f", "uint": "I", "uchar": "B", "int": "i", "double": "d", "ushort": "H"}
rec = struct.Struct("<" + "".join(fmt[t] for t, _ in props))
names = [p for _, p in props]
pi, si = names.index("patch_id"), names.index("surface_id")
patch, surf, pairs = {}, {}, {}
for v in rec.iter_unpack(data[end:end + n * rec.size]):
    p, s = v[pi], v[si]
    patch[p] = patch.get(p, 0) + 1
    surf[s] = surf.get(s, 0) + 1
    pairs[(p, s)] = pairs.get((p, s), 0) + 1
print("segments", len(surf))
for p in sorted(patch):
    best = max((c / (patch[p] + surf[s] - c), s) for (q, s), c in pairs.items() if q == p)
    print("patch %d splats %d surface %d IoU %r" % (p, patch[p], best[1], best[0]))
PY
}

finish() {
  echo "$CHECKS checks passed, $FAILS failed"
  [ "$FAILS" -eq 0 ]
  exit $?
}

# sweep_ply FILE N: N splats at the same place (0: an empty cloud), x y z nx ny nz radius.
sweep_ply() {
  printf 'ply\nformat ascii 1.0\nelement vertex %d\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float radius\nend_header\n' "$2" >"$1"
  for ((i = 0; i < $2; i++)); do echo "1 2 3 0 0 1 0.1"; done >>"$1"
}

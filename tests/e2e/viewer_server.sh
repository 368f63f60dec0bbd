# splat-view --serve: serves the page and exactly the files named (with Range requests), answers
# 404 for anything else however the path is spelled, listens on 127.0.0.1 only, and exits 0 on
# SIGINT and SIGTERM.
source "$(dirname "$0")/common.bash"
source "$SRC/tests/viewer/serve.bash"
S=$SRC/data-samples
command -v curl >/dev/null || { echo "SKIP: curl is not installed"; exit 77; }

mkdir -p "$WORK/d"
cp "$S/torus.ply" "$WORK/d/torus.ply"
echo secret >"$WORK/d/secret.txt"
start_server "$WORK/d/torus.ply" || finish

# getr PATH [CURL ARGS...]: prints the HTTP status; the body goes to $WORK/body.
getr() { local p=$1; shift; curl -s --path-as-is -o "$WORK/body" -w '%{http_code}' "$@" "${URL%/}$p"; }

expect_eq "page" "$(getr /)" 200
grep -q '<canvas' "$WORK/body" && pass || fail "/ is not the viewer page"
expect_eq "page module" "$(getr /viewer.js)" 200
expect_eq "listing" "$(getr /files.json)" 200
expect_eq "listing body" "$(cat "$WORK/body")" '{"files":["torus.ply"]}'
expect_eq "served file" "$(getr /files/torus.ply)" 200
cmp -s "$WORK/body" "$S/torus.ply" && pass || fail "/files/torus.ply differs from the file"
expect_eq "range" "$(getr /files/torus.ply -H 'Range: bytes=100-199')" 206
expect_eq "range bytes" "$(od -An -tx1 "$WORK/body" | tr -d ' \n')" \
  "$(tail -c +101 "$S/torus.ply" | head -c 100 | od -An -tx1 | tr -d ' \n')"
expect_eq "view model" "$(getr /model/torus.ply)" 200
expect_eq "view model magic" "$(head -c 7 "$WORK/body")" SKVIEW1

# Nothing else: other files beside it, path escapes in every spelling, absolute paths.
for p in /files/secret.txt /files/../d/secret.txt /files/..%2fsecret.txt /files/%2e%2e/secret.txt \
         "/files/$WORK/d/secret.txt" /files//etc/passwd /files/../../../../etc/passwd \
         /etc/passwd /model/secret.txt /files/ /files/torus.ply/ /files/TORUS.PLY /viewer.js/.. \
         /../../etc/passwd /files/torus.ply%00 /model/../files/torus.ply; do
  code=$(getr "$p")
  expect_eq "GET $p" "$code" 404
  grep -q secret "$WORK/body" && fail "GET $p returned the other file"
done
expect_eq "POST" "$(getr /files/torus.ply -X POST -d x)" 404

# Loopback only: the listening socket is 127.0.0.1:PORT (never 0.0.0.0 or ::).
port=${URL##*:}; port=${port%/}
listen=$(ss -Hltn "sport = :$port" | awk '{print $4}' | sort -u | tr '\n' ' ')
expect_eq "listening address" "$listen" "127.0.0.1:$port "
other=$(hostname -I 2>/dev/null | awk '{print $1}')
if [ -n "$other" ] && [ "${other#127.}" = "$other" ]; then
  code=$(curl -s -o /dev/null -w '%{http_code}' --max-time 2 "http://$other:$port/")
  expect_eq "reached on $other" "$code" 000
fi
# A port already taken is an error (exit 4), not a second server sharing it.
expect_exit 4 "$BIN/splat-view" --serve "$S/torus.ply" --port "$port"
expect_stderr "cannot listen there"
stop_server INT

start_server "$S/torus.ply" || finish
stop_server TERM

# Bad command lines.
expect_exit 2 "$BIN/splat-view" --serve "$WORK/missing.ply"
expect_exit 1 "$BIN/splat-view" --serve "$S/torus.ply" "$WORK/d/torus.ply"
expect_stderr "two files named 'torus.ply'"
expect_exit 1 "$BIN/splat-view" --serve "$S/torus.ply" -o x.png
expect_exit 1 "$BIN/splat-view" "$S/torus.ply" "$WORK/x.png" --port 80
finish

# LAZ (LASzip) reading and writing, point data formats 0-3.
#  1. Random scan-like records of every format (with and without extra bytes, one chunk and many,
#     a last chunk of one point, fixed and variable chunk sizes) written as LAS and as LAZ by
#     splatkit's writer: splatkit's decoder
#     and laz-perf (LASzip compiled to WebAssembly, npm "laz-perf", run under node; the oracle,
#     skipped with a message when node or laz-perf is missing) must both give back every byte of
#     every record.
#  2. The clouds read from a LAZ file and from the same LAS file are identical, for any thread
#     count and through stdin; LAS -> LAZ -> LAS keeps every record.
#  3. The LAZ samples in data-samples/ decode identically in laz-perf.
#  4. Hostile LAZ files exit 2 (truncated chunk, bad chunk table, wrong point count, corrupt chunk
#     data) within 5 s and 300 MB; LAZ variants the decoder lacks exit 3 naming what is missing.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
S=$SRC/data-samples
R=${SPLATKIT_LAZ_RECORDS:-$BIN/../tests/laz_records}
[ -x "$R" ] || { echo "laz_records helper not found ($R)" >&2; exit 1; }
cd "$WORK"

# The records of an uncompressed LAS file (after offset_to_point_data).
las_records() {
  python3 -c 'import struct,sys; d=open(sys.argv[1],"rb").read(); o=struct.unpack_from("<I",d,96)[0]; open(sys.argv[2],"wb").write(d[o:])' "$1" "$2"
}

lazperf=""
if ! command -v node >/dev/null; then
  echo "SKIP laz-perf comparisons: node is not installed (apt-get install nodejs npm)"
elif [ -z "${SPLATKIT_LAZ_PERF_DIR:-}" ] || [ ! -d "$SPLATKIT_LAZ_PERF_DIR/laz-perf" ]; then
  echo "SKIP laz-perf comparisons: laz-perf not found in SPLATKIT_LAZ_PERF_DIR='${SPLATKIT_LAZ_PERF_DIR:-}'" \
       "(npm install --prefix BUILD/node laz-perf, or configure with -DSPLATKIT_LAZ_PERF_DIR=.../node_modules)"
else
  lazperf=yes
fi
lazperf_dump() { NODE_PATH=$SPLATKIT_LAZ_PERF_DIR node "$SRC/tests/laz/lazperf_dump.js" "$1" "$2" >/dev/null; }

# ---- 1. records, every format ------------------------------------------------------------------
for spec in "0 20000 6000 0" "0 1 50000 0" "1 15001 5000 3" "2 9000 50000 0" "2 12001 4000 7" \
            "3 25000 7000 0" "3 10001 5000 2" "1 2 1 0" "1 20000 v3000 0" "3 9000 v100 1"; do
  read -r fmt n chunk extra <<<"$spec"
  tag="format $fmt, $n points, chunks of $chunk, $extra extra bytes"
  "$R" make "$fmt" "$n" "$chunk" "$((n + fmt))" "$extra" r.las r.laz || { fail "make: $tag"; continue; }
  las_records r.las want.bin
  "$R" dump r.laz ours.bin >/dev/null || fail "our decoder failed: $tag"
  cmp -s want.bin ours.bin && pass || fail "our decoder differs from the records: $tag"
  if [ -n "$lazperf" ]; then
    if lazperf_dump r.laz lp.bin; then
      cmp -s want.bin lp.bin && pass || fail "laz-perf decodes our LAZ differently: $tag"
    else fail "laz-perf cannot read our LAZ: $tag"; fi
  fi
  # The same file read through the whole pipeline: LAS and LAZ give the same cloud.
  "$BIN/splat-convert" -q r.las a.ply && "$BIN/splat-convert" -q r.laz b.ply
  cmp -s a.ply b.ply && pass || fail "LAZ and LAS give different clouds: $tag"
done

# ---- 2. threads, stdin, LAS -> LAZ -> LAS -------------------------------------------------------
"$R" make 3 60000 5000 11 0 m.las m.laz
expect_eq "LAZ smaller than LAS" "$(( $(stat -c%s m.laz) * 3 < $(stat -c%s m.las) ))" 1
"$BIN/splat-convert" -q --threads 1 m.laz t1.ply
"$BIN/splat-convert" -q --threads 2 m.laz t2.ply
cmp -s t1.ply t2.ply && pass || fail "LAZ decoding depends on the thread count"
"$BIN/splat-convert" -q - stdin.ply <m.laz
cmp -s t1.ply stdin.ply && pass || fail "LAZ through stdin differs"
# splat-convert's LAZ output (a cloud's fields back into records) reads back as the same cloud.
"$BIN/splat-convert" -q "$S/torus-las12.las" torus.laz && "$BIN/splat-convert" -q torus.laz a.ply
"$BIN/splat-convert" -q "$S/torus-las12.las" b.ply
cmp -s a.ply b.ply && pass || fail "LAS -> LAZ by splat-convert changed the cloud"
if [ -n "$lazperf" ]; then
  "$BIN/splat-convert" -q torus.laz torus.las && las_records torus.las a.bin && lazperf_dump torus.laz b.bin
  cmp -s a.bin b.bin && pass || fail "laz-perf reads splat-convert's LAZ differently"
fi
"$BIN/splat-info" --json m.laz >info.json 2>/dev/null || "$BIN/splat-info" m.laz >info.json
grep -q '60000' info.json && pass || fail "splat-info on LAZ: $(head -3 info.json)"

# ---- 3. shipped samples ---------------------------------------------------------------------------
for f in "$S"/*.laz; do
  [ -e "$f" ] || { fail "no LAZ sample in data-samples/"; break; }
  "$R" dump "$f" ours.bin >/dev/null || fail "our decoder failed on $(basename "$f")"
  if [ -n "$lazperf" ]; then
    lazperf_dump "$f" lp.bin && cmp -s ours.bin lp.bin && pass || fail "laz-perf disagrees on $(basename "$f")"
  fi
done

# ---- 4. hostile and unsupported -------------------------------------------------------------------
# bounded CODE REGEX FILE: splat-info exits CODE with a message matching REGEX in 5 s and 300 MB.
time_limit=5 rss_limit_kb=$((300 * 1024))
if grep -q __asan_init "$BIN/splat-info" 2>/dev/null; then time_limit=20 rss_limit_kb=$((900 * 1024)); fi
bounded() {
  local want=$1 regex=$2 file=$3 t0 t1 got rss
  t0=$(date +%s.%N)
  /usr/bin/time -f %M -o rss timeout -s KILL $((time_limit * 3)) "$BIN/splat-info" "$file" >/dev/null 2>err
  got=$?; t1=$(date +%s.%N)
  rss=$(tail -1 rss | grep -Eo '^[0-9]+$' || echo 0)
  [ "$got" -eq "$want" ] && pass || { fail "exit $got (want $want): $file"; head -2 err >&2; }
  grep -Eq -- "$regex" err && pass || fail "stderr does not match /$regex/: $(head -1 err)"
  awk -v a="$t0" -v b="$t1" -v l="$time_limit" 'BEGIN { exit !(b - a > l) }' && fail "too slow: $file" || pass
  [ "$rss" -le "$rss_limit_kb" ] && pass || fail "peak RSS $((rss / 1024)) MB: $file"
}
"$R" make 1 30000 5000 5 0 h.las h.laz
"$R" cut h.laz cut.laz 2 40
bounded 2 "LAZ chunk 2 of 6 .*compressed data ends before the points" cut.laz
python3 - h.laz <<'PY'
import struct, sys, random
d = bytearray(open(sys.argv[1], "rb").read())
off = struct.unpack_from("<I", d, 96)[0]
table = struct.unpack_from("<Q", d, off)[0]
def w(name, b): open(name, "wb").write(b)
w("trunc.laz", d[: len(d) // 2])                                  # the chunk table is cut off
b = bytearray(d); struct.pack_into("<Q", b, off, 1 << 60); w("table-offset.laz", b)
b = bytearray(d); struct.pack_into("<I", b, table + 4, 0xFFFFFFFF); w("table-count.laz", b)
b = bytearray(d); b[table + 8:] = bytes(random.Random(1).randrange(256) for _ in range(len(d) - table - 8)); w("table-garbage.laz", b)
b = bytearray(d); struct.pack_into("<I", b, 107, 3000000); w("count-more.laz", b)
b = bytearray(d); struct.pack_into("<I", b, 107, 29000); w("count-less.laz", b)
b = bytearray(d); struct.pack_into("<I", b, 107, 29999); w("count-one-less.laz", b)
b = bytearray(d); start = off + 8 + 300
b[start:start + 200] = bytes(random.Random(2).randrange(256) for _ in range(200)); w("chunk-garbage.laz", b)
# The LASzip VLR: 227-byte header, 54-byte VLR header, then its payload.
vlr = 227 + 54
b = bytearray(d); struct.pack_into("<I", b, vlr + 12, 0xFFFFFFFF); w("variable-chunks.laz", b)
b = bytearray(d); struct.pack_into("<H", b, vlr + 0, 3); w("layered.laz", b)
b = bytearray(d); struct.pack_into("<H", b, vlr + 0, 1); w("pointwise.laz", b)
b = bytearray(d); struct.pack_into("<H", b, vlr + 34 + 4, 1); w("item-v1.laz", b)
b = bytearray(d); b[vlr - 54 + 2:vlr - 54 + 18] = b"something else\0\0"; w("no-vlr.laz", b)
PY
bounded 2 "chunk table offset .* lies outside the point data" trunc.laz
bounded 2 "chunk table offset .* lies outside the point data" table-offset.laz
bounded 2 "chunk table lists 4294967295 chunks but the point data has room for at most" table-count.laz
bounded 2 "LAZ chunk .* (claims|bytes)" table-garbage.laz
bounded 2 "header says 3000000 points, 600 chunks of 5000 points, but the chunk table lists 6" count-more.laz
bounded 2 "LAZ chunk 5 of 6 .*bytes are left after its 4000 points" count-less.laz
bounded 2 "LAZ chunk 5 of 6 .*bytes are left after its 4999 points" count-one-less.laz
bounded 2 "LAZ chunk 0 of 6" chunk-garbage.laz
bounded 2 "LAZ chunk table" variable-chunks.laz
bounded 3 "layered compressor.* is not supported" layered.laz
bounded 3 "LASzip compressor 1 is not supported" pointwise.laz
bounded 3 "LASzip item POINT10 version 1 is not supported" item-v1.laz
bounded 2 "without the LASzip VLR" no-vlr.laz

finish

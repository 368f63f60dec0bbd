# LAZ (LASzip) reading and writing, point data formats 0-3 (point-wise chunks) and 6-8 (layered
# chunks, LAS 1.4).
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
            "3 25000 7000 0" "3 10001 5000 2" "1 2 1 0" "1 20000 v3000 0" "3 9000 v100 1" \
            "6 20000 6000 0" "6 15001 5000 0" "7 12001 4000 2" "7 9000 v300 1" "8 10000 50000 3" \
            "8 7001 3000 0" "6 1 50000 0" "8 2 1 1"; do
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

# ---- 1b. layered chunks: the fields the records exercise, and splat-convert's LAS 1.4 output ------
# (odd seeds keep intensity, user data and point source constant: empty layers; even seeds vary)
"$R" make 8 20000 5000 21 2 l.las l.laz
python3 - l.las l.laz <<'PY' && pass || fail "format 8 records do not exercise the layered models"
import struct, sys
d = open(sys.argv[1], "rb").read(); z = open(sys.argv[2], "rb").read()
assert d[24:26] == bytes([1, 4]) and struct.unpack_from("<H", d, 94)[0] == 375
assert struct.unpack_from("<I", d, 107)[0] == 0 and struct.unpack_from("<Q", d, 247)[0] == 20000
assert z[104] == 0x88 and struct.unpack_from("<H", z, 375 + 54)[0] == 3   # compressor 3
o = struct.unpack_from("<I", d, 96)[0]; rl = struct.unpack_from("<H", d, 105)[0]
recs = [d[o + i * rl:o + (i + 1) * rl] for i in range(20000)]
chans = {(r[15] >> 4) & 3 for r in recs}; rets = {r[14] >> 4 for r in recs}
assert chans == {0, 1, 2, 3}, chans
assert max(rets) > 7, rets
assert len({r[36:38] for r in recs}) > 100 and len({r[18:20] for r in recs}) > 100
PY
# splat-convert keeps a LAS 1.4 file's point format family; --las-format picks one.
"$BIN/splat-convert" -q l.las l2.laz && "$BIN/splat-convert" -q l2.laz l2.ply && "$BIN/splat-convert" -q l.las l.ply
cmp -s l.ply l2.ply && pass || fail "LAS 1.4 format 8 -> LAZ -> cloud changed the cloud"
expect_eq "splat-convert keeps format 8" "$(python3 -c 'import sys; print(open(sys.argv[1],"rb").read()[104])' l2.laz)" 136
"$BIN/splat-convert" -q --las-format 7 "$S/torus-las12.las" t7.laz && "$BIN/splat-convert" -q t7.laz t7.las
expect_eq "--las-format 7" "$(python3 -c 'import sys; print(open(sys.argv[1],"rb").read()[104])' t7.laz)" 135
"$BIN/splat-convert" -q "$S/torus-las12.las" t2.ply && "$BIN/splat-convert" -q t7.las t7.ply
python3 - t2.ply t7.ply <<'PY' && pass || fail "--las-format 7 changed positions or colours"
import sys
def body(p):
    d = open(p, "rb").read(); return d, d.index(b"end_header\n") + 11
a, ia = body(sys.argv[1]); b, ib = body(sys.argv[2])
# Same vertex count and the same first 12 bytes (x, y, z float32) of the first vertex.
import re
na = int(re.search(rb"element vertex (\d+)", a).group(1)); nb = int(re.search(rb"element vertex (\d+)", b).group(1))
assert na == nb and a[ia:ia + 12] == b[ib:ib + 12], (na, nb)
PY
if [ -n "$lazperf" ]; then
  las_records t7.las a.bin && lazperf_dump t7.laz b.bin
  cmp -s a.bin b.bin && pass || fail "laz-perf reads splat-convert's format 7 LAZ differently"
fi

# ---- 2. threads, stdin, LAS -> LAZ -> LAS -------------------------------------------------------
"$R" make 3 60000 5000 11 0 m.las m.laz
expect_eq "LAZ smaller than LAS" "$(( $(stat -c%s m.laz) * 3 < $(stat -c%s m.las) ))" 1
"$BIN/splat-convert" -q --threads 1 m.laz t1.ply
"$BIN/splat-convert" -q --threads 2 m.laz t2.ply
cmp -s t1.ply t2.ply && pass || fail "LAZ decoding depends on the thread count"
"$BIN/splat-convert" -q - stdin.ply <m.laz
cmp -s t1.ply stdin.ply && pass || fail "LAZ through stdin differs"
"$BIN/splat-info" --json - <m.laz | grep -q '"format": "laz"' && pass || fail "LAZ on stdin named"
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
# Bytes after the chunk table are refused as after a LAS file's last record (LAS 1.2 and 1.4).
for f in h.laz "$S/torus-las12.laz" "$S/two-spheres-las14.laz"; do
  cp "$f" tail-in.laz && head -c 1000 /dev/urandom >>tail-in.laz
  bounded 2 "tail-in.laz: 100[01] bytes of trailing data after the LAZ chunk table" tail-in.laz
done
# LAS 1.4 EVLRs after the chunk table are read over (the same cloud); bytes after the last EVLR,
# or an EVLR that overlaps the chunk table, are refused.
python3 - "$S/two-spheres-las14.laz" <<'PY'
import struct, sys
d = bytearray(open(sys.argv[1], "rb").read())
def evlr(payload):
    return struct.pack("<H16sHQ32s", 0, b"splatkit test", 1, len(payload), b"an EVLR") + payload
def w(name, b, start, count):
    b = bytearray(b); struct.pack_into("<QI", b, 235, start, count); open(name, "wb").write(b)
w("evlr.laz", d + evlr(b"x" * 100) + evlr(b""), len(d), 2)
w("evlr-tail.laz", d + evlr(b"x" * 100) + b"garbage", len(d), 1)
w("evlr-overlap.laz", d + evlr(b"x" * 100), len(d) - 20, 1)
PY
expect_exit 0 "$BIN/splat-convert" -q evlr.laz evlr.ply
"$BIN/splat-convert" -q "$S/two-spheres-las14.laz" no-evlr.ply
cmp -s evlr.ply no-evlr.ply && pass || fail "EVLRs after the chunk table changed the cloud"
bounded 2 "evlr-tail.laz: 7 bytes of trailing data after the EVLR" evlr-tail.laz
bounded 2 "evlr-overlap.laz: first EVLR at byte [0-9]+ does not lie between the end of the LAZ chunk table" evlr-overlap.laz
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

# Layered chunks (format 7, 3 extra bytes): a truncated layer, a layer size beyond the chunk, wrong
# point counts in the chunk, the header and the table, garbage layers; formats 9/10 and LASzip
# variants the decoder lacks exit 3.
"$R" make 7 30000 5000 2 3 h7.las h7.laz
"$R" cut h7.laz cut7.laz 2 40
bounded 2 "LAZ chunk 2 of 6 .*layers claim [0-9]+ bytes, [0-9]+ follow" cut7.laz
python3 - h7.laz <<'PY'
import struct, sys, random
d = bytearray(open(sys.argv[1], "rb").read())
off = struct.unpack_from("<I", d, 96)[0]
table = struct.unpack_from("<Q", d, off)[0]
rl = 39; chunk0 = off + 8; sizes0 = chunk0 + rl + 4        # 9 POINT14 + 1 RGB14 + 3 BYTE14 sizes
def w(name, b): open(name, "wb").write(b)
b = bytearray(d); struct.pack_into("<I", b, chunk0 + rl, 5001); w("l-count.laz", b)
b = bytearray(d); struct.pack_into("<I", b, chunk0 + rl, 0xFFFFFFFF); w("l-count-huge.laz", b)
b = bytearray(d); struct.pack_into("<I", b, sizes0 + 4, 0x7FFFFFFF); w("l-size.laz", b)
b = bytearray(d); struct.pack_into("<I", b, sizes0, 0); w("l-xy-empty.laz", b)
b = bytearray(d); struct.pack_into("<I", b, sizes0 + 8, 2); w("l-size-small.laz", b)
b = bytearray(d); s = sizes0 + 13 * 4 + 50
b[s:s + 3000] = bytes(random.Random(3).randrange(256) for _ in range(3000)); w("l-garbage.laz", b)
b = bytearray(d); struct.pack_into("<Q", b, 247, 10 ** 12); w("l-header-count.laz", b)
b = bytearray(d); struct.pack_into("<Q", b, 247, 29999); w("l-header-less.laz", b)
b = bytearray(d); b[104] = 0x80 | 10; struct.pack_into("<H", b, 105, 67 + 3); w("l-format10.laz", b)
b = bytearray(d); b[104] = 0x80 | 9; struct.pack_into("<H", b, 105, 59 + 3); w("l-format9.laz", b)
vlr = 375 + 54
b = bytearray(d); struct.pack_into("<H", b, vlr, 2); w("l-pointwise.laz", b)
b = bytearray(d); struct.pack_into("<H", b, vlr + 34 + 4, 4); w("l-item-v4.laz", b)
b = bytearray(d); struct.pack_into("<H", b, vlr + 34 + 6, 12); w("l-item-nir.laz", b)
PY
bounded 2 "LAZ chunk 0 of 6 .*chunk says it holds 5001 points, the chunk table 5000" l-count.laz
bounded 2 "LAZ chunk 0 of 6 .*chunk says it holds 4294967295 points" l-count-huge.laz
bounded 2 "LAZ chunk 0 of 6 .*layers claim" l-size.laz
bounded 2 "LAZ chunk 0 of 6 .*(X/Y or Z layer of POINT14 is empty|layers claim)" l-xy-empty.laz
bounded 2 "LAZ chunk 0 of 6" l-size-small.laz
bounded 2 "LAZ chunk 0 of 6" l-garbage.laz
bounded 2 "header says 1000000000000 points, 200000000 chunks of 5000 points, but the chunk table lists 6" l-header-count.laz
bounded 2 "LAZ chunk 5 of 6 .*chunk says it holds 5000 points, the chunk table 4999" l-header-less.laz
bounded 3 "point data format 10 .*waveform.* is not supported" l-format10.laz
bounded 3 "point data format 9 .*waveform.* is not supported" l-format9.laz
bounded 3 "LASzip compressor 2 for point data format 7 is not supported \(3, layered chunked, is\)" l-pointwise.laz
bounded 3 "LASzip item POINT14 version 4 is not supported \(3 is\)" l-item-v4.laz
bounded 2 "LASzip item 1 is RGBNIR14 of 6 bytes; point data format 7 needs RGB14" l-item-nir.laz

# A careless user's LAZ: an empty cloud, one point and 100 identical points out and back in; a
# missing directory (4), nothing left.
sweep_ply empty.ply 0; sweep_ply one.ply 1; sweep_ply dup.ply 100
for f in empty one dup; do
  expect_exit 0 "$BIN/splat-convert" -q "$f.ply" "$f.laz"
  expect_exit 0 "$BIN/splat-info" "$f.laz"
  grep -q "^Points: $(case $f in empty) echo 0 ;; one) echo 1 ;; dup) echo 100 ;; esac)\$" "$WORK/stdout" &&
    pass || fail "$f.laz: $(grep Points "$WORK/stdout")"
done
expect_exit 4 "$BIN/splat-convert" -q dup.ply no/such/x.laz
expect_stderr "no/such/x.laz: cannot create"

finish

# Hostile and careless input, through the real binaries: every case must end with its documented
# exit code (never a signal), within a time and memory budget, leave every input byte-identical
# and leave no temporary file behind (beside the outputs, or a spill file in $TMPDIR).
#
# One line per case: hostile CODE REGEX [STDIN=file] -- CMD...
#   CODE   the exit code wanted; REGEX must match stderr (use '' to skip)
# Budget: 5 s and 300 MB per command in a release build; sanitizer builds (ASan, detected from
# the binary) get 4× the time and 3× the memory.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
S=$SRC/data-samples
IN=$WORK/in      # inputs: checksummed before and after every case
OUT=$WORK/out    # outputs
mkdir -p "$IN" "$OUT" "$WORK/tmp"
export TMPDIR=$WORK/tmp

time_limit=5 rss_limit_kb=$((300 * 1024))
if grep -q __asan_init "$BIN/splat-info" 2>/dev/null; then
  time_limit=20 rss_limit_kb=$((900 * 1024))
fi

sums() { (cd "$IN" && find . -type f -print0 | sort -z | xargs -0 -r sha256sum); }

hostile() {
  local want=$1 regex=$2; shift 2
  local stdin=/dev/null
  if [[ $1 == STDIN=* ]]; then stdin=${1#STDIN=}; shift; fi
  [ "$1" = -- ] && shift
  local before; before=$(sums)
  local t0 t1 got rss
  t0=$(date +%s.%N)
  /usr/bin/time -f %M -o "$WORK/rss" timeout -s KILL $((time_limit * 3)) "$@" \
    <"$stdin" >"$WORK/stdout" 2>"$WORK/stderr"
  got=$?
  t1=$(date +%s.%N)
  rss=$(tail -1 "$WORK/rss" 2>/dev/null | grep -Eo '^[0-9]+$' || echo 0)
  local what="$*"
  what=${what//$WORK/}
  if [ "$got" -ne "$want" ]; then
    fail "exit $got (want $want): $what"; sed 's/^/  stderr: /' "$WORK/stderr" | head -3 >&2
  else pass; fi
  # /usr/bin/time reports a signal as "Command terminated by signal N" and exit 128+N.
  if grep -q "terminated by signal" "$WORK/rss" 2>/dev/null || [ "$got" -ge 128 ]; then
    fail "killed by a signal: $what"
  else pass; fi
  if awk -v a="$t0" -v b="$t1" -v l="$time_limit" 'BEGIN { exit !(b - a > l) }'; then
    fail "took $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.1f", b - a }') s (limit $time_limit s): $what"
  else pass; fi
  if [ "$rss" -gt "$rss_limit_kb" ]; then
    fail "peak RSS $((rss / 1024)) MB (limit $((rss_limit_kb / 1024)) MB): $what"
  else pass; fi
  if [ -n "$regex" ] && ! grep -Eq -- "$regex" "$WORK/stderr"; then
    fail "stderr does not match /$regex/: $(head -2 "$WORK/stderr") ($what)"
  else pass; fi
  if [ "$before" = "$(sums)" ]; then pass; else
    fail "an input changed: $what"
    rm -rf "$IN" && cp -a "$WORK/in.orig" "$IN"  # so that the next cases read the real inputs
  fi
  local left
  left=$(find "$WORK" \( -name '*.tmp.*' -o -name 'splatkit-*' \) -print | head -3)
  [ -z "$left" ] && pass || fail "temporary files left: $left ($what)"
  rm -f "$OUT"/* 2>/dev/null
}

# ---- inputs --------------------------------------------------------------------------------------
"$BIN/splat-synth" -q torus "$IN/torus.splk" -n 4000 --random --seed 3
"$BIN/estimate-normals" -q "$IN/torus.splk" "$IN/splats.splk"
cp "$S/torus.ply" "$IN/torus.ply"
cp "$S/kitten.xyz" "$IN/kitten.xyz"

python3 - "$IN" <<'PY'
import struct, sys, random
d = sys.argv[1]
# PLY headers that scale: 100k properties, 100k elements.
with open(f"{d}/many-props.ply", "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n")
    f.write("".join(f"property float p{i}\n" for i in range(100000)))
    f.write("end_header\n" + " ".join(["0"] * 100003) + "\n")
with open(f"{d}/many-elements.ply", "w") as f:
    f.write("ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nproperty float y\nproperty float z\n")
    f.write("".join(f"element e{i} 0\nproperty float a\n" for i in range(100000)))
    f.write("end_header\n0 0 0\n")
# XYZ with 100k columns; CSV with a header of 100k names.
with open(f"{d}/many-columns.xyz", "w") as f:
    for r in range(3): f.write(" ".join(str(r + c % 7) for c in range(100000)) + "\n")
with open(f"{d}/many-names.csv", "w") as f:
    f.write(",".join(["x", "y", "z"] + [f"c{i}" for i in range(100000)]) + "\n")
    for r in range(3): f.write(",".join(str(r + c % 5) for c in range(100003)) + "\n")
# Numbers that overflow float32.
open(f"{d}/huge.xyz", "w").write("0 0 0\n1e39 0 0\n0 1 0\n")
open(f"{d}/huge.off", "w").write("OFF\n3 0 0\n0 0 0\n1e300 0 0\n0 1 0\n")
# A UTM-like cloud whose first point is the origin: 10,001 distinct points near (5e5, 4e6, 100).
rng = random.Random(5)
with open(f"{d}/utm.xyz", "w") as f:
    f.write("0 0 0\n")
    for i in range(10000):
        f.write("%.3f %.3f %.3f\n" % (500000 + rng.uniform(0, 100), 4000000 + rng.uniform(0, 100), 100 + rng.uniform(0, 1)))
# Splats with a NaN normal and with a zero normal (ascii PLY).
hdr = ("ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n"
       "property float nx\nproperty float ny\nproperty float nz\nproperty float radius\nend_header\n")
rows = ["0 0 0 0 0 1 0.6", "1 0 0 0 0 1 0.6", "0 1 0 0 0 1 0.6", "1 1 0 %s 0.6"]
open(f"{d}/nan-normal.ply", "w").write(hdr + "\n".join(rows[:3] + [rows[3] % "nan 0 1"]) + "\n")
open(f"{d}/zero-normal.ply", "w").write(hdr + "\n".join(rows[:3] + [rows[3] % "0 0 0"]) + "\n")
# A cloud of one distinct point, and 10k identical points.
open(f"{d}/one.xyz", "w").write("1 2 3\n")
open(f"{d}/same.xyz", "w").write("1 2 3\n" * 10000)
open(f"{d}/empty.xyz", "w").write("")
PY

# A 20 MB .splk of 1M empty private chunks (type "XPRV", flags 0, size 0, CRC 0) before END.
python3 - "$IN/splats.splk" "$IN/many-chunks.splk" <<'PY'
import sys
data = open(sys.argv[1], "rb").read()
end = data[-20:]
assert end[:4] == b"END ", end
open(sys.argv[2], "wb").write(data[:-20] + (b"XPRV" + bytes(16)) * 1000000 + end)
PY

# A splat cloud with one far outlier, for the neighbour graph and the normals.
"$BIN/splat-synth" -q torus "$IN/big.xyz" -n 100000 --random --seed 9 --no-color
tail -1 "$IN/big.xyz" | awk '{ $1 = "1e20"; $2 = 0; $3 = 0; print }' >>"$IN/big.xyz"
# A graph file whose GRPH chunk is repeated, and one whose CLIP payload lost its last byte (its
# CRC recomputed, so only the decoder can tell).
"$BIN/build-splat-graph" -q "$IN/splats.splk" "$WORK/graph.splk"
python3 - "$WORK/graph.splk" "$IN" <<'PY'
import struct, sys
def crc32c(b):
    c = 0xFFFFFFFF
    for x in b:
        c ^= x
        for _ in range(8): c = (c >> 1) ^ (0x82F63B78 & -(c & 1))
    return c ^ 0xFFFFFFFF
data = open(sys.argv[1], "rb").read()
chunks, pos = [], 16
while pos < len(data):
    typ, flags, size, crc = struct.unpack_from("<4sIQI", data, pos)
    chunks.append([typ, flags, data[pos + 20:pos + 20 + size]]); pos += 20 + size
def write(name, cs):
    out = bytearray(data[:16])
    for typ, flags, payload in cs:
        out += struct.pack("<4sIQI", typ, flags, len(payload), crc32c(payload) if payload else 0) + payload
    open(f"{sys.argv[2]}/{name}", "wb").write(out)
grph = [c for c in chunks if c[0] == b"GRPH"][0]
i = chunks.index(grph)
write("dup-grph.splk", chunks[:i + 1] + [grph] + chunks[i + 1:])
write("bad-clip.splk", [[t, f, p[:-1] if t == b"CLIP" else p] for t, f, p in chunks])
PY
# LAZ (formats/laz.md): a 4000-point LAZ cut short, its chunk table's count forged, its point
# count inflated (the full set of LAZ cases: tests/e2e/laz.sh).
"$BIN/splat-convert" -q "$IN/torus.splk" "$WORK/torus.laz"
python3 - "$WORK/torus.laz" "$IN" <<'PY'
import struct, sys
d = bytearray(open(sys.argv[1], "rb").read())
off = struct.unpack_from("<I", d, 96)[0]
table = struct.unpack_from("<Q", d, off)[0]
open(f"{sys.argv[2]}/laz-cut.laz", "wb").write(d[:len(d) // 2])
b = bytearray(d); struct.pack_into("<I", b, table + 4, 0x7FFFFFFF); open(f"{sys.argv[2]}/laz-table.laz", "wb").write(b)
b = bytearray(d); struct.pack_into("<I", b, 107, 4000000000); open(f"{sys.argv[2]}/laz-count.laz", "wb").write(b)
PY
# The same as LAS 1.4 format 7 (LASzip layered chunks): a layer size beyond the chunk.
"$BIN/splat-convert" -q --las-format 7 "$IN/torus.splk" "$WORK/torus7.laz"
python3 - "$WORK/torus7.laz" "$IN" <<'PY'
import struct, sys
d = bytearray(open(sys.argv[1], "rb").read())
off = struct.unpack_from("<I", d, 96)[0]
struct.pack_into("<I", d, off + 8 + 36 + 4 + 4, 0x7FFFFFF0)  # the Z layer's size
open(f"{sys.argv[2]}/laz14-layer.laz", "wb").write(d)
PY
cp -a "$IN" "$WORK/in.orig"

# ---- 1. crashes and hangs ------------------------------------------------------------------------
hostile 1 "background" -- "$BIN/splat-view" "$IN/splats.splk" -o "$OUT/x.png" --background nan,0,0
hostile 1 "background" -- "$BIN/splat-view" "$IN/splats.splk" -o "$OUT/x.png" --background 2
hostile 1 "background" -- "$BIN/splat-view" "$IN/splats.splk" -o "$OUT/x.png" --background -1,0,0
hostile 1 "background" -- "$BIN/splat-view" "$IN/splats.splk" -o "$OUT/x.png" --background inf,0,0
for fov in 0 180 nan; do
  hostile 1 "fov" -- "$BIN/splat-view" "$IN/splats.splk" -o "$OUT/x.png" --fov $fov
done
hostile 0 "" -- "$BIN/estimate-normals" -q "$IN/big.xyz" "$OUT/big.splk"
"$BIN/estimate-normals" -q "$IN/big.xyz" "$IN/big-splats.splk"
hostile 0 "" -- "$BIN/build-splat-graph" -q "$IN/big-splats.splk" "$OUT/g.splk"
for f in many-props.ply many-elements.ply many-columns.xyz many-names.csv; do
  "$BIN/splat-info" "$IN/$f" >/dev/null 2>&1
  code=$?
  # Accepted or refused with a clear message: either way fast, small and without a signal.
  [ $code -eq 0 ] || [ $code -eq 2 ] && pass || fail "splat-info $f: exit $code"
  hostile $code "" -- "$BIN/splat-info" "$IN/$f"
done
hostile 2 "many-chunks.splk.*chunks" -- "$BIN/splat-info" "$IN/many-chunks.splk"
hostile 2 "laz-cut.laz: LAZ chunk table offset" -- "$BIN/splat-info" "$IN/laz-cut.laz"
hostile 2 "laz-table.laz: LAZ chunk table lists" -- "$BIN/estimate-normals" "$IN/laz-table.laz" "$OUT/l.splk"
hostile 2 "laz-count.laz: header says 4000000000 points" -- "$BIN/splat-convert" "$IN/laz-count.laz" "$OUT/l.ply"
hostile 2 "laz14-layer.laz: LAZ chunk 0 of 1 .*layers claim" -- "$BIN/splat-info" "$IN/laz14-layer.laz"

# ---- 2. data loss --------------------------------------------------------------------------------
hostile 1 "report|input" -- "$BIN/estimate-normals" "$IN/torus.ply" "$OUT/n.ply" --report "$IN/torus.ply"
hostile 1 "report|input" -- "$BIN/estimate-normals" "$IN/torus.ply" "$OUT/n.ply" --report "$IN/./torus.ply"
cp "$IN/torus.ply" "$WORK/n.ply"; ln -sf "$WORK/n.ply" "$WORK/out-link.ply"
hostile 1 "report|OUT|output" -- "$BIN/estimate-normals" "$IN/torus.ply" "$WORK/n.ply" --report "$WORK/out-link.ply"
cmp -s "$WORK/n.ply" "$IN/torus.ply" && pass || fail "--report through a symlink overwrote OUT"
hostile 1 "input|same" -- "$BIN/estimate-normals" "$IN/torus.ply" "$IN/torus.ply"
hostile 1 "input|same" -- "$BIN/splat-convert" "$IN/torus.ply" "$IN/./torus.ply"
hostile 1 "stats|input" -- "$BIN/splat-view" "$IN/splats.splk" -o "$OUT/x.png" --stats "$IN/splats.splk"
hostile 1 "input|same" -- "$BIN/build-splat-graph" "$IN/splats.splk" "$IN/splats.splk"
hostile 1 "input|same" -- "$BIN/segment-surfaces" "$IN/splats.splk" "$IN/splats.splk"
# The origin comes from the bounds: no point of the UTM cloud is merged as a duplicate.
hostile 0 "" -- "$BIN/estimate-normals" -q "$IN/utm.xyz" "$OUT/utm.splk" --report "$OUT/utm.json"
"$BIN/estimate-normals" -q "$IN/utm.xyz" "$WORK/utm.splk" --report "$WORK/utm.json"
expect_eq "UTM duplicates merged" "$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["duplicates_merged"])' "$WORK/utm.json")" 0
# A FIFO as OUT gets the bytes; a symlink as OUT is followed (the link stays a link).
mkfifo "$WORK/fifo"
timeout 30 cat "$WORK/fifo" >"$WORK/from-fifo" &
hostile 0 "" -- "$BIN/splat-convert" -q "$IN/torus.ply" "$WORK/fifo" --format splk
wait
"$BIN/splat-convert" -q "$IN/torus.ply" "$WORK/direct.splk" --format splk
cmp -s "$WORK/from-fifo" "$WORK/direct.splk" && pass || fail "FIFO reader did not get the output"
[ -p "$WORK/fifo" ] && pass || fail "the FIFO was replaced"
touch "$WORK/target.splk"; ln -sf "$WORK/target.splk" "$WORK/link.splk"
hostile 0 "" -- "$BIN/splat-convert" -q "$IN/torus.ply" "$WORK/link.splk"
"$BIN/splat-convert" -q "$IN/torus.ply" "$WORK/plain.splk"
[ -L "$WORK/link.splk" ] && cmp -s "$WORK/target.splk" "$WORK/plain.splk" && pass ||
  fail "a symlink OUT was not followed"
if [ "$(id -u)" = 0 ]; then  # a character device node as OUT (our own, never /dev/null itself)
  mknod "$WORK/null" c 1 3
  hostile 0 "" -- "$BIN/splat-convert" -q "$IN/torus.ply" "$WORK/null" --format splk
  [ -c "$WORK/null" ] && pass || fail "a character device OUT was replaced by a file"
fi
cp "$WORK/direct.splk" "$WORK/protected.splk"; chmod 0444 "$WORK/protected.splk"
hostile 4 "protected|permission" -- "$BIN/splat-convert" -q "$IN/kitten.xyz" "$WORK/protected.splk"
cmp -s "$WORK/protected.splk" "$WORK/direct.splk" && pass || fail "a write-protected OUT was replaced"

# ---- 3. leftovers --------------------------------------------------------------------------------
hostile 0 "" STDIN="$S/cad-pcl.pcd" -- "$BIN/splat-info" -

# ---- 4. exit codes and examples ------------------------------------------------------------------
hostile 0 "" STDIN="$IN/kitten.xyz" -- "$BIN/splat-convert" --columns x,y,z,_,_,_ - "$OUT/k.splk"
hostile 2 "huge.xyz.*(range|finite|overflow)" -- "$BIN/splat-convert" "$IN/huge.xyz" "$OUT/h.ply"
hostile 2 "huge.off.*(range|finite|overflow)" -- "$BIN/splat-convert" "$IN/huge.off" "$OUT/h.splk"
hostile 2 "empty" -- "$BIN/splat-info" /dev/null
hostile 2 "empty" -- "$BIN/splat-info" -
printf 'ply\nformat ascii 1.0\nelement vertex 1\nproperty float x\nend_header\n' >"$WORK/bad.ply"
hostile 2 "bad.ply" -- "$BIN/splat-info" --json "$IN/torus.ply" "$WORK/bad.ply" "$IN/torus.ply"
python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); assert len(d) >= 2, d' "$WORK/stdout" 2>/dev/null &&
  pass || fail "splat-info --json good bad good does not describe the good files"

# ---- 5. pipeline rules: what one tool writes, the next one reads ---------------------------------
hostile 2 "one.xyz" -- "$BIN/estimate-normals" "$IN/one.xyz" "$OUT/one.splk"
hostile 2 "same.xyz" -- "$BIN/estimate-normals" "$IN/same.xyz" "$OUT/same.splk"
"$BIN/estimate-normals" -q "$IN/big.xyz" "$WORK/outlier.splk"
# (an explicit camera: the default one frames the outlier too, 1e20 away, beyond float's reach,
# which is said as such: bad input, naming the file)
hostile 0 "" -- "$BIN/splat-view" -q "$WORK/outlier.splk" -o "$OUT/o.png" --width 64 --height 48 \
  --eye 3,3,3 --target 0,0,0
hostile 2 "outlier.splk.*bounding sphere.*--eye" -- "$BIN/splat-view" "$WORK/outlier.splk" \
  -o "$OUT/o2.png" --width 64 --height 48
hostile 2 "dup-grph.splk.*GRPH" -- "$BIN/segment-surfaces" "$IN/dup-grph.splk" "$OUT/s.splk"
hostile 2 "bad-clip.splk.*CLIP" -- "$BIN/segment-surfaces" "$IN/bad-clip.splk" "$OUT/s.splk"
for f in nan-normal.ply zero-normal.ply; do
  hostile 2 "$f.*normal" -- "$BIN/build-splat-graph" "$IN/$f" "$OUT/g.splk"
  hostile 2 "$f.*normal" -- "$BIN/splat-view" "$IN/$f" -o "$OUT/x.png"
done

# .spt: a header claiming 2^40 entries (rejected before any allocation), build-spt's options
# and its input named as its output.
spt=$SRC/tests/fuzz/corpus/spt/sphere30.spt
cp "$spt" "$IN/huge.spt"
printf '\x00\x00\x00\x00\x00\x01' | dd of="$IN/huge.spt" bs=1 seek=24 conv=notrunc status=none
hostile 2 "huge.spt: byte 24: .*truncated" -- "$BIN/splat-info" "$IN/huge.spt"
hostile 2 "huge.spt: byte 24" -- "$BIN/splat-view" "$IN/huge.spt" -o "$OUT/x.png"
hostile 1 "epsilon" -- "$BIN/build-spt" "$IN/splats.splk" "$OUT/x.spt" --epsilon 0
hostile 1 "epsilon" -- "$BIN/build-spt" "$IN/splats.splk" "$OUT/x.spt" --epsilon nan
hostile 1 "color-weight" -- "$BIN/build-spt" "$IN/splats.splk" "$OUT/x.spt" --color-weight -1
hostile 1 "\\.spt" -- "$BIN/build-spt" "$IN/splats.splk" "$OUT/x.ply"
hostile 1 "input|same|OUT" -- "$BIN/build-spt" "$IN/huge.spt" "$IN/huge.spt"
hostile 2 "estimate-normals" -- "$BIN/build-spt" "$IN/kitten.xyz" "$OUT/x.spt"
hostile 0 "" -- "$BIN/build-spt" -q "$IN/splats.splk" "$OUT/x.spt"
# ---- 6. heightmaps (build-ham, splat-view --terrain) ----------------------------------------------
# A TIFF header claiming 10^6 x 10^6 uncompressed float samples in 200 bytes; an empty .hgt;
# RAW rows of 2^31 texels from stdin; a TIFF whose first directory lies past its end.
python3 - "$IN" <<'PY'
import struct, sys
d = sys.argv[1]
e = [(256, 4, 1000000), (257, 4, 1000000), (258, 3, 32), (259, 3, 1), (262, 3, 1), (273, 4, 200),
     (277, 3, 1), (278, 4, 1), (279, 4, 4000000), (339, 3, 3)]
ifd = struct.pack("<H", len(e)) + b"".join(
    struct.pack("<HHII", t, y, 1, v) if y == 4 else struct.pack("<HHIHH", t, y, 1, v, 0) for t, y, v in e) + b"\0" * 4
open(d + "/huge.tif", "wb").write(b"II*\0" + struct.pack("<I", 8) + ifd + b"\0" * 64)
open(d + "/far-ifd.tif", "wb").write(b"II*\0" + struct.pack("<I", 1 << 30) + b"\0" * 64)
PY
: >"$IN/N10E010.hgt"
hostile 2 "huge.tif.*(truncated|cannot hold|strip)" -- "$BIN/build-ham" "$IN/huge.tif" "$OUT/h.exr"
hostile 2 "far-ifd.tif" -- "$BIN/build-ham" "$IN/far-ifd.tif" "$OUT/h.exr"
hostile 2 "N10E010.hgt.*SRTM" -- "$BIN/build-ham" "$IN/N10E010.hgt" "$OUT/h.exr"
hostile 3 "2147483648 texels" -- "$BIN/build-ham" - "$OUT/h.exr" --raw 2147483648,2147483648,float32
hostile 2 "huge.tif" -- "$BIN/splat-view" --terrain "$IN/huge.tif" --ham "$IN/huge.tif" -o "$OUT/x.png"

finish

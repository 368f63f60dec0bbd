# Readers against hostile or careless input, through the real binaries: headers of 100k
# properties, elements or columns answered at once (a bounded wall clock: headers are parsed in
# linear time and refused beyond 16384 attributes), a .splk of a million empty chunks in bounded
# memory, numbers beyond float range, empty input, text on stdin, and a UTM scan that starts with
# a stray (0, 0, 0).
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
W=$WORK

python3 - "$W" <<'PY'
import struct, sys, random
w = sys.argv[1]
n = 100000
xyz = "property float x\nproperty float y\nproperty float z\n"
def ply_props(path, k):
    h = "ply\nformat binary_little_endian 1.0\nelement vertex 1\n" + xyz
    h += "".join(f"property uchar p{i}\n" for i in range(k)) + "end_header\n"
    open(path, "wb").write(h.encode() + struct.pack("<3f", 1, 2, 3) + bytes(k))
ply_props(f"{w}/props.ply", n)
ply_props(f"{w}/props16k.ply", 16384 - 3)
h = "ply\nformat ascii 1.0\nelement vertex 1\n" + xyz
h += "".join(f"element e{i} 0\n" for i in range(n)) + "end_header\n1 2 3\n"
open(f"{w}/elements.ply", "w").write(h)
open(f"{w}/columns.xyz", "w").write(" ".join(str(i % 10) for i in range(n)) + "\n")
names = ["x", "y", "z"] + [f"c{i}" for i in range(n)]
open(f"{w}/names.csv", "w").write(",".join(names) + "\n" + ",".join(["1"] * len(names)) + "\n")

# .splk: one point, then a million zero-byte private chunks, then END (20 MB).
def chunk(t, flags, payload):
    return t + struct.pack("<IQI", flags, len(payload), crc32c(payload)) + payload
def crc32c(b):
    crc = 0xFFFFFFFF
    for byte in b:
        crc ^= byte
        for _ in range(8):
            crc = (crc >> 1) ^ (0x82F63B78 if crc & 1 else 0)
    return crc ^ 0xFFFFFFFF
splt = struct.pack("<Q3dI3dI", 1, 0, 0, 0, 0, 0, 0, 0, 1)
splt += struct.pack("<H", 8) + b"position" + bytes([0, 9, 3]) + struct.pack("<3f", 1, 2, 3)
head = b"\x89SPLK\r\n\x1a" + struct.pack("<HHI", 1, 0, 0) + chunk(b"SPLT", 3, splt)
empty = chunk(b"xprv", 0, b"")
with open(f"{w}/chunks.splk", "wb") as f:
    f.write(head + empty * 1000000 + chunk(b"END ", 1, b""))
with open(f"{w}/chunks1k.splk", "wb") as f:
    f.write(head + empty * 1000 + chunk(b"END ", 1, b""))

# A UTM survey on a jittered 10 cm grid after a stray (0, 0, 0): 10,001 points.
rng = random.Random(5)
with open(f"{w}/utm.xyz", "w") as f:
    f.write("0 0 0\n")
    for i in range(100):
        for j in range(100):
            f.write("%.3f %.3f %.3f\n" % (512345.678 + 0.1 * i + rng.uniform(-0.02, 0.02),
                                          5412345.678 + 0.1 * j + rng.uniform(-0.02, 0.02),
                                          231.5 + rng.uniform(-0.02, 0.02)))
PY

# Headers: a clear answer at once (the old quadratic parse took 15-40 s for these).
for f in props.ply elements.ply columns.xyz names.csv; do
  expect_exit 2 timeout 5 "$BIN/splat-info" "$W/$f"
  expect_stderr "^splat-info: .*$f: .*more than (the )?16384"
done
expect_exit 0 timeout 5 "$BIN/splat-info" "$W/props16k.ply"

# A million empty chunks: refused, in bounded memory (it took 1.5 GB); a thousand are carried.
expect_exit 2 /usr/bin/time -f '%M' -o "$W/rss" "$BIN/splat-info" "$W/chunks.splk"
grep -q "more than 65536 chunks" "$W/stderr" && pass || fail "chunks: $(cat "$W/stderr")"
rss=$(tail -1 "$W/rss")
rss_limit=300000  # KiB; sanitizer builds (ASan's shadow memory) get 3x
grep -q __asan_init "$BIN/splat-info" 2>/dev/null && rss_limit=900000
[ "$rss" -le "$rss_limit" ] && pass || fail "chunks.splk took $rss KiB (limit $rss_limit KiB)"
expect_exit 0 "$BIN/splat-info" --json "$W/chunks1k.splk"
expect_eq "chunks listed" "$(grep -c '"type": "xprv"' "$W/stdout")" 1000

# Numbers beyond float range: exit 2 naming the file, the line and the value.
printf '1 2 3\n1e39 0 0\n' > "$W/big.xyz"
expect_exit 2 "$BIN/splat-convert" -q "$W/big.xyz" "$W/big.ply"
expect_stderr "big.xyz: line 2: coordinate '1e39' .* beyond float range"
[ ! -e "$W/big.ply" ] && pass || fail "big.ply written"
printf 'OFF\n2 0 0\n0 0 0\n1 1e300 1\n' > "$W/big.off"
expect_exit 2 "$BIN/splat-convert" -q "$W/big.off" "$W/big.splk"
expect_stderr "big.off: line 4: vertex 1: coordinate '1e300' is beyond float range"
printf 'ply\nformat ascii 1.0\nelement vertex 1\nproperty double x\nproperty double y\nproperty double z\nend_header\n1 -1e300 3\n' > "$W/big.ply"
expect_exit 2 "$BIN/splat-info" "$W/big.ply"
expect_stderr "big.ply: line 8: .*coordinate -1e\+300 is beyond float range"
rm -f "$W/big.ply"

# Empty input: exit 2, "file is empty", whatever the name or the source.
: > "$W/empty.xyz"
for src in /dev/null "$W/empty.xyz"; do
  expect_exit 2 "$BIN/splat-info" "$src"
  expect_stderr "file is empty"
done
expect_exit 2 "$BIN/splat-convert" - "$W/e.splk" < /dev/null
expect_stderr "<stdin>: file is empty"

# Text on stdin: recognised by content, and --columns says text.
printf '1 2 3 0 10 20 30\n4 5 6 0 40 50 60\n' > "$W/scan.xyz"
expect_exit 0 "$BIN/splat-convert" -q --columns x,y,z,_,r,g,b - "$W/scan.splk" < "$W/scan.xyz"
expect_exit 0 "$BIN/splat-info" --json "$W/scan.splk"
grep -q '"name": "red"' "$W/stdout" && pass || fail "colours lost on stdin"
expect_exit 0 "$BIN/splat-info" - < "$W/scan.xyz"
grep -q "Points: *2" "$W/stdout" && pass || fail "stdin xyz: $(head -3 "$W/stdout")"
printf 'OFF\n3 1 0\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n' | "$BIN/splat-info" - > "$W/stdout" 2>"$W/stderr"
grep -q "Faces: *1" "$W/stdout" && pass || fail "stdin off: $(cat "$W/stderr")"
printf 'hello\n' | "$BIN/splat-info" - > /dev/null 2>"$W/stderr"
grep -q "unknown file format" "$W/stderr" && pass || fail "prose on stdin: $(cat "$W/stderr")"

# A stray (0, 0, 0) before a UTM scan: the origin follows the scan, no point is a duplicate of
# another, and every coordinate comes back to the millimetre.
expect_exit 0 "$BIN/estimate-normals" -q "$W/utm.xyz" "$W/utm.splk" --report "$W/utm.json"
expect_eq "duplicates merged" "$(python3 -c 'import json,sys; print(json.load(open(sys.argv[1]))["duplicates_merged"])' "$W/utm.json")" 0
expect_exit 0 "$BIN/splat-convert" -q "$W/utm.xyz" "$W/utm-copy.xyz"
python3 - "$W/utm.xyz" "$W/utm-copy.xyz" <<'PY' && pass || fail "utm copy differs"
import sys
a = [list(map(float, l.split())) for l in open(sys.argv[1]) if l.strip()]
b = [list(map(float, l.split()[:3])) for l in open(sys.argv[2]) if l.strip() and l[0] != "#"]
assert len(a) == len(b) == 10001, (len(a), len(b))
worst = max(abs(p - q) for u, v in zip(a, b) for p, q in zip(u, v))
assert worst < 1e-3, worst
PY

finish

# build-ham and splat-view --terrain through the real binaries: the real SRTM sample with its
# voids and georeferencing; the same map as int16/int32/float32 TIFF, 16-bit PNG, EXR, SRTM .hgt
# and RAW (from a file and from stdin) giving the same tiles; the same bytes for 1 and 2 threads;
# --ham-full as a tiled EXR; bad options and bad files with their exit codes; terrain renders
# (plain and wireframe) byte-identical from run to run, and their --stats.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
S=$SRC/data-samples
DEM=$S/rainier-srtm.tif

json() {  # json FILE EXPR: prints the Python expression EXPR over the JSON document d
  python3 -c 'import json,sys; d=json.load(open(sys.argv[1])); print(eval(sys.argv[2]))' "$1" "$2"
}
same_pixels() {  # same_pixels A B [CHANNELS [TOLERANCE]]: the EXR images hold the same values
  if [ -n "${3:-}" ]; then
    oiiotool "$1" --ch "$3" -o "$WORK/a.exr" && oiiotool "$2" --ch "$3" -o "$WORK/b.exr" &&
      idiff -a -fail "${4:-0}" -warn "${4:-0}" "$WORK/a.exr" "$WORK/b.exr" >/dev/null
  else
    idiff -a -fail 0 -warn 0 "$1" "$2" >/dev/null
  fi
}

# The real sample: voids counted, georeferencing and no-data kept, tiles and header.
expect_exit 0 "$BIN/build-ham" "$DEM" "$WORK/t.exr" -q --report "$WORK/t.json"
expect_eq "voids" "$(json "$WORK/t.json" 'd["voids"]')" 2551
expect_eq "tiles" "$(json "$WORK/t.json" '(d["tiles_x"], d["tiles_y"])')" "(5, 5)"
expect_eq "heights" "$(json "$WORK/t.json" '(d["h_min"], d["h_max"])')" "(806.0, 4371.0)"
expect_eq "crs" "$(json "$WORK/t.json" 'd["header"]["georef"]["crs"]')" "EPSG:4326"
expect_eq "nodata" "$(json "$WORK/t.json" 'd["header"]["nodata"]')" "-32768.0"
iinfo -v "$WORK/t.exr" >"$WORK/iinfo" 2>&1
for c in "ham_max (float)" "h_max (float)" "x (uint)" "y (uint)" "voids (uint)" \
  "splatkit:tile_size: 64" "splatkit:width: 257" "splatkit:height: 257"; do
  grep -qF "$c" "$WORK/iinfo" && pass || fail "tile EXR lacks '$c'"
done

# A full disk under --ham-full: exit 4 naming the target (not the temporary file), nothing left.
mkdir -p "$WORK/tiny"
if mount -t tmpfs -o size=64k tmpfs "$WORK/tiny" 2>/dev/null; then
  expect_exit 4 "$BIN/build-ham" "$DEM" "$WORK/t5.exr" -q --ham-full "$WORK/tiny/full.exr"
  expect_stderr "tiny/full.exr: .*\"$WORK/tiny/full.exr\""
  grep -q "full.exr.tmp" "$WORK/stderr" && fail "the message names the temporary file" || pass
  [ -z "$(ls -A "$WORK/tiny")" ] && pass || fail "a full disk left files: $(ls "$WORK/tiny")"
  umount "$WORK/tiny"
fi

# splat-info describes the heightmap and the tiles.
expect_exit 0 "$BIN/splat-info" "$DEM" "$WORK/t.exr"
for line in "Format: heightmap \(tiff, int16\)" "Map: 257 x 257 texels" "No-data: -32768" \
  "Georeferencing: EPSG:4326" "Format: ham \(build-ham tiles, EXR\)" "Tiles: 5 x 5 of 64 texels" \
  "Heights: 806 .. 4371" "Voids filled: 2551"; do
  grep -Eq "^$line" "$WORK/stdout" && pass || fail "splat-info lacks '$line'"
done
expect_exit 0 "$BIN/splat-info" --json "$WORK/t.exr"
expect_eq "splat-info --json tiles" "$(json "$WORK/stdout" '(d["format"], d["tiles"], d["voids"])')" \
  "('ham', [5, 5], 2551)"

# Same bytes: 1 and 2 threads, a second run; a tile size of 1 and a partial last tile.
expect_exit 0 "$BIN/build-ham" "$DEM" "$WORK/t1.exr" -q --threads 1
expect_exit 0 "$BIN/build-ham" "$DEM" "$WORK/t2.exr" -q --threads 2
cmp -s "$WORK/t1.exr" "$WORK/t2.exr" && pass || fail "1 and 2 threads give different tiles"
cmp -s "$WORK/t1.exr" "$WORK/t.exr" && pass || fail "two runs give different tiles"
expect_exit 0 "$BIN/build-ham" "$DEM" "$WORK/t100.exr" -q --tile 100 --report "$WORK/t100.json"
expect_eq "tiles of 100" "$(json "$WORK/t100.json" '(d["tiles_x"], d["tiles_y"])')" "(3, 3)"

# --ham-full: a tiled float EXR of the whole map.
expect_exit 0 "$BIN/build-ham" "$DEM" "$WORK/t3.exr" -q --ham-full "$WORK/full.exr"
iinfo -v "$WORK/full.exr" >"$WORK/iinfo" 2>&1
grep -q "257 x  257, 1 channel, float" "$WORK/iinfo" && grep -q "tile size: 64 x 64" "$WORK/iinfo" &&
  pass || fail "--ham-full: $(head -3 "$WORK/iinfo")"
max_full=$(oiiotool --stats "$WORK/full.exr" 2>/dev/null | awk '/Stats Max/ {print $3}')
max_tiles=$(json "$WORK/t.json" 'd["ham_max"]')
awk -v a="$max_full" -v b="$max_tiles" 'BEGIN {exit !(a > 0 && (a - b) ^ 2 < 1e-6 * b * b)}' &&
  pass || fail "--ham-full max $max_full against the tiles' $max_tiles"
# A new file's mode follows the umask (not the temporary file's 0600).
[ "$(stat -c %a "$WORK/full.exr")" = "$(printf '%o' $(( 0666 & ~$(umask) )))" ] &&
  pass || fail "--ham-full mode $(stat -c %a "$WORK/full.exr")"
# Never the report, and not put in place when the report fails (a full disk).
expect_exit 1 "$BIN/build-ham" "$DEM" "$WORK/t4.exr" -q --ham-full "$WORK/f4.exr" \
  --report "$WORK/./f4.exr"
expect_stderr "--ham-full must not be the report"
if [ -w /dev/full ]; then
  expect_exit 4 "$BIN/build-ham" "$DEM" "$WORK/t4.exr" -q --ham-full "$WORK/f4.exr" --report /dev/full
  [ ! -e "$WORK/t4.exr" ] && [ ! -e "$WORK/f4.exr" ] && pass || fail "outputs in place after a failed report"
fi

# The same map in other files: the same tiles (the header aside).
python3 - "$DEM" "$WORK" <<'PY'
import importlib.util, struct, sys, zlib
spec = importlib.util.spec_from_file_location("m", sys.argv[1].rsplit("/", 2)[0] + "/scripts/make-dem-sample.py")
m = importlib.util.module_from_spec(spec); spec.loader.exec_module(m)
data = open(sys.argv[1], "rb").read()
order, tags = m.read_tags(data)
w, h, at = m.sample_reader(data, order, tags)
px = [at(x, y) for y in range(h) for x in range(w)]
d = sys.argv[2]
open(d + "/le.raw", "wb").write(struct.pack("<%dh" % len(px), *px))
open(d + "/N46W122.hgt", "wb").write(struct.pack(">%dh" % len(px), *px))
def tiff(name, fmt, bits, sample_format, values, nodata=None, tiled=False):
    body = struct.pack("<%d%s" % (len(values), fmt), *values)
    entries = [(256, 3, w), (257, 3, h), (258, 3, bits), (259, 3, 1), (262, 3, 1), (277, 3, 1),
               (284, 3, 1), (339, 3, sample_format)]
    blob = bytearray(b"II*\0\0\0\0\0")
    if tiled:  # 128 x 128 tiles, padded
        t = 128; across = (w + t - 1) // t; down = (h + t - 1) // t; size = bits // 8
        offsets = []
        for ty in range(down):
            for tx in range(across):
                offsets.append(len(blob))
                for y in range(ty * t, ty * t + t):
                    for x in range(tx * t, tx * t + t):
                        v = values[y * w + x] if x < w and y < h else values[0]
                        blob += struct.pack("<" + fmt, v)
        entries += [(322, 3, t), (323, 3, t)]
        off_pos = len(blob); blob += struct.pack("<%dI" % len(offsets), *offsets)
        cnt_pos = len(blob); blob += struct.pack("<%dI" % len(offsets), *[t * t * size] * len(offsets))
        entries += [(324, 4, (len(offsets), off_pos)), (325, 4, (len(offsets), cnt_pos))]
    else:
        entries += [(273, 4, len(blob)), (278, 3, h), (279, 4, len(body))]
        blob += body
    if nodata is not None:
        s = nodata.encode() + b"\0"
        nd_pos = len(blob); blob += s
        entries.append((42113, 2, (len(s), nd_pos)))
    entries.sort()
    if len(blob) % 2: blob += b"\0"
    ifd = len(blob)
    blob += struct.pack("<H", len(entries))
    for tag, typ, v in entries:
        if isinstance(v, tuple):
            blob += struct.pack("<HHII", tag, typ, v[0], v[1])
        elif typ == 3:
            blob += struct.pack("<HHIHH", tag, typ, 1, v, 0)
        else:
            blob += struct.pack("<HHII", tag, typ, 1, v)
    blob += b"\0\0\0\0"
    blob[4:8] = struct.pack("<I", ifd)
    open(d + "/" + name, "wb").write(bytes(blob))
nan = float("nan")
fl = [nan if v == -32768 else float(v) for v in px]
tiff("f32.tif", "f", 32, 3, fl)
tiff("f32-tiled.tif", "f", 32, 3, fl, tiled=True)
tiff("i32.tif", "i", 32, 2, px, nodata="-32768")
tiff("i16-tiled.tif", "h", 16, 2, px, nodata="-32768", tiled=True)
# 16-bit PNG: heights + 1000, voids 0 (--nodata 0)
rows = b"".join(b"\0" + struct.pack(">%dH" % w, *[0 if v == -32768 else v + 1000 for v in px[y * w:(y + 1) * w]]) for y in range(h))
def chunk(t, b): return struct.pack(">I", len(b)) + t + b + struct.pack(">I", zlib.crc32(t + b) & 0xffffffff)
open(d + "/u16.png", "wb").write(b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 16, 0, 0, 0, 0)) + chunk(b"IDAT", zlib.compress(rows)) + chunk(b"IEND", b""))
PY
oiiotool "$WORK/f32.tif" -o "$WORK/f32.exr" 2>/dev/null
# A compressed TIFF goes through OpenImageIO (the uncompressed ones are read directly).
oiiotool "$WORK/f32.tif" --compression zip -o "$WORK/f32-zip.tif" 2>/dev/null
for f in f32.tif f32-tiled.tif i32.tif i16-tiled.tif f32-zip.tif f32.exr N46W122.hgt; do
  expect_exit 0 "$BIN/build-ham" "$WORK/$f" "$WORK/$f.tiles.exr" -q
  same_pixels "$WORK/t.exr" "$WORK/$f.tiles.exr" && pass || fail "$f: tiles differ from the TIFF's"
done
expect_exit 0 "$BIN/build-ham" "$WORK/le.raw" "$WORK/raw.exr" -q --raw 257,257,int16 --nodata -32768
same_pixels "$WORK/t.exr" "$WORK/raw.exr" && pass || fail "RAW: tiles differ from the TIFF's"
expect_exit 0 bash -c "cat '$WORK/le.raw' | '$BIN/build-ham' - '$WORK/stdin.exr' -q --raw 257,257,int16,little --nodata -32768"
same_pixels "$WORK/t.exr" "$WORK/stdin.exr" && pass || fail "RAW on stdin: tiles differ"
# 16-bit PNG: heights 1000 m up, voids 0: the same texels, the same HAM but for the rounding of
# filled heights (float32 near 1000 m more), h_max 1000 more.
expect_exit 0 "$BIN/build-ham" "$WORK/u16.png" "$WORK/png.exr" -q --nodata 0
same_pixels "$WORK/t.exr" "$WORK/png.exr" x,y,voids && pass || fail "16-bit PNG: texels differ"
same_pixels "$WORK/t.exr" "$WORK/png.exr" ham_max 0.05 && pass || fail "16-bit PNG: HAM differs"
expect_exit 0 "$BIN/build-ham" "$DEM" "$WORK/z2.exr" -q --z-scale 2 --report "$WORK/z2.json"
expect_eq "z-scale 2" "$(json "$WORK/z2.json" 'd["h_max"]')" "8742.0"
expect_exit 0 "$BIN/build-ham" "$WORK/N46W122.hgt" "$WORK/hgt.exr" -q --report "$WORK/hgt.json"
expect_eq "hgt georef" "$(json "$WORK/hgt.json" 'd["header"]["georef"]["origin"]')" "[-122.0, 47.0]"

# Bad options and files.
expect_exit 1 "$BIN/build-ham" "$DEM" "$WORK/x.png" -q
expect_stderr "OUT must end in .exr"
expect_exit 1 "$BIN/build-ham" "$DEM" "$WORK/x.exr" --tile 0
expect_exit 1 "$BIN/build-ham" "$WORK/le.raw" "$WORK/x.exr" --raw 257,257,int12
expect_stderr "TYPE must be"
expect_exit 1 "$BIN/build-ham" "$DEM" "$DEM.exr" --ham-full "$DEM"
expect_exit 1 "$BIN/build-ham" - "$WORK/x.exr"
expect_stderr "only with --raw"
expect_exit 2 "$BIN/build-ham" "$WORK/le.raw" "$WORK/x.exr" --raw 256,257,int16
expect_stderr "le.raw: 132098 bytes; --raw 256,257,int16 needs 131584"
head -c 1000 "$WORK/N46W122.hgt" >"$WORK/N00E000.hgt"
expect_exit 2 "$BIN/build-ham" "$WORK/N00E000.hgt" "$WORK/x.exr"
expect_stderr "1000 bytes: an SRTM .hgt file holds"
expect_exit 2 bash -c "head -c 5000 '$WORK/le.raw' | '$BIN/build-ham' - '$WORK/x.exr' --raw 257,257,int16"
expect_stderr "<stdin>: ends at row 9 of 257"
# A scale that overflows the slopes, and a map with no valid sample: refused, nothing written.
expect_exit 1 "$BIN/build-ham" "$DEM" "$WORK/x.exr" --z-scale 1e30
expect_stderr "too large for float arithmetic"
expect_exit 1 "$BIN/build-ham" "$DEM" "$WORK/x.exr" --z-scale 1e-50
expect_stderr "z-scale must be > 0 and within the float range"
head -c 2000 /dev/zero >"$WORK/void.raw"
expect_exit 2 "$BIN/build-ham" "$WORK/void.raw" "$WORK/x.exr" --raw 40,50,uint8 --nodata 0
expect_stderr "void.raw: every sample is a void"
[ ! -e "$WORK/x.exr" ] && pass || fail "a refused map left OUT behind"
# The same as SRTM voids (int16 -32768, a map taller than the void filler's look-ahead, from a
# file and from stdin, with --ham-full and a report): refused, nothing of any output left.
python3 -c 'import struct, sys; open(sys.argv[1], "wb").write(struct.pack("<%dh" % (300 * 300), *([-32768] * (300 * 300))))' \
  "$WORK/void16.raw"
mkdir -p "$WORK/voidout"
expect_exit 2 "$BIN/build-ham" "$WORK/void16.raw" "$WORK/voidout/x.exr" --raw 300,300,int16 \
  --nodata -32768 --ham-full "$WORK/voidout/full.exr" --report "$WORK/voidout/r.json"
expect_stderr "^build-ham: .*void16.raw: every sample is a void"
expect_exit 2 bash -c "'$BIN/build-ham' - '$WORK/voidout/x.exr' --raw 300,300,int16 --nodata -32768 <'$WORK/void16.raw'"
expect_stderr "^build-ham: <stdin>: every sample is a void"
[ -z "$(ls -A "$WORK/voidout")" ] && pass || fail "an all-void map left: $(ls "$WORK/voidout")"
# Heights near the float range overflow their slopes: the file's fault (exit 2), not an option's.
python3 -c 'import struct, sys; open(sys.argv[1], "wb").write(struct.pack("<64f", *([3e38, -3e38] * 32)))' \
  "$WORK/huge.raw"
expect_exit 2 "$BIN/build-ham" "$WORK/huge.raw" "$WORK/x.exr" --raw 8,8,float32
expect_stderr "huge.raw: heights up to 3e\+38: their slopes are too large"
head -c 30000 "$DEM" >"$WORK/cut.tif"
expect_exit 2 "$BIN/build-ham" "$WORK/cut.tif" "$WORK/x.exr"
expect_stderr "build-ham: .*cut.tif: "
[ ! -e "$WORK/x.exr" ] && pass || fail "a failed run left OUT behind"
ls "$WORK"/*.tmp.* >/dev/null 2>&1 && fail "temporary files left" || pass

# splat-view --terrain: plain and wireframe, same bytes twice, stats.
view=(--width 320 --height 200 --view 200,30)
expect_exit 0 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/t.exr" -o "$WORK/v.png" "${view[@]}" \
  -q --stats "$WORK/v.json"
expect_exit 0 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/t.exr" -o "$WORK/v2.png" "${view[@]}" -q
cmp -s "$WORK/v.png" "$WORK/v2.png" && pass || fail "two terrain renders differ"
expect_exit 0 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/t.exr" -o "$WORK/w.png" "${view[@]}" \
  -q --wireframe --stats "$WORK/w.json"
cmp -s "$WORK/v.png" "$WORK/w.png" && fail "the wireframe changed nothing" || pass
# 257 texels in tiles of 64: 4 x 4 tiles with area (the fifth column and row are the shared
# border texel only).
expect_eq "triangles" "$(json "$WORK/v.json" '(d["tiles"], d["triangles"] > 0, d["triangles_at_64"])')" \
  "(16, True, 131072)"
expect_eq "histogram" "$(json "$WORK/v.json" 'sum(d["factor_histogram"].values()) == 5 * d["visible_tiles"]')" "True"
expect_eq "same triangles" "$(json "$WORK/w.json" 'd["triangles"]')" "$(json "$WORK/v.json" 'd["triangles"]')"
# A tiny --tess-error: every tile at full resolution, one texel per triangle edge (2 · 256²).
expect_exit 0 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/t.exr" -o "$WORK/full.png" "${view[@]}" \
  -q --tess-error 0.001 --stats "$WORK/full.json"
expect_eq "full resolution" "$(json "$WORK/full.json" '(d["triangles"], d["factor_histogram"])')" \
  "(131072, {'64': 80})"
expect_exit 0 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/t.exr" -o "$WORK/away.png" \
  --width 64 --height 48 --eye 0,1e6,1e4 --target 0,2e6,1e4 -q --stats "$WORK/away.json"
expect_eq "looking away" "$(json "$WORK/away.json" '(d["visible_tiles"], d["triangles"])')" "(0, 0)"
expect_stderr "^splat-view: warning: .*away.png: the frame draws no terrain \(0 triangles\).*EPSG:4326: x = longitude"
[ -s "$WORK/away.png" ] && pass || fail "an empty frame is still an image"
# --eye/--target in the DEM's own lon/lat (and heights): south of the centre, looking at it.
read -r eye target <<<"$(json "$WORK/t.json" '(lambda g: "%.6f,%.6f,6000 %.6f,%.6f,2000" % (
  g["tiepoint"][3] + 128 * g["pixel_scale"][0], g["tiepoint"][4] - 200 * g["pixel_scale"][1],
  g["tiepoint"][3] + 128 * g["pixel_scale"][0], g["tiepoint"][4] - 128 * g["pixel_scale"][1]))(d["header"]["georef"])')"
expect_exit 0 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/t.exr" -o "$WORK/lonlat.png" \
  --width 64 --height 48 --eye "$eye" --target "$target" -q --stats "$WORK/lonlat.json"
expect_eq "a lon/lat camera draws" "$(json "$WORK/lonlat.json" 'd["triangles"] > 1000')" "True"
expect_eq "the frame of the options" "$(json "$WORK/lonlat.json" 'd["camera"]["options_frame"][:9]')" "EPSG:4326"
grep -q warning "$WORK/stderr" && fail "a frame that draws warned: $(cat "$WORK/stderr")" || pass
expect_exit 1 "$BIN/splat-view" --terrain "$DEM" -o "$WORK/x.png"
expect_stderr "needs --ham"
# Options at their extremes name themselves (--fov was blamed on --view's distance).
for v in 0 -1 180 1e300 nan inf; do
  expect_exit 1 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/t.exr" -o "$WORK/x.png" --fov "$v"
  expect_stderr "^splat-view: --fov must be in \(0, 180\) degrees"
done
expect_exit 1 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/t.exr" -o "$WORK/x.png" --eye 1e300,0,0
expect_stderr "^splat-view: --eye and --target must lie within float range"
expect_exit 1 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/t.exr" -o "$WORK/x.png" \
  --eye -121.7,46.8,3000 --target -121.7,46.8,3000
expect_stderr "^splat-view: --eye and --target must differ"
[ ! -e "$WORK/x.png" ] && pass || fail "a refused terrain view wrote OUT"
expect_exit 1 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/t.exr" -o "$WORK/k-%04d.png"
expect_stderr "k-%04d.png' has a frame number field"
ls "$WORK" | grep -q '^k-' && fail "a literal k-%04d.png was written" || pass
expect_exit 1 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/t.exr" -o "$WORK/x.tif"
expect_stderr "x.tif: images are written as .png or .exr, not .tif"
expect_exit 2 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/t100.exr.bad" -o "$WORK/x.png"
expect_exit 2 "$BIN/splat-view" --terrain "$WORK/N00E000.hgt" --ham "$WORK/t.exr" -o "$WORK/x.png"
expect_exit 2 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/full.exr" -o "$WORK/x.png"
expect_stderr "not a build-ham tile file"
expect_exit 1 "$BIN/splat-view" -o "$WORK/x.png"
expect_stderr "input is required"
# Tiles of another map of the same size: refused, naming a tile.
expect_exit 0 "$BIN/splat-view" --terrain "$WORK/le.raw" --raw 257,257,int16 --ham "$WORK/raw.exr" \
  -o "$WORK/raw.png" --width 64 --height 48 -q
python3 -c 'import sys; b = bytearray(open(sys.argv[1], "rb").read()); o = 2 * (257 * 100 + 100); b[o:o + 2] = (30000).to_bytes(2, "little", signed=True); open(sys.argv[2], "wb").write(b)' \
  "$WORK/le.raw" "$WORK/peak.raw"
expect_exit 2 "$BIN/splat-view" --terrain "$WORK/peak.raw" --raw 257,257,int16 --ham "$WORK/raw.exr" \
  -o "$WORK/x.png"
expect_stderr "raw.exr: not the tiles of .*peak.raw .*: tile \(1, 1\) holds a highest height of"
# (tiles made with --z-scale 2 carry it: the viewer scales the map alike, and they match)
expect_exit 0 "$BIN/splat-view" --terrain "$DEM" --ham "$WORK/z2.exr" -o "$WORK/x.png" --width 64 \
  --height 48 -q
# Terrain options without --terrain: a usage error, not ignored.
for opt in "--ham $WORK/t.exr" --wireframe "--tess-error 3"; do
  expect_exit 1 "$BIN/splat-view" "$S/cube.ply" -o "$WORK/x.png" $opt
  grep -q "^splat-view: ${opt%% *} requires --terrain" "$WORK/stderr" && pass ||
    fail "$opt without --terrain: $(cat "$WORK/stderr")"
done

# A careless user's build-ham: --tile and --z-scale at their extremes (1), a 1 x 1 and a flat map
# (valid tiles), splats or a .qs as the heightmap (2), OUT and --ham-full in a missing directory
# and OUT in a read-only one (4); nothing left behind.
for v in 0 -1 1e12 nan inf; do
  expect_exit 1 "$BIN/build-ham" -q "$DEM" "$WORK/x.exr" --tile "$v"
  grep -q "^build-ham: --tile" "$WORK/stderr" && pass || fail "--tile $v: $(head -1 "$WORK/stderr")"
done
for v in 0 -1 nan inf; do
  expect_exit 1 "$BIN/build-ham" -q "$DEM" "$WORK/x.exr" --z-scale "$v"
  grep -q "^build-ham: --z-scale" "$WORK/stderr" && pass || fail "--z-scale $v: $(head -1 "$WORK/stderr")"
done
head -c 2 /dev/zero >"$WORK/one.raw"
expect_exit 0 "$BIN/build-ham" -q "$WORK/one.raw" "$WORK/one.exr" --raw 1,1,int16
head -c 2000 /dev/zero >"$WORK/flat.raw"
expect_exit 0 "$BIN/build-ham" -q "$WORK/flat.raw" "$WORK/flat.exr" --raw 40,50,uint8
"$BIN/estimate-normals" -q "$S/sphere.ply" "$WORK/s.splk" && "$BIN/build-qsplat" -q "$WORK/s.splk" "$WORK/s.qs"
for f in "$WORK/s.splk" "$WORK/s.qs" "$S/sphere.ply"; do
  expect_exit 3 "$BIN/build-ham" -q "$f" "$WORK/x.exr"
  expect_stderr "^build-ham: .*${f##*/}: a .*, not a heightmap \\(GeoTIFF/TIFF"
done
rm -f "$WORK/x.png"
expect_exit 3 "$BIN/splat-view" -q --terrain "$WORK/s.qs" --ham "$WORK/t.exr" -o "$WORK/x.png"
expect_stderr "^splat-view: .*s.qs: a QSplat hierarchy \\(.qs\\), not a heightmap"
[ ! -e "$WORK/x.png" ] && pass || fail "a refused terrain view wrote OUT"
expect_exit 4 "$BIN/build-ham" -q "$DEM" "$WORK/no/such/x.exr"
expect_stderr "no/such/x.exr: cannot create"
expect_exit 4 "$BIN/build-ham" -q "$DEM" "$WORK/x.exr" --ham-full "$WORK/no/such/f.exr"
expect_stderr "no/such/f.exr: cannot create"
mkdir -p "$WORK/ro"
if mount -t tmpfs -o ro,size=64k tmpfs "$WORK/ro" 2>/dev/null; then
  expect_exit 4 "$BIN/build-ham" -q "$DEM" "$WORK/ro/x.exr"
  expect_stderr "ro/x.exr: cannot create: Read-only file system"
  umount "$WORK/ro"
fi
[ ! -e "$WORK/x.exr" ] && pass || fail "a refused run left x.exr"

finish

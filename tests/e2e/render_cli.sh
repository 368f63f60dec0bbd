# splat-view end to end: renders the bundled samples to PNG and EXR (checked with OpenImageIO's
# iinfo when installed), turntables, the JSON report, identical bytes for any thread count, and
# one-line errors with the right exit codes for clouds without normals/radii and bad options.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
S=$SRC/data-samples
V=$BIN/splat-view

expect_exit 0 "$V" --version
expect_exit 0 "$V" --help
grep -q "Examples:" "$WORK/stdout" && pass || fail "splat-view --help has no examples"
grep -q -- "--view AZ,EL\[,DIST\] " "$WORK/stdout" && pass || fail "--help: --view is not AZ,EL[,DIST]"

# PNG by default, 8-bit RGB of the requested size; the model is drawn (not all background).
expect_exit 0 "$V" -q "$S/torus.ply" -o "$WORK/torus.png" --width 200 --height 150
if command -v iinfo >/dev/null; then
  info=$(iinfo "$WORK/torus.png")
  grep -q "200 x  150, 3 channel, uint8 png" <<<"$info" && pass || fail "torus.png: $info"
  stats=$(iinfo --stats "$WORK/torus.png" | grep "Stats Max")
  grep -q "Stats Max: 2[0-9][0-9] " <<<"$stats" && pass || fail "torus.png looks empty: $stats"
fi

# EXR: float colour and AOVs with OpenEXR channel names.
expect_exit 0 "$V" -q "$S/cad.ply" -o "$WORK/cad.exr" --width 120 --height 90 --view 30,40
if command -v iinfo >/dev/null; then
  channels=$(iinfo -v "$WORK/cad.exr" | grep "channel list")
  expect_eq "exr channels" "$(echo $channels)" "channel list: R, G, B, A, Z, N.X, N.Y, N.Z"
fi

# Only .png and .exr are written (both byte-identical from run to run); any other image format
# (TIFF stamps the date, and was written without its image length) is refused before rendering,
# naming the formats, and leaves nothing; the terrain view and a single frame name with a frame
# number field likewise.
for ext in tif tiff jpg bmp; do
  expect_exit 1 "$V" -q "$S/torus.ply" -o "$WORK/x.$ext" --width 32 --height 24
  expect_stderr "^splat-view: .*x.$ext: images are written as .png or .exr, not .$ext"
  [ ! -e "$WORK/x.$ext" ] && pass || fail "a refused .$ext was written"
done
expect_exit 0 "$V" -q "$S/torus.ply" -o "$WORK/torus2.png" --width 200 --height 150
cmp -s "$WORK/torus.png" "$WORK/torus2.png" && pass || fail "two PNG runs differ"
"$V" --help | grep -- "-o,--output" | grep -q "\.png .*\.exr .*no other format" && pass ||
  fail "--help does not name .png and .exr for -o"
expect_exit 1 "$V" -q "$S/torus.ply" -o "$WORK/k-%04d.png" --width 32 --height 24
expect_stderr "k-%04d.png.*frame number field.*--turntable or --path"
[ -z "$(ls "$WORK" | grep '^k-')" ] && pass || fail "a literal k-%04d.png was written"
expect_exit 0 "$V" -q "$S/torus.ply" -o "$WORK/100%.png" --width 32 --height 24
[ -s "$WORK/100%.png" ] && pass || fail "a name with a lone '%' is not written as it is"

# Same bytes whatever the thread count; every shading mode and both blend methods run.
expect_exit 0 "$V" -q "$S/two-spheres.ply" -o "$WORK/t1.png" --threads 1 --width 160 --height 120
expect_exit 0 "$V" -q "$S/two-spheres.ply" -o "$WORK/t2.png" --threads 2 --width 160 --height 120
cmp -s "$WORK/t1.png" "$WORK/t2.png" && pass || fail "images differ between 1 and 2 threads"
expect_exit 0 "$V" -q "$S/cad.ply" -o "$WORK/cad1.exr" --width 120 --height 90 --view 30,40 --threads 1
cmp -s "$WORK/cad.exr" "$WORK/cad1.exr" && pass || fail "EXR differs between runs or thread counts"
for shade in phong normals depth flat; do
  expect_exit 0 "$V" -q "$S/sphere.ply" -o "$WORK/s_$shade.png" --shade $shade --width 64 --height 48
done
expect_exit 0 "$V" -q "$S/sphere.ply" -o "$WORK/zr.png" --blend zrange --width 64 --height 48
expect_exit 0 "$V" -q "$S/sphere.ply" -o "$WORK/zt.png" --blend zthreshold=0.05 --width 64 --height 48
expect_exit 0 "$V" -q "$S/sphere.ply" -o "$WORK/eye.png" --eye 3,0,1 --target 0,0,0 --fov 30 \
  --width 64 --height 48

# Top and bottom views with the default up (+z): the image up becomes +y, the sphere is drawn
# (the centre pixel is not the background); a top-view turntable renders every frame. An --up
# the user gives parallel to the view stays an error.
pixel() { oiiotool --dumpdata "$1" | awk -v p="Pixel ($2, $3):" 'index($0, p) {print $4, $5, $6}'; }
for eye in 0,0,3 0,0,-3; do
  expect_exit 0 "$V" -q "$S/sphere.ply" -o "$WORK/pole.png" --eye $eye --target 0,0,0 \
    --width 64 --height 48
  if command -v oiiotool >/dev/null; then
    corner=$(pixel "$WORK/pole.png" 0 0) centre=$(pixel "$WORK/pole.png" 32 24)
    [ -n "$centre" ] && [ "$centre" != "$corner" ] && pass ||
      fail "--eye $eye: centre pixel '$centre' is the background '$corner'"
  fi
done
for view in 0,90 120,-90; do
  expect_exit 0 "$V" -q "$S/sphere.ply" -o "$WORK/orbit.png" --view $view --width 64 --height 48
done
expect_exit 0 "$V" -q "$S/cad.ply" -o "$WORK/top_%d.png" --eye 0,0,4 --turntable 3 \
  --width 64 --height 48
cmp -s "$WORK/top_0.png" "$WORK/top_1.png" && fail "top turntable: frames 0, 1 equal" || pass
expect_exit 1 "$V" "$S/sphere.ply" -o "$WORK/x.png" --eye 0,0,3 --target 0,0,0 --up 0,0,1
expect_stderr "^splat-view: --up 0,0,1 is parallel to the viewing direction from --eye to --target"
[ -e "$WORK/x.png" ] && fail "x.png written after an --up error" || pass

# A camera path from standard input (IN a file); both from stdin refused.
printf '[{"eye": [3, 0, 1], "target": [0, 0, 0]}, {"eye": [0, 3, 1], "target": [0, 0, 0]}]' |
  "$V" -q "$S/torus.ply" -o "$WORK/p%d.png" --path - --width 32 --height 24 &&
  [ -s "$WORK/p0.png" ] && [ -s "$WORK/p1.png" ] && pass || fail "--path - (stdin)"
expect_exit 1 "$V" - -o "$WORK/p%d.png" --path - </dev/null
expect_stderr "would both read standard input"
expect_exit 1 "$V" "$S/torus.ply" -o "$WORK/t%d.png" --turntable 0
head -1 "$WORK/stderr" | grep -q "not in range 1 to 1000000" && pass || fail "--turntable 0: $(head -1 "$WORK/stderr")"

# Turntable: N frames named by the %04d field; the JSON report has the counts and stage times.
expect_exit 0 "$V" -q "$S/torus.ply" -o "$WORK/turn_%04d.png" --turntable 3 --width 64 --height 48 \
  --stats "$WORK/stats.json"
for i in 0000 0001 0002; do [ -s "$WORK/turn_$i.png" ] && pass || fail "turntable frame $i missing"; done
cmp -s "$WORK/turn_0000.png" "$WORK/turn_0001.png" && fail "turntable frames 0 and 1 are equal" || pass
if command -v python3 >/dev/null; then
  python3 - "$WORK/stats.json" <<'PY' && pass || fail "stats.json content"
import json, sys
j = json.load(open(sys.argv[1]))
assert j["splats_in"] == 12001 and 0 < j["splats_drawn"] <= 12001, j
assert j["fragments"] > 0 and j["pixels_covered"] > 0 and "pixels_overflowed" in j
for k in ("setup", "binning", "rasterize", "reconstruct", "shade", "frame", "write"):
    assert j["time_ms"][k] >= 0, k
assert j["splats_per_second"] > 0 and len(j["frames"]) == 3
PY
fi

# Frames are encoded on a second thread while the next renders: the bytes do not depend on it
# nor on the thread count. A frame that cannot be written (here a directory in its place) fails
# the run (exit 4) before any frame is written: every frame's name is checked first, so an
# existing frame 0 is kept, and no temporary file is left.
mkdir -p "$WORK/tt1" "$WORK/tt2" "$WORK/ttbad/f1.png"
echo old > "$WORK/ttbad/f0.png"
for t in 1 2; do
  expect_exit 0 "$V" -q "$S/cad.ply" -o "$WORK/tt$t/f%d.png" --turntable 4 --width 96 --height 64 \
    --threads $t
done
for i in 0 1 2 3; do
  cmp -s "$WORK/tt1/f$i.png" "$WORK/tt2/f$i.png" && pass || fail "turntable frame $i: threads"
done
expect_exit 4 "$V" -q "$S/cad.ply" -o "$WORK/ttbad/f%d.png" --turntable 4 --width 96 --height 64
expect_stderr "f1.png"
[ "$(cat "$WORK/ttbad/f0.png")" = old ] && pass || fail "frame 0 written though frame 1 cannot be"
[ -e "$WORK/ttbad/f2.png" ] || [ -e "$WORK/ttbad/f3.png" ] && fail "frames after a failure" || pass
ls "$WORK/ttbad" | grep -q tmp && fail "temporary file left: $(ls "$WORK/ttbad")" || pass

# PNG to standard output.
"$V" -q "$S/sphere.ply" -o - --width 32 --height 24 > "$WORK/stdout.png" 2>"$WORK/stderr" && pass || fail "-o -"
head -c 8 "$WORK/stdout.png" | od -An -c | grep -q "P   N   G" && pass || fail "stdout is not a PNG"

# Errors: one line naming the file and the tool to run first; nothing written.
expect_exit 2 "$V" "$S/kitten.xyz" -o "$WORK/kitten.png"
expect_stderr "^splat-view: .*kitten.xyz: .*no radii; run estimate-normals first"
[ -e "$WORK/kitten.png" ] && fail "kitten.png written after an error" || pass
expect_exit 2 "$V" "$S/nefertiti.off" -o "$WORK/n.png"
expect_stderr "no normals and no radii; run estimate-normals first"
expect_exit 1 "$V" "$S/sphere.ply" -o "$WORK/x.png" --blend median
expect_stderr "--blend must be zthreshold"
expect_exit 1 "$V" "$S/sphere.ply" -o "$WORK/x.png" --turntable 4
expect_stderr "one frame number field"
expect_exit 0 "$V" -q "$S/sphere.ply" -o "$WORK/far.png" --view 10,20,9 --width 64 --height 48
expect_exit 0 "$V" -q "$S/sphere.ply" -o "$WORK/near.png" --view 10,20,4 --width 64 --height 48
cmp -s "$WORK/far.png" "$WORK/near.png" && fail "--view distance has no effect" || pass
for bad in 10 10,x 1,2,3,4 10,20,; do
  expect_exit 1 "$V" "$S/sphere.ply" -o "$WORK/x.png" --view $bad
  expect_stderr "--view needs AZ,EL or AZ,EL,DIST"
done
expect_exit 1 "$V" "$S/sphere.ply" -o "$WORK/x.png" --eye 1,2,3 --view 10,20
expect_exit 1 "$V" "$S/sphere.ply" -o "$WORK/x.png" --eye 0,0,0 --target 0,0,0
expect_exit 1 "$V" "$S/sphere.ply" -o "$WORK/x.nosuchformat"
expect_exit 2 "$V" "$WORK/missing.ply" -o "$WORK/x.png"
# A `class` attribute that is not build-splat-graph's (scene labels 3..7 here) is left alone.
"$BIN/splat-synth" -q sphere "$WORK/labelled.xyz" -n 2000
awk '!/^#/ { print $0, 3 + NR % 5 }' "$WORK/labelled.xyz" >"$WORK/labelled-class.xyz"
"$BIN/splat-convert" -q --columns x,y,z,nx,ny,nz,r,g,b,radius,patch_id,class \
  "$WORK/labelled-class.xyz" "$WORK/labelled.ply"
expect_exit 0 "$V" "$WORK/labelled.ply" -o "$WORK/labelled.png"
# A y-up model (the kitten: longest along y, deep along z) gets the hint in the summary line;
# given --up, or a flat scene, none.
"$BIN/estimate-normals" -q --columns x,y,z,_,_,_ "$SRC/data-samples/kitten.xyz" "$WORK/kitten.splk"
expect_exit 0 "$BIN/splat-view" "$WORK/kitten.splk" "$WORK/kitten.png" --width 64 --height 48
expect_stderr "if \\+y is up \\(as in many PLY models\\), give --up 0,1,0$"
expect_exit 0 "$BIN/splat-view" "$WORK/kitten.splk" "$WORK/kitten.png" --width 64 --height 48 \
  --up 0,1,0
! grep -q -- "--up 0,1,0" "$WORK/stderr" && pass || fail "a hint although --up was given"
expect_exit 0 "$BIN/splat-view" "$SRC/data-samples/torus.ply" "$WORK/torus.png" --width 64 \
  --height 48
! grep -q -- "--up 0,1,0" "$WORK/stderr" && pass || fail "a y-up hint for the torus"

finish

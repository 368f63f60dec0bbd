# The files the examples of tests/e2e/examples.sh (every tool's --help) and
# tests/e2e/doc_examples.sh (README.md and docs/tools/*.md) name, made in the current directory
# from data-samples/ ($S), and left_out, the examples a sanitizer build does not run. Sourced
# after common.bash, in the directory the examples run in.
mkdir -p scans out frames
ln -sfn "$S" data-samples  # the documentation's commands name the samples by this path
# The files the examples name.
# A scan as scanners give it: points without normals or radii (the examples that draw or build
# from splats must name the output of estimate-normals).
splat-convert -q "$S/cad-scan.laz" scan.ply 2>/dev/null || fail "setup: scan.ply"
cp "$S/cube.ply" big.ply
cp "$S/torus-las12.las" scan.las
cp "$S/torus-las12.laz" scan.laz
cp "$S/cad-scan.laz" survey.laz
mkdir -p survey && cp "$S/cad-scan.laz" survey/
cp "$S/sphere.ply" "$S/torus-big-endian.ply" scans/
cp "$S/cad-noisy.xyz" part.xyz
cp "$S/kitten.xyz" points.xyz  # x y z nx ny nz
awk '{ printf "%s %s %s 0 %d %d %d\n", $1, $2, $3, NR % 256, (3 * NR) % 256, 128 }' \
  "$S/kitten.xyz" > points.txt  # x y z _ r g b
cp points.txt scan.xyz
setup() { "$@" 2>"$WORK/setup.err" || { fail "setup: $*: $(cat "$WORK/setup.err")"; }; }
setup splat-convert -q "$S/torus-ascii.ply" model.splk
setup estimate-normals -q --columns x,y,z,_,_,_ "$S/kitten.xyz" bunny.splk
setup estimate-normals -q --method robust part.xyz part.splk
setup splat-convert -q part.splk part.ply
setup build-splat-graph -q part.splk part-graph.splk
setup segment-surfaces -q part-graph.splk part-surf.splk
setup splat-convert -q bunny.splk bunny.ply
setup build-qsplat -q bunny.splk bunny.qs
# Heightmaps: the real SRTM crop as GeoTIFF, as an SRTM .hgt, and 1024² float32 RAW.
cp "$S/rainier-srtm.tif" dem.tif
python3 -c 'import struct, math, sys
n = 257
open("N46W122.hgt", "wb").write(struct.pack(">%dh" % (n * n), *[int(1500 + 800 * math.sin(i / 900)) for i in range(n * n)]))
open("dem.f32", "wb").write(struct.pack("<%df" % (1024 * 1024), *[100 * math.sin(i / 5000) for i in range(1024 * 1024)]))' ||
  fail "setup: heightmaps"
setup build-ham -q dem.tif tiles.exr

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
  elif grep -v -E '^[a-z-]+: [0-9]+ (points|splats|samples|triangles) in ' "$WORK/ex.err" | grep -q .; then
    fail "$1: unexpected stderr: $cmd: $(head -3 "$WORK/ex.err")"
  else
    pass
  fi
}

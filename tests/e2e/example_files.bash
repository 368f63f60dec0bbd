# The files the examples of every tool's --help name (tests/e2e/examples.sh), made in the current
# directory from data-samples/ ($S). Sourced after common.bash, in the directory the examples run in.
mkdir -p scans out frames
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
# Tiles' level-of-detail files (build-spt --merge, build-qsplat --merge): a torus in four tiles.
setup splat-tile -q "$S/torus.ply" -o torus-tiles --tile-size 1.5
mkdir -p lod surfaces
for t in torus-tiles/tiles/*.splk; do
  setup build-spt -q "$t" "lod/$(basename "$t" .splk).spt"
  setup build-qsplat -q "$t" "lod/$(basename "$t" .splk).qs"
  # Segmented tiles (splat-convert's join of their surfaces).
  setup build-splat-graph -q "$t" "surfaces/graph-$(basename "$t")"
  setup segment-surfaces -q "surfaces/graph-$(basename "$t")" "surfaces/$(basename "$t")"
  rm "surfaces/graph-$(basename "$t")"
done
# Heightmaps: the real SRTM crop as GeoTIFF, as an SRTM .hgt, and 1024² float32 RAW.
cp "$S/rainier-srtm.tif" dem.tif
python3 -c 'import struct, math, sys
n = 257
open("N46W122.hgt", "wb").write(struct.pack(">%dh" % (n * n), *[int(1500 + 800 * math.sin(i / 900)) for i in range(n * n)]))
open("dem.f32", "wb").write(struct.pack("<%df" % (1024 * 1024), *[100 * math.sin(i / 5000) for i in range(1024 * 1024)]))' ||
  fail "setup: heightmaps"
setup build-ham -q dem.tif tiles.exr

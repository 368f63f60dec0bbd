#!/usr/bin/env bash
# Every example of every tool's --help (the lines "$ ...") and of README.md's "In a shell" section
# runs as written, in a private directory holding the files the examples name (made from
# data-samples/), with the tools first on PATH: exit code 0, nothing on stderr but the summary
# lines, and the files the examples promise (a sanitizer build leaves out the 10M-point city's).
source "$(dirname "$0")/common.bash"
S=$SRC/data-samples
EX=$WORK/ex
mkdir -p "$EX/scans" "$EX/out" "$EX/frames"
export PATH=$BIN:$PATH
cd "$EX" || exit 1

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

count=0
for tool in splat-info splat-tile splat-convert splat-synth estimate-normals build-splat-graph \
            segment-surfaces build-qsplat build-spt build-ham splat-view; do
  # The examples: lines "$ command  # comment" in the help footer (commands span one line).
  while IFS= read -r cmd; do
    left_out "$cmd" && continue
    run_example "$tool --help" "$cmd"
    count=$((count + 1))
  done < <("$tool" --help | sed -n 's/^ *\$ //p' | sed 's/  *# .*$//')
done
expect_eq "number of --help examples run" "$([ "$count" -ge 25 ] && echo ok)" ok

readme=0
while IFS= read -r cmd; do
  left_out "$cmd" && continue
  run_example "README In a shell" "$cmd"
  readme=$((readme + 1))
done < <(awk '/^## In a shell/ { on = 1; next } on && /^```sh/ { code = 1; next }
              on && code && /^```/ { exit } code && !/^#/ && NF' "$SRC/README.md")
expect_eq "number of README examples run" "$([ "$readme" -ge 5 ] && echo ok)" ok

# What the examples promise.
for f in model.ply out/sphere.splk out/torus-big-endian.splk out.ply sphere.ply cad.ply \
         spheres.ply torus.xyz scan.splk part-graph.splk parts.ply graph.json part-surf.ply \
         surfaces.json bunny.png top.png part.exr turn_0000.png turn_0035.png stats.json \
         surf.png soft.png scan.png part-surfaces.ply frames/part-0035.png part.json part-top.png \
         inventory.json bunny.qs scan.qs qs.json far.png scan.spt spt.json s.json \
         rainier-tiles.exr ham.json ham.exr dem-f32.exr dem.png tiled/tiles.json \
         parts/tiles.json tile.json retiled/tiles.json survey.splk; do
  [ -s "$f" ] && pass || fail "no $f after the examples"
done
expect_eq "inventory.json describes every scan" \
  "$(jq -r '[.[].points] | length' inventory.json 2>/dev/null)" 2
grep -aq "property uint surface_id" part-surfaces.ply && pass ||
  fail "part-surfaces.ply has no surface_id"
grep -aq "property uint surface_id" parts.ply && pass || fail "parts.ply has no surface_id"

finish

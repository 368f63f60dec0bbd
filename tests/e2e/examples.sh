#!/usr/bin/env bash
# Every example of every tool's --help (the lines "$ ...") runs as written, in a private directory
# holding the files the examples name (example_files.bash), with the tools first on PATH: exit
# code 0, nothing on stderr but the summary lines, and the files the examples promise (a
# sanitizer build leaves out the 10M-point city's). The documentation's commands: doc_examples.sh.
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/common.bash"
S=$SRC/data-samples
EX=$WORK/ex
mkdir -p "$EX"
export PATH=$BIN:$PATH
cd "$EX" || exit 1

source "$HERE/example_files.bash"
source "$HERE/run_example.bash"

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

# What the examples promise.
for f in model.ply out/sphere.splk out/torus-big-endian.splk out.ply sphere.ply cad.ply \
         spheres.ply torus.xyz scan.splk part-graph.splk parts.ply graph.json part-surf.ply \
         surfaces.json bunny.png top.png part.exr turn_0000.png turn_0035.png stats.json \
         surf.png soft.png bunny.qs scan.qs qs.json far.png scan.spt spt.json s.json \
         rainier-tiles.exr ham.json ham.exr dem-f32.exr dem.png tiled/tiles.json \
         parts/tiles.json tile.json retiled/tiles.json survey.splk; do
  [ -s "$f" ] && pass || fail "no $f after the examples"
done
grep -aq "property uint surface_id" parts.ply && pass || fail "parts.ply has no surface_id"

finish

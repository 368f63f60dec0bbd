#!/usr/bin/env bash
# The whole pipeline on the bundled samples, in one command: installs what is missing, builds,
# and writes the results to out/ (files, JSON reports and images). Works from any directory.
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$top/scripts/install-deps.sh"
"$top/scripts/build.sh" "$top/build"
bin=$top/build/tools
out=$top/out
samples=$top/data-samples
mkdir -p "$out/formats" "$out/normals" "$out/images" "$out/terrain"
shopt -s nullglob

echo "== 1. every sample -> .splk, with splat-info reports (out/formats/) =="
for f in "$samples"/*.{ply,xyz,off,las,laz,pcd}; do
  name=$(basename "$f")
  "$bin/splat-convert" -q "$f" "$out/formats/$name.splk"
  "$bin/splat-info" "$out/formats/$name.splk" > "$out/formats/$name.info.txt"
  "$bin/splat-info" --json "$f" > "$out/formats/$name.info.json"
  printf '  %-24s %8s points -> out/formats/%s.splk\n' "$name" \
    "$(sed -n 's/^Points: //p' "$out/formats/$name.info.txt")" "$name"
done

echo "== 2. normals and radii from bare points (out/normals/) =="
# The real scan (kitten, positions only) and the CAD-like part with its creases, PCA vs robust.
"$bin/estimate-normals" "$samples/kitten.xyz" --columns x,y,z,_,_,_ "$out/normals/kitten.splk" \
  --report "$out/normals/kitten.report.json"
for method in pca robust; do
  "$bin/estimate-normals" "$samples/cad.ply" "$out/normals/cad-$method.splk" --method "$method" \
    --report "$out/normals/cad-$method.report.json"
done
# LAZ (LASzip-compressed LAS): a scan-line sample, decoded by splatkit, through normals and radii
# to an image (section 4).
"$bin/estimate-normals" "$samples/cad-scan.laz" "$out/normals/cad-scan-laz.splk" \
  --report "$out/normals/cad-scan-laz.report.json"
# A pipeline: normals straight into the renderer's input, through a pipe.
"$bin/estimate-normals" -q "$samples/torus-las12.las" - | "$bin/splat-info" - > "$out/normals/torus-las12.info.txt"
# Scan lines 4x denser along than across: circles, and ellipses fitted to the same cells.
"$bin/splat-synth" -q torus "$out/normals/torus-lines.ply" -n 40000 --scan-lines 4 --no-color
for splat in circle ellipse; do
  "$bin/estimate-normals" "$out/normals/torus-lines.ply" "$out/normals/torus-lines-$splat.splk" \
    --splat "$splat" --report "$out/normals/torus-lines-$splat.report.json"
done

echo "== 3. neighbour graph, sharp edges, clip partners and surfaces (out/graph/) =="
mkdir -p "$out/graph"
"$bin/build-splat-graph" "$out/normals/cad-robust.splk" "$out/graph/cad.splk" \
  --report "$out/graph/cad.graph.json"
"$bin/segment-surfaces" "$out/graph/cad.splk" "$out/graph/cad-surfaces.splk" \
  --report "$out/graph/cad.surfaces.json"
# The same as PLY with surface_id and class per vertex, for CloudCompare / MeshLab.
"$bin/segment-surfaces" -q "$out/graph/cad.splk" "$out/graph/cad-surfaces.ply"
"$bin/splat-info" "$out/graph/cad-surfaces.splk" > "$out/graph/cad-surfaces.info.txt"

echo "== 4. images (out/images/) =="
render() {  # render NAME INPUT [options]
  local name=$1 input=$2; shift 2
  "$bin/splat-view" -q "$input" -o "$out/images/$name.png" --width 800 --height 600 "$@"
  echo "  out/images/$name.png"
}
render sphere "$samples/sphere.ply"
render torus "$samples/torus.ply"
render two-spheres "$samples/two-spheres.ply"
render cad-true-normals "$samples/cad.ply"
render cad-scan-laz "$out/normals/cad-scan-laz.splk"
render cad-pca "$out/normals/cad-pca.splk"
render cad-robust "$out/normals/cad-robust.splk"
render kitten "$out/normals/kitten.splk"
# The graph stages at work on the robust CAD part: clipped creases and per-surface reconstruction
# (plain), the surfaces found, the splats with a sharp edge (red), and the same view without the
# clip partners and surface ids to compare.
view=(--view 35,30)
render cad-graph-plain "$out/graph/cad-surfaces.splk" "${view[@]}"
render cad-graph-surfaces "$out/graph/cad-surfaces.splk" "${view[@]}" --shade surface
render cad-graph-sharp "$out/graph/cad-surfaces.splk" "${view[@]}" --shade sharp
render cad-graph-clipped "$out/graph/cad-surfaces.splk" "${view[@]}" --shade clipped
render cad-graph-no-clip "$out/graph/cad-surfaces.splk" "${view[@]}" --no-clip --no-surface-ids
render kitten-normals "$out/normals/kitten.splk" --shade normals
# Shading from few splats (5k on the kitten): each pixel lit by its nearest splat's own normal
# (--blend zbuffer: a facet per splat, dark specks in the crevices) on the left, by the default
# reconstruction's smooth per-pixel normal field on the right.
render kitten-zbuffer "$out/normals/kitten.splk" --blend zbuffer
oiiotool "$out/images/kitten-zbuffer.png" "$out/images/kitten.png" --mosaic 2x1 \
  -o "$out/images/kitten-shading-before-after.png"
echo "  out/images/kitten-shading-before-after.png"
for splat in circle ellipse; do  # a close-up: no background through the surface either way
  render "torus-lines-$splat" "$out/normals/torus-lines-$splat.splk" --view 20,35,1.6
done
"$bin/splat-view" -q "$samples/cad.ply" -o "$out/images/cad.exr" --width 800 --height 600
echo "  out/images/cad.exr (colour + Z, N, A channels)"
# QSplat: 400k coloured splats (two spheres) as a .qs hierarchy, drawn by the QSplat traversal at
# 1, 4 and 16 px (--stats: nodes visited, culled, splats drawn).
"$bin/splat-synth" -q two-spheres "$out/images/two-spheres-400k.splk" -n 400000
"$bin/build-qsplat" -q "$out/images/two-spheres-400k.splk" "$out/images/two-spheres.qs"
echo "  out/images/two-spheres.qs ($(stat -c %s "$out/images/two-spheres.qs") bytes)"
for px in 1 4 16; do
  render "two-spheres-qsplat-${px}px" "$out/images/two-spheres.qs" --qsplat-threshold "$px" \
    --stats "$out/images/two-spheres-qsplat-${px}px.json"
done
# Sequential Point Tree: the CAD sample as an .spt list, drawn at three distances at a 1 px
# error (--stats: the prefix, the entries culled in it, the splats drawn; fewer as it recedes).
"$bin/build-spt" -q "$samples/cad.ply" "$out/images/cad.spt" --report "$out/images/cad-spt.json"
echo "  out/images/cad.spt ($(stat -c %s "$out/images/cad.spt") bytes)"
for d in 5 20 80; do
  render "cad-spt-$d" "$out/images/cad.spt" --view "30,25,$d" --spt-error 1 \
    --stats "$out/images/cad-spt-$d.json"
done
echo "== 4b. a real scan, oriented before and after (out/real-scan/) =="
# CGAL's photogrammetry building (Debian's libcgal-demo): normals oriented over the kNN graph
# alone (--orient mst) and by visibility and smooth regions (the default), drawn with their
# normals as colours and as a QSplat tree, whose traversal culls back faces: a facade whose
# normals point inward disappears. Each image: mst on the left, the default on the right.
mkdir -p "$out/real-scan"
if "$top/scripts/fetch-cgal-scans.sh" "$out/real-scan" > /dev/null; then
  for orient in mst auto; do
    "$bin/estimate-normals" -q "$out/real-scan/building.ply" "$out/real-scan/building-$orient.splk" \
      --orient "$orient" --report "$out/real-scan/building-$orient.json"
    "$bin/build-qsplat" -q "$out/real-scan/building-$orient.splk" "$out/real-scan/building-$orient.qs"
    "$bin/splat-view" -q "$out/real-scan/building-$orient.splk" --shade normals --width 640 \
      --height 480 -o "$out/real-scan/normals-$orient.png"
    "$bin/splat-view" -q "$out/real-scan/building-$orient.qs" --width 640 --height 480 \
      -o "$out/real-scan/qsplat-$orient.png"
  done
  for kind in normals qsplat; do
    oiiotool "$out/real-scan/$kind-mst.png" "$out/real-scan/$kind-auto.png" --mosaic 2x1 \
      -o "$out/real-scan/$kind-before-after.png"
    echo "  out/real-scan/$kind-before-after.png"
  done
  # Its shading, as the kitten's above: one normal per splat (left), the default (right).
  for blend in zbuffer zthreshold; do
    "$bin/splat-view" -q "$out/real-scan/building-auto.splk" --blend "$blend" --view 200,15,45 \
      --width 640 --height 480 -o "$out/real-scan/shading-$blend.png"
  done
  oiiotool "$out/real-scan/shading-zbuffer.png" "$out/real-scan/shading-zthreshold.png" \
    --mosaic 2x1 -o "$out/real-scan/shading-before-after.png"
  echo "  out/real-scan/shading-before-after.png"
else
  echo "  skipped: Debian's libcgal-demo could not be downloaded"
fi
echo "== 5. occlusion culling: a city walkthrough (out/city/) =="
# 2 M splats of buildings (walls, floor slabs, roofs) and 6 street-level cameras, rendered with
# every splat and with CHC++ occlusion culling over the chunk hierarchy: the same images.
mkdir -p "$out/city/none" "$out/city/chc++"
"$bin/splat-synth" -q city "$out/city/city.splk" -n 2000000 --walkthrough "$out/city/walk.json" \
  --walk-frames 6
for mode in none chc++; do
  "$bin/splat-view" -q "$out/city/city.splk" -o "$out/city/$mode/%04d.png" \
    --path "$out/city/walk.json" --width 960 --height 540 --occlusion "$mode" \
    --stats "$out/city/$mode.json"
  python3 -c "import json, sys; j = json.load(open(sys.argv[1])); print('  %-6s %.1f frames/s' %
    (sys.argv[2], 1000 / j['mean_frame_ms']))" "$out/city/$mode.json" "$mode"
done
same=yes
for f in "$out/city/none"/*.png; do cmp -s "$f" "$out/city/chc++/$(basename "$f")" || same=no; done
echo "  images identical with and without culling: $same"
echo "== 6. terrain: HAM tiles and HAM-driven tessellation (out/terrain/) =="
# A real SRTM crop around Mount Rainier, with voids: the per-tile HAM (and the full HAM), then the
# terrain from an orbit view and from a low camera south-east of the summit, each with and
# without the triangles drawn; --stats: triangles against factor 64 everywhere, factor histogram.
"$bin/build-ham" -q "$samples/rainier-srtm.tif" "$out/terrain/rainier-tiles.exr" --tile 32 \
  --ham-full "$out/terrain/rainier-ham.exr" --report "$out/terrain/rainier-ham.json"
echo "  out/terrain/rainier-tiles.exr, rainier-ham.exr, rainier-ham.json"
terrain() {  # terrain NAME [camera options]
  local name=$1; shift
  for wire in "" --wireframe; do
    "$bin/splat-view" -q --terrain "$samples/rainier-srtm.tif" \
      --ham "$out/terrain/rainier-tiles.exr" -o "$out/terrain/$name${wire:+-wire}.png" \
      --width 1024 --height 640 --stats "$out/terrain/$name${wire:+-wire}.json" $wire "$@"
    echo "  out/terrain/$name${wire:+-wire}.png"
  done
}
terrain rainier-orbit --view 200,35
terrain rainier-low --eye 16000,-26000,5200 --target 8120,-11800,3300 --fov 50
echo "== 7. the browser viewer =="
# splat-view --serve shows the models above in a browser (WebGL2; http://127.0.0.1 only):
# .spt on the GPU by its distance intervals, .qs by the QSplat traversal, .splk blended.
served=("$out/images/cad.spt")
for f in "$out/real-scan/building-auto.splk" "$out/real-scan/building-auto.qs"; do
  [ -e "$f" ] && served+=("$f")
done
echo "  to look at them in a browser, run:"
echo "    $bin/splat-view --serve ${served[*]} --port 8080"
echo "  and open http://127.0.0.1:8080/#file=$(basename "${served[0]}")&view=35,25"
echo "demo: results in $out"

#!/usr/bin/env bash
# Regenerates the synthetic files in data-samples/ with the built splat-synth (byte-identical on
# every run: fixed seeds, deterministic sampling; the LAZ files by the built splat-convert). The
# PCD variant is converted by PCL's own pcl_ply2pcd (package pcl-tools) when it is installed, the LAS variants by
# scripts/make-las-samples.py (python3). With --cgal it also fetches the two real
# samples (kitten.xyz, nefertiti.off) from Debian's libcgal-demo package (downloaded into a temp
# dir, not installed). Provenance of every file: data-samples/README.md.
#
#   scripts/make-samples.sh [--cgal] [BIN_DIR]   # BIN_DIR: where splat-synth is (default:
#                                                # build/tools, else the first build-*/tools)
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
out=$top/data-samples

cgal=0
bin=
for arg in "$@"; do
  case $arg in
    --cgal) cgal=1 ;;
    -h | --help) sed -n '2,10p' "${BASH_SOURCE[0]}"; exit 0 ;;
    -*) echo "make-samples: unknown option $arg" >&2; exit 1 ;;
    *) bin=$arg ;;
  esac
done
if [[ -z $bin ]]; then
  for candidate in "$top/build/tools" "$top"/build-*/tools; do
    if [[ -x $candidate/splat-synth ]]; then bin=$candidate; break; fi
  done
fi
if [[ -z $bin || ! -x $bin/splat-synth ]]; then
  echo "make-samples: no splat-synth found; build it (scripts/build.sh) or pass its directory" >&2
  exit 1
fi
mkdir -p "$out"
# Everything is made in a temp dir and moved into place at the end: a failed run changes nothing.
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
synth() {
  local shape=$1 name=$2
  shift 2
  "$bin/splat-synth" -q "$shape" "$tmp/$name" "$@"
}

# The ground-truth samples: binary little-endian PLY with normals, radius and patch_id. Colours
# only where they mean something (the red and blue spheres): grey would add 3 bytes a point.
synth sphere sphere.ply -n 10000 --seed=1 --no-color
synth torus torus.ply -n 12000 --seed=1 --no-color
synth cad cad.ply -n 30000 --seed=1 --no-color
synth two-spheres two-spheres.ply -n 12000 --seed=1 --keep-inside
synth cube cube.ply -n 12000 --seed=1 --no-color

# Small variants in the other encodings and formats, for the readers.
synth torus torus-ascii.ply -n 1000 --seed=2 --no-color --ascii
synth torus torus-big-endian.ply -n 1000 --seed=2 --no-color --big-endian
synth cad cad-noisy.xyz -n 1000 --seed=3 --noise 0.002 --no-color
synth sphere sphere-random.off -n 1000 --seed=4 --random --no-color

# A scan-line LAZ (point format 0, two LASzip chunks of 50000 points) for the LAZ demo and tests.
synth cad cad-scan.ply -n 60000 --seed=7 --scan-lines 4 --no-color
"$bin/splat-convert" -q "$tmp/cad-scan.ply" "$tmp/cad-scan.laz"
# A LAS 1.4 LAZ (point format 7, LASzip layered chunks).
synth two-spheres two-spheres-scan.ply -n 20000 --seed=7 --scan-lines 4 --noise 0.001
"$bin/splat-convert" -q --las-format 7 "$tmp/two-spheres-scan.ply" "$tmp/two-spheres-las14.laz"

made=(sphere.ply torus.ply cad.ply two-spheres.ply cube.ply torus-ascii.ply torus-big-endian.ply
  cad-noisy.xyz sphere-random.off cad-scan.laz two-spheres-las14.laz)

if command -v pcl_ply2pcd > /dev/null; then
  synth cad cad-pcl.ply -n 1000 --seed=5 --no-color
  pcl_ply2pcd -format 1 "$tmp/cad-pcl.ply" "$tmp/cad-pcl.pcd" > /dev/null
  made+=(cad-pcl.pcd)
else
  echo "make-samples: pcl_ply2pcd not found (apt-get install pcl-tools); kept the old cad-pcl.pcd" >&2
fi

# The LAS variants come from the text variants above through an independent writer (plain
# struct packing of the ASPRS layouts), so they follow them.
if command -v python3 > /dev/null; then
  python3 "$top/scripts/make-las-samples.py" "$tmp"
  made+=(torus-las12.las cad-utm-las14.las)
  # LAZ: the LAS torus compressed by splatkit's LASzip writer (point format 3, one chunk).
  "$bin/splat-convert" -q "$tmp/torus-las12.las" "$tmp/torus-las12.laz"
  made+=(torus-las12.laz)
else
  echo "make-samples: python3 not found; kept the old LAS samples" >&2
fi

if ((cgal)); then
  (cd "$tmp" && apt-get download libcgal-demo > /dev/null 2>&1)
  dpkg -x "$tmp"/libcgal-demo_*.deb "$tmp/deb"
  tar -xzf "$tmp/deb/usr/share/doc/libcgal-demo/data.tar.gz" -C "$tmp" \
    data/points_3/kitten.xyz data/meshes/nefertiti.off
  mv "$tmp/data/points_3/kitten.xyz" "$tmp/data/meshes/nefertiti.off" "$tmp/"
  made+=(kitten.xyz nefertiti.off)
fi

for name in "${made[@]}"; do mv "$tmp/$name" "$out/$name"; done
du -ab "$out" | sort -k2 | awk '{ printf "%10d  %s\n", $1, $2 }'

#!/usr/bin/env bash
# The whole pipeline on the bundled samples, in one command: installs what is missing, builds,
# and writes the results to out/ (files, reports and images). Works from any directory.
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$top/scripts/install-deps.sh"
"$top/scripts/build.sh" "$top/build"
bin=$top/build/tools
out=$top/out
mkdir -p "$out"
samples=$top/data-samples

echo "== samples -> .splk and splat-info =="
shopt -s nullglob
for f in "$samples"/*.{ply,xyz,pts,txt,csv,off,las,pcd}; do
  name=$(basename "$f")
  stem=${name%.*}.${name##*.}
  "$bin/splat-convert" -q "$f" "$out/$stem.splk"
  "$bin/splat-info" "$out/$stem.splk" > "$out/$stem.info.txt"
  "$bin/splat-info" --json "$f" > "$out/$stem.info.json"
  printf '%-40s -> %s\n' "$name" "out/$stem.splk"
done
echo "demo: results in $out"

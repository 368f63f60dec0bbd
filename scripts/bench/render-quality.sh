#!/usr/bin/env bash
# Rendering quality: splat-view's per-pixel normal (the EXR's N.X, N.Y, N.Z) against the exact
# normal of the unit sphere, on a sphere of N i.i.d. samples (splat-synth sphere --random), once
# with its exact normals and once with estimate-normals' own, each with the default blend
# (zthreshold) and with --blend zbuffer. Camera: --eye 2.18,-1.36,1.5 --target 0,0,0, 1280x720,
# fov 40. Counted: the pixels whose ray meets the sphere at a view angle below 75 degrees. Prints
# each case's mean, 95th percentile and maximum error in degrees and the sphere pixels left empty
# (bench_render_quality). With REF_VIEW=/path/to/splat-view, the same cases with that binary too
# (before/after). The images are left in $OUT_DIR when it is set.
# usage: scripts/bench/render-quality.sh [points=3000] [seed=1]
#        (build dir: $BUILD_DIR, default build-bench)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-bench}
points=${1:-3000} seed=${2:-1}
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSPLATKIT_BUILD_BENCH=ON \
  >/dev/null
ninja -C "$build" -j2 bench_render_quality splat-synth estimate-normals splat-view >/dev/null

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
out=${OUT_DIR:-$work}
mkdir -p "$out"
eye=2.18,-1.36,1.5
"$build/tools/splat-synth" -q sphere "$work/exact.splk" -n "$points" --random --seed "$seed"
"$build/tools/estimate-normals" -q "$work/exact.splk" "$work/estimated.splk"
views=("this:$build/tools/splat-view")
[ -n "${REF_VIEW:-}" ] && views+=("ref:$REF_VIEW")
echo "unit sphere, $points i.i.d. points (seed $seed), eye $eye, 1280x720, view angle < 75 deg"
for view in "${views[@]}"; do
  label=${view%%:*} bin=${view#*:}
  for normals in exact estimated; do
    for blend in zthreshold zbuffer; do
      image="$out/$label-$normals-$blend.exr"
      "$bin" -q "$work/$normals.splk" -o "$image" --eye "$eye" --target 0,0,0 --blend "$blend"
      printf '%-4s %-9s normals, --blend %-10s: %s\n' "$label" "$normals" "$blend" \
        "$("$build/scripts/bench/bench_render_quality" "$image" "$eye")"
    done
  done
done

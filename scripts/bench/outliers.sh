#!/usr/bin/env bash
# Outlier removal measured: each scan below gets 1 % of its point count added uniformly in its
# bounding box, and bench_outliers prints, over a grid of K and SIGMA, the share of the injected
# points `estimate-normals --outliers sor:K,SIGMA` removes against the share of the scan's own
# points it removes (PCL's StatisticalOutlierRemoval rule; the default cell also run through
# find_outliers itself), the same for a robust threshold (median + KAPPA * 1.4826 MAD of the
# same distances), the best cell that removes at most 0.5 % of the scan, and the injected points
# by their distance to the nearest scan point in s (the square root of the scan's area per point,
# from the median distance to the 8th nearest scan point): points that land on the surface are
# not outliers any rule can see (the "ceiling": the share 1 s or more away). Then iterated SOR,
# PCL's filter applied again to its own output: a first pass K1,SIGMA1 (K1 in 8, 12, 16; SIGMA1
# in 1, 2, 3), then one or two passes K2,SIGMA2 over the survivors, whose mean and deviation no
# longer hold the far outliers. Then, over all scans, the single-pass and the iterated cells that
# remove at most 0.5 % of every scan, best first, and the cells meeting both goals on the most
# scans. Deterministic (every cloud made with a fixed --seed); about 3 CPU minutes.
# The goal: >= 95 % of the injected points, <= 0.5 % of the scan.
# estimate-normals `--outliers sor` is the chain sor:12,3+sor:6,3.5 chosen here.
# usage: scripts/bench/outliers.sh [K=12 SIGMA=1: a single pass to check] [scale=1: point counts x]
#   [CHAIN=12,3+6,3.5: passes K1,SIGMA1+K2,SIGMA2... to check, default: estimate-normals'
#   `--outliers sor`], both run through find_outliers, with outliers and on each scan alone.
#   (build dir: $BUILD_DIR, default build-bench)
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build-bench}
k=${1:-12} sigma=${2:-1} scale=${3:-1} chain=${4:-12,3+6,3.5}
cmake -S "$root" -B "$build" -G Ninja -DCMAKE_BUILD_TYPE=Release -DSPLATKIT_BUILD_BENCH=ON \
  -DSPLATKIT_BUILD_TESTS=OFF >/dev/null
ninja -C "$build" -j2 bench_outliers splat-synth >/dev/null
bench=$build/scripts/bench/bench_outliers
synth=$build/tools/splat-synth
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
n() { awk -v a="$1" -v s="$scale" 'BEGIN {printf "%d", a * s}'; }

"$synth" -q cad "$work/cad-lines.ply" -n "$(n 100000)" --scan-lines 4 --seed=1 --no-color
"$synth" -q torus "$work/torus-noisy.ply" -n "$(n 100000)" --random --noise 0.002 --seed=2 --no-color
"$synth" -q sphere "$work/sphere-30k.ply" -n "$(n 30000)" --random --noise 0.001 --seed=3 --no-color
"$synth" -q sphere "$work/sphere-300k.ply" -n "$(n 300000)" --random --noise 0.001 --seed=3 --no-color
"$synth" -q city "$work/city.ply" -n "$(n 200000)" --blocks 2 --seed=4 --no-color
"$synth" -q cad "$work/cad-lines-40k.ply" -n "$(n 40000)" --scan-lines 4 --seed=1 --no-color
"$synth" -q torus "$work/torus-noisy-40k.ply" -n "$(n 40000)" --random --noise 0.002 --seed=2 --no-color
"$synth" -q city "$work/city-50k.ply" -n "$(n 50000)" --blocks 2 --seed=4 --no-color
python3 "$root/scripts/bench/dem_to_xyz.py" "$root/data-samples/rainier-srtm.tif" "$work/rainier.xyz"

for scan in "cad --scan-lines 4:cad-lines.ply" "torus --random --noise 0.002:torus-noisy.ply" \
  "sphere --random --noise 0.001, 30k:sphere-30k.ply" "sphere --random --noise 0.001, 300k:sphere-300k.ply" \
  "city --blocks 2:city.ply" "cad --scan-lines 4, 40k:cad-lines-40k.ply" \
  "torus --random --noise 0.002, 40k:torus-noisy-40k.ply" "city --blocks 2, 50k:city-50k.ply" \
  "real terrain (data-samples/rainier-srtm.tif as points):rainier.xyz" \
  "real scan (data-samples/kitten.xyz):$root/data-samples/kitten.xyz" \
  "cad scan lines (data-samples/cad-scan.laz):$root/data-samples/cad-scan.laz"; do
  file=${scan##*:}
  [ "${file#/}" = "$file" ] && file=$work/$file
  "$bench" "${scan%%:*}" "$file" 1 "$k" "$sigma" "$work/cells.tsv" "$chain" | tee -a "$work/out.txt"
  echo
done

python3 - "$work/cells.tsv" "$k" "$sigma" <<'PY'
import collections, sys
cells = collections.defaultdict(list)
for line in open(sys.argv[1]):
    name, rule, k, par, found, lost = line.rstrip("\n").split("\t")
    key = f"{rule}:{k},{float(par):g}" if rule != "iter" else f"sor:{par}"
    cells[key].append((name, float(found), float(lost)))
ceiling = cells.pop("ceiling:0,1")
print(f"ceiling (share of the injected points 1 s or more from the scan, per scan): "
      + ", ".join(f"{f:.1f}" for _, f, _ in ceiling)
      + f"; >= 95 on {sum(f >= 95 for _, f, _ in ceiling)} of {len(ceiling)} scans")
def table(keys, title):
    nscans = len(next(iter(cells.values())))
    print(f"over all {nscans} scans: {title}")
    print("  cell                     injected removed: mean   min   scan removed: worst  (both goals on)")
    for key in keys:
        v = cells[key]
        print(f"  {key:<24} {sum(f for _, f, _ in v) / len(v):26.1f} {min(f for _, f, _ in v):5.1f}"
              f" {max(l for _, _, l in v):20.3f}  ({sum(f >= 95 and l <= 0.5 for _, f, l in v)} of {len(v)})")
ok = [key for key, v in cells.items() if max(l for _, _, l in v) <= 0.5]
table(sorted((key for key in ok if not key.startswith("sor:") or "+" not in key),
             key=lambda key: -sum(f for _, f, _ in cells[key]))[:8],
      "single-pass cells that remove <= 0.5 % of every scan, best mean first")
table(sorted((key for key in ok if "+" in key),
             key=lambda key: -sum(f for _, f, _ in cells[key]))[:12],
      "iterated cells (K1,SIGMA1+K2,SIGMA2[x2: 2 later passes]) that remove <= 0.5 % of every "
      "scan, best mean first")
table(sorted(cells, key=lambda key: (-sum(f >= 95 and l <= 0.5 for _, f, l in cells[key]),
                                      -sum(f for _, f, _ in cells[key])))[:8],
      "cells meeting both goals (>= 95 %, <= 0.5 %) on the most scans")
d = cells.get(f"sor:{int(sys.argv[2])},{float(sys.argv[3]):g}")
if d:
    worst = max(l for _, _, l in d)
    print(f"single pass sor:{sys.argv[2]},{sys.argv[3]}: injected removed {min(f for _, f, _ in d):.1f}-"
          f"{max(f for _, f, _ in d):.1f} % (goal >= 95: met on {sum(f >= 95 for _, f, _ in d)} of "
          f"{len(d)} scans), scan removed at most {worst:.3f} % (goal <= 0.5: "
          f"{'met' if worst <= 0.5 else 'NOT met'})")
PY
echo "passes sor:$chain through find_outliers, per scan (injected removed %, scan removed %):"
grep '^passes' "$work/out.txt" |
  sed 's/.*removes \([0-9.]*\) % of the injected points, \([0-9.]*\) % of the scan.*/\1 \2/' |
  awk '{ printf "  %s/%s", $1, $2; f = NR == 1 || $1 < f ? $1 : f; l = $2 > l ? $2 : l; s += $1 }
       END { printf "\n  mean %.1f %%, min %.1f %% of the injected points; at most %.3f %% of a scan\n", s / NR, f, l }'
echo "the same on each scan alone, without injected points (share of the clean scan removed):"
grep '^clean scan' "$work/out.txt" | sed 's/^clean scan /  /; s/ (no injected points)//'

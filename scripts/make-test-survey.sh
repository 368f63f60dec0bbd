#!/usr/bin/env bash
# A small survey as a tiled workflow gets it: a CAD part and a torus side by side (i.i.d. samples,
# metres: the parts 10 m across), cut along two slanted lines into four LAZ files
# OUT_DIR/scans/scan0..3.laz (1 mm scale). Used by tests/e2e/workflow.sh and
# scripts/test-cluster.sh.
# usage: scripts/make-test-survey.sh OUT_DIR BIN_DIR [POINTS (total, default 40000)]
set -euo pipefail
out=${1:?usage: make-test-survey.sh OUT_DIR BIN_DIR [POINTS]}
bin=${2:?usage: make-test-survey.sh OUT_DIR BIN_DIR [POINTS]}
points=${3:-40000}
mkdir -p "$out/scans"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
"$bin/splat-synth" -q cad "$tmp/cad.xyz" -n $((points * 3 / 5)) --random --no-color
"$bin/splat-synth" -q torus "$tmp/torus.xyz" -n $((points * 2 / 5)) --random --no-color
python3 - "$tmp" <<'PY'
import sys
tmp = sys.argv[1]
files = [open("%s/scan%d.xyz" % (tmp, k), "w") for k in range(4)]
for name, dx in (("cad", 0.0), ("torus", 3.2)):
    for l in open("%s/%s.xyz" % (tmp, name)):
        if not l.strip() or l[0] == "#": continue
        x, y, z = (10 * float(v) for v in l.split()[:3])
        x += 10 * dx
        u, v = x + 0.3 * y, y - 0.2 * x
        files[(u > 17) * 2 + (v > -3)].write("%.4f %.4f %.4f\n" % (x, y, z))
PY
for k in 0 1 2 3; do
  "$bin/splat-convert" -q --columns x,y,z "$tmp/scan$k.xyz" "$out/scans/scan$k.laz"
done

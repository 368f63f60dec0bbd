#!/usr/bin/env bash
# Makes the scan test set: scenes with known reference normals for normal-orientation tests
# (city, terrain, facade, cad, their -scan / -noisy / -scan-noisy variants, city-utm, and the
# real scans building and ball), one PLY per scene plus scenes.json, in OUT_DIR. Byte-identical on
# every run (fixed seeds). The scenes and the PLY layout: data-samples/README.md ("Scan test set")
# and scripts/make_scan_scenes.py, which makes them (/usr/bin/python3 with numpy; as root this
# script installs python3-numpy when it is missing). The cad scene is splat-synth's own when
# BIN_DIR has it, else the same part sampled in Python. The real scans come from Debian's
# libcgal-demo package (downloaded into a temp dir with apt-get download, not installed); without
# it they are skipped.
#
#   scripts/make-scan-set.sh OUT_DIR [BIN_DIR]   # BIN_DIR: where splat-synth is (default:
#                                                # build/tools, else the first build-*/tools)
#   SCAN_SET_SCALE=0.1 scripts/make-scan-set.sh OUT_DIR   # every point count times 0.1
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)

usage() { sed -n '2,14p' "${BASH_SOURCE[0]}"; }
case ${1:-} in -h | --help) usage; exit 0 ;; esac
if [[ $# -lt 1 || $# -gt 2 ]]; then usage >&2; exit 1; fi
out=$1
bin=${2:-}
scale=${SCAN_SET_SCALE:-1}
if ! awk -v s="$scale" 'BEGIN { exit !(s + 0 > 0 && s + 0 <= 100) }'; then
  echo "make-scan-set: SCAN_SET_SCALE must be a number in (0, 100], not '$scale'" >&2
  exit 1
fi

python=/usr/bin/python3
if ! "$python" -c 'import numpy' 2> /dev/null; then
  if [[ $(id -u) -ne 0 ]]; then
    echo "make-scan-set: $python has no numpy; install it (apt-get install python3-numpy)" >&2
    exit 1
  fi
  echo "make-scan-set: installing python3-numpy" >&2
  DEBIAN_FRONTEND=noninteractive apt-get install -y -qq --no-install-recommends python3-numpy \
    > /dev/null
fi

if [[ -z $bin ]]; then
  for candidate in "$top/build/tools" "$top"/build-*/tools; do
    if [[ -x $candidate/splat-synth ]]; then bin=$candidate; break; fi
  done
fi
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
args=("$out" --scale "$scale")

if [[ -n $bin && -x $bin/splat-synth ]]; then
  args+=(--splat-synth "$bin/splat-synth")
else
  echo "make-scan-set: no splat-synth found (build it or pass BIN_DIR); the cad scenes are" \
    "sampled in Python" >&2
fi

# The real scans: CGAL's demo data set, in Debian's libcgal-demo (not installed, only unpacked).
if version=$("$top/scripts/fetch-cgal-scans.sh" "$tmp/cgal"); then
  args+=(--cgal-dir "$tmp/cgal" --cgal-package "libcgal-demo $version")
else
  echo "make-scan-set: could not get Debian's libcgal-demo; skipping the real scans" \
    "(building, ball)" >&2
fi

"$python" "$top/scripts/make_scan_scenes.py" "${args[@]}"

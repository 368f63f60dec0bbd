#!/usr/bin/env bash
# Puts CGAL's two real point sets with reference normals, data/points_3/building.ply (a 100k-point
# photogrammetry building: x y z nx ny nz segment_index) and ball.ply, into DIR, from Debian's
# libcgal-demo package (downloaded with apt-get download and unpacked, not installed; as root an
# 'apt-get update' is tried when the download fails). Prints the package's version. Exit 1 when the
# package cannot be had. Used by scripts/make-scan-set.sh and scripts/demo.sh.
#   scripts/fetch-cgal-scans.sh DIR
set -euo pipefail
dir=${1:?usage: fetch-cgal-scans.sh DIR}
mkdir -p "$dir"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
(cd "$tmp" && apt-get download libcgal-demo > /dev/null 2>&1) ||
  { [[ $(id -u) -eq 0 ]] && apt-get update -qq > /dev/null 2>&1 &&
    (cd "$tmp" && apt-get download libcgal-demo > /dev/null 2>&1); } || exit 1
dpkg -x "$tmp"/libcgal-demo_*.deb "$tmp/deb"
tar -xzf "$tmp/deb/usr/share/doc/libcgal-demo/data.tar.gz" -C "$tmp" \
  data/points_3/building.ply data/points_3/ball.ply
mv "$tmp/data/points_3/building.ply" "$tmp/data/points_3/ball.ply" "$dir/"
dpkg-deb -f "$tmp"/libcgal-demo_*.deb Version

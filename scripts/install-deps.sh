#!/usr/bin/env bash
# Installs the Debian 12 packages splatkit needs, only those missing. Idempotent; quiet when
# everything is there. Needs root (or sudo) only when something must be installed.
set -euo pipefail

packages=(
  cmake ninja-build g++ clang libclang-rt-14-dev pkg-config
  libgtest-dev libgmock-dev
  libpcl-dev libcgal-dev libeigen3-dev libtbb-dev libnanoflann-dev
  libopenimageio-dev openimageio-tools libopenexr-dev libopencv-dev
  libcli11-dev nlohmann-json3-dev zlib1g-dev
  snakemake help2man man-db
  libcpp-httplib-dev chromium nodejs curl jq
)
# snakemake: the workflow engine of workflows/Snakefile (tiled surveys; e2e.workflow runs it).
# libcpp-httplib-dev: splat-view --serve's HTTP server. chromium, nodejs, curl, jq: the viewer's
# tests (headless Chromium with software GL, driven over the DevTools protocol by a Node.js
# script).
# help2man, man-db: the tools' man pages, made at build time and rendered by a test.
# pcl-tools: PCL's own command-line tools, the peers of some benchmarks.
[ "${SPLATKIT_BENCH_DEPS:-0}" = 1 ] && packages+=(pcl-tools)

missing=()
for p in "${packages[@]}"; do
  status=$(dpkg-query -W -f='${Status}' "$p" 2>/dev/null || true)
  [ "$status" = "install ok installed" ] || missing+=("$p")
done
[ ${#missing[@]} -eq 0 ] && exit 0

echo "install-deps: installing ${missing[*]}" >&2
sudo=()
[ "$(id -u)" -eq 0 ] || sudo=(sudo)
export DEBIAN_FRONTEND=noninteractive
"${sudo[@]}" apt-get update -qq
"${sudo[@]}" apt-get install -y -qq --no-install-recommends "${missing[@]}" >/dev/null
echo "install-deps: done" >&2

#!/usr/bin/env bash
# The browser viewer's frame rate: a Sequential Point Tree of at least 5 M entries (splat-synth's
# CAD part, 3.5 M points, build-spt at its defaults) served by splat-view --serve and drawn in
# headless Chromium with software GL (SwiftShader) at WIDTHxHEIGHT from the default view, for
# each blending mode: botsch (three passes, [Botsch05] in docs/references.md) and zbuffer (one pass, no
# blending), the page's default for a file this large marked "(default)". The page draws one
# frame per animation frame for 5 s, turning the camera (a moving camera: the z-buffer pass culls
# back faces, backfaces=auto; the same run with backfaces=show, every back face drawn, is printed
# too), and reports frames/s; the frame's fixed cost (clearing,
# shading, compositing) is shown by the same run at a distance where one entry is drawn. Prints
# the CPU model and the load average (before each run): SwiftShader runs on the CPU, and other
# work on the machine lowers the figures.
# usage: scripts/bench/viewer-fps.sh [points=3500000] [width=1280] [height=720]
#        (build dir: $BUILD_DIR, default build)
# Goal: >= 20 frames/s at 1280x720 for a 5M-entry .spt in software GL, in the default mode.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build}
ninja -C "$build" -j2 build-spt splat-view splat-synth >/dev/null
bin=$build/tools
n=${1:-3500000} width=${2:-1280} height=${3:-720}
work=$(mktemp -d)
server=
cleanup() { [ -n "$server" ] && kill "$server" 2>/dev/null; rm -rf "$work"; }
trap cleanup EXIT
"$bin/splat-synth" -q cad "$work/in.ply" -n "$n" --no-color
"$bin/build-spt" -q "$work/in.ply" "$work/model.spt"
rm "$work/in.ply"
"$bin/splat-info" "$work/model.spt" | grep -E '^Entries'
"$bin/splat-view" --serve "$work/model.spt" --port 0 >"$work/serve.out" &
server=$!
for _ in $(seq 100); do grep -q http "$work/serve.out" && break; sleep 0.05; done
url=$(grep -o 'http://127\.0\.0\.1:[0-9]*/' "$work/serve.out")
echo "CPU: $(lscpu | sed -n 's/^Model name: *//p'), $(nproc) cores; load average $(cut -d' ' -f1-3 /proc/loadavg)"
# Runs: LABEL|URL options|with the empty frame (1) or the default view alone (0).
for run in "zbuffer|blend=zbuffer|1" "zbuffer-show|blend=zbuffer&backfaces=show|0" \
           "botsch|blend=botsch|1"; do
  IFS='|' read -r label options empty <<<"$run"
  views=("")
  [ "$empty" = 1 ] && views+=("&view=35,25,1000000")
  for view in "${views[@]}"; do
    load=$(cut -d' ' -f1 /proc/loadavg)
    r=$(node "$root/tests/viewer/drive_chromium.mjs" --width "$width" --height "$height" \
          --url "${url}#file=model.spt&hud=0&$options$view" --bench 5000 --timeout 300)
    node -e '
      const r = JSON.parse(process.argv[1]);
      const b = r.bench;
      const mode = process.argv[2] + (b.default_blend === process.argv[2] ? " (default)" : "");
      console.log(`${mode.padEnd(18)} ${process.argv[3] ? "empty frame " : "default view"}: ` +
                  `${b.fps.toFixed(1)} frames/s (${b.ms_per_frame.toFixed(1)} ms), ` +
                  `${b.splats} of ${b.entries} entries submitted, ${b.width}x${b.height}, ` +
                  `load ${process.argv[4]}, ${r.gl}`);' \
      "$r" "$label" "$view" "$load"
  done
done

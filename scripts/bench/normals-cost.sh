#!/usr/bin/env bash
# The default estimate-normals whole command against a reference build of it (e.g. one from before
# a change), on an i.i.d. torus: both run by turns (ref, ours, ref, ours, ...) so that a shared or
# throttled machine slows both alike; prints the medians of the whole commands' wall times, the
# ratio ours / ref, the median of each phase from their --report, and the CPU model.
# usage: scripts/bench/normals-cost.sh REF_BIN [points] [threads] [runs] [estimate-normals options...]
#   REF_BIN: the reference estimate-normals binary (or $REF_BIN when the argument is '-'); it must
#   read .xyz and write .splk. Ours: $BUILD_DIR/tools/estimate-normals (default build/; built here
#   with splat-synth). Defaults: 1000000 points, 2 threads, 5 runs each. Exits 1 when the ratio is
#   above $MAX_RATIO (default 1.3).
# e.g. git worktree add /tmp/ref d7e636d && cmake -S /tmp/ref -B /tmp/ref/build -G Ninja \
#        -DCMAKE_BUILD_TYPE=Release && ninja -C /tmp/ref/build estimate-normals
#      scripts/bench/normals-cost.sh /tmp/ref/build/tools/estimate-normals
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build}
ref=${1:?usage: normals-cost.sh REF_BIN [points] [threads] [runs] [options...]}
[ "$ref" = - ] && ref=${REF_BIN:?REF_BIN is not set}
points=${2:-1000000} threads=${3:-2} runs=${4:-5}
shift $(($# < 4 ? $# : 4))
max_ratio=${MAX_RATIO:-1.3}
[ -x "$ref" ] || { echo "normals-cost.sh: $ref: not an executable" >&2; exit 1; }
cmake --build "$build" -j "${SPLATKIT_JOBS:-2}" --target estimate-normals splat-synth >/dev/null
ours=$build/tools/estimate-normals
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$build/tools/splat-synth" -q torus "$work/torus.xyz" -n "$points" --random

# run NAME BIN [options...]: one whole command; its wall time (ms) is appended to $work/NAME.t and
# its phase times to $work/NAME.phases.
run() {
  local name=$1 bin=$2 t0 t1
  shift 2
  t0=$(date +%s%N)
  "$bin" -q --threads "$threads" "$work/torus.xyz" "$work/$name.splk" --report "$work/$name.json" "$@"
  t1=$(date +%s%N)
  echo "$(((t1 - t0) / 1000000))" >> "$work/$name.t"
  python3 -c 'import json, sys
r = json.load(open(sys.argv[1]))
print(" ".join(f"{k}={v}" for k, v in r["timings_s"].items()))' "$work/$name.json" >> "$work/$name.phases"
}
for _ in $(seq "$runs"); do
  run ref "$ref" "$@"
  run ours "$ours" "$@"
done

python3 - "$work" "$max_ratio" "$points" "$threads" "$runs" "$(grep -m1 'model name' /proc/cpuinfo |
  cut -d: -f2 | sed 's/^ *//')" <<'EOF'
import statistics as st, sys
work, max_ratio, points, threads, runs, cpu = sys.argv[1:7]
def times(name):
    return [int(l) / 1000 for l in open(f"{work}/{name}.t")]
def phases(name):
    rows = [dict((k, float(v)) for k, v in (p.split("=") for p in l.split()))
            for l in open(f"{work}/{name}.phases")]
    return {k: st.median(r[k] for r in rows if k in r) for k in rows[0]}
ref, ours = times("ref"), times("ours")
r, o = st.median(ref), st.median(ours)
print(f"estimate-normals whole command, i.i.d. torus of {points} points, --threads {threads}, "
      f"{runs} runs each by turns; CPU: {cpu}")
print(f"  ref  runs (s): {' '.join(f'{t:.2f}' for t in ref)}  median {r:.3f}")
print(f"  ours runs (s): {' '.join(f'{t:.2f}' for t in ours)}  median {o:.3f}")
print(f"  ratio ours / ref: {o / r:.2f} (target <= {max_ratio})")
pr, po = phases("ref"), phases("ours")
print("  phase medians (s, from --report):")
for k in sorted(set(pr) | set(po), key=lambda k: -max(pr.get(k, 0), po.get(k, 0))):
    print(f"    {k:18s} {pr.get(k, float('nan')):8.3f} {po.get(k, float('nan')):8.3f}")
sys.exit(0 if o / r <= float(max_ratio) else 1)
EOF

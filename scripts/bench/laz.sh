#!/usr/bin/env bash
# LAZ decoding: splatkit's LASzip decoder against NATIVE laz-perf and LASzip, both built from
# source (Release), by turns in one run. Input: splat-synth cad with scan lines, colours and
# intensity as a scanner records them (--texture), written as LAZ by splat-convert in point
# format 2 (LASzip's point-wise chunks) and 7 (LAS 1.4, layered chunks), 50 000 points a chunk.
# Each harness reads the whole file into memory, allocates and touches the output records
# (N x record length bytes) before its clock starts, and times decoding only; each prints a
# checksum of the records, and the three must agree (the same bytes):
#   splatkit (scripts/bench/src/bench_laz_splatkit.cpp): read_laz_points as splat-convert calls
#     it (chunk table, every check, runs of chunks decoded in parallel in a TBB pipeline while
#     earlier runs go to the sink in order); the sink copies each run into the output; THREADS
#     is TBB's parallelism.
#   laz-perf 3.4 (bench_laz_lazperf.cpp): decompress_chunk_table, then one
#     lazperf::reader::chunk_decompressor per chunk writing straight into the output; THREADS
#     std::threads take chunks from a shared counter.
#   LASzip 3.5.1 (bench_laz_laszip.cpp): LASreadPoint over a ByteStreamInArrayLE (what
#     laszip_dll.cpp drives) reading items straight into the output; LASzip has no per-chunk
#     decompressor, so for 2 threads each thread has its own reader, seeks (by the chunk table)
#     to its half of the chunks and reads them in order.
#   whole:   splat-convert -q --threads T IN.laz OUT.splk (the whole command, wall time),
#     compared with laz-perf's decode-only rate at the same thread count.
# Per format (2, 7) and thread count (1, 2): the medians of the runs (all programs of a turn run
# one after the other, turn after turn) in M points/s and the ratios. Exits 1 when a goal is
# missed: decoding >= 1.3x laz-perf at 1 and 2 threads, the whole command >= 0.8x laz-perf's
# decode-only rate.
# usage: scripts/bench/laz.sh [points=3000000] [runs=5]
#   build dir: $BUILD_DIR (default build/, configured with -DSPLATKIT_BUILD_BENCH=ON);
#   peers: built once into $LAZ_PEERS_DIR (default build-bench/peers) from the git repositories
#   $LAZ_PERF_GIT (default https://github.com/hobuinc/laz-perf, tag 3.4.0) and $LASZIP_GIT
#   (default https://github.com/LASzip/LASzip, master at ac3e9e9, 3.5.1); a local clone or
#   mirror works too.
set -euo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
build=${BUILD_DIR:-$root/build}
points=${1:-3000000} runs=${2:-5}
peers=${LAZ_PEERS_DIR:-$root/build-bench/peers}
ninja -C "$build" -j2 splat-synth splat-convert bench_laz_splatkit >/dev/null
bin=$build/tools
ours=$build/scripts/bench/bench_laz_splatkit

# peer NAME GIT REF CMAKE-OPTIONS...: clones and builds a peer (Release) into $peers/NAME once.
peer() {
  local name=$1 git=$2 tag=$3 dir=$peers/$1
  shift 3
  if [ ! -f "$dir/.built-$tag" ]; then
    rm -rf "$dir" && mkdir -p "$dir"
    git clone -q "$git" "$dir/src"
    git -C "$dir/src" -c advice.detachedHead=false checkout -q "$tag"
    cmake -S "$dir/src" -B "$dir/build" -G Ninja -DCMAKE_BUILD_TYPE=Release \
      -DCMAKE_INSTALL_PREFIX="$dir/install" -DCMAKE_INSTALL_LIBDIR=lib "$@" >"$dir/cmake.log"
    ninja -C "$dir/build" -j2 install >"$dir/build.log" ||
      { tail -20 "$dir/build.log"; echo "laz.sh: building $name failed ($dir/build.log)"; exit 1; }
    touch "$dir/.built-$tag"
  fi
}
peer laz-perf "${LAZ_PERF_GIT:-https://github.com/hobuinc/laz-perf}" 3.4.0 -DWITH_TESTS=OFF
# LASzip: its master of 2026-05-05 (3.5.1): the 3.5.0 tag's build compiles its C++17 sources
# as C++11 and fails.
peer LASzip "${LASZIP_GIT:-https://github.com/LASzip/LASzip}" ac3e9e9f954427872c8c77b68b7766cf706322f9
src=$root/scripts/bench/src
mkdir -p "$peers/bin"
cxx=${CXX:-c++}
# The harnesses with the peers' own Release flags (-O3 -DNDEBUG), linked to their libraries.
"$cxx" -O3 -DNDEBUG -std=c++17 -I"$src" -I"$peers/laz-perf/install/include" \
  "$src/bench_laz_lazperf.cpp" -o "$peers/bin/bench_laz_lazperf" \
  -L"$peers/laz-perf/install/lib" -Wl,-rpath,"$peers/laz-perf/install/lib" -llazperf -pthread
"$cxx" -O3 -DNDEBUG -std=c++17 -DUNORDERED -DHAVE_UNORDERED_MAP=1 -I"$src" \
  -I"$peers/LASzip/src/src" -I"$peers/LASzip/src/include/laszip" \
  "$src/bench_laz_laszip.cpp" -o "$peers/bin/bench_laz_laszip" \
  -L"$peers/LASzip/install/lib" -Wl,-rpath,"$peers/LASzip/install/lib" -llaszip -pthread

work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin/splat-synth" -q cad "$work/in.ply" -n "$points" --scan-lines 4 --seed=1 --texture
"$bin/splat-convert" -q "$work/in.ply" "$work/in2.laz"
"$bin/splat-convert" -q --las-format 7 "$work/in.ply" "$work/in7.laz"
rm "$work/in.ply"
echo "input: $points points (textured colours, intensity): format 2 $(stat -c%s "$work/in2.laz")" \
  "bytes LAZ, format 7 $(stat -c%s "$work/in7.laz") bytes LAZ; $runs runs by turns"
grep -m1 'model name' /proc/cpuinfo | sed 's/^model name\s*: /CPU: /'
echo "cores: $(nproc); $(uptime | sed 's/.*load/load/') (before)"

now() { date +%s.%N; }
: >"$work/times"
for r in $(seq "$runs"); do
  for f in 2 7; do
    for t in 1 2; do
      for h in "$ours" "$peers/bin/bench_laz_lazperf" "$peers/bin/bench_laz_laszip"; do
        "$h" "$work/in$f.laz" "$t" | awk -v f="$f" -v t="$t" '{ print f, t, $1, $3, $4 }' >>"$work/times"
      done
      t0=$(now)
      "$bin/splat-convert" -q --threads "$t" "$work/in$f.laz" "$work/out.splk"
      echo "$f $t whole $(awk -v a="$t0" -v b="$(now)" 'BEGIN { print b - a }') -" >>"$work/times"
    done
  done
done
echo "$(uptime | sed 's/.*load/load/') (after)"
# The range decoder's serial chain alone (scripts/bench/src/laz_floor.cpp, formats/laz.md), timed
# on random bytes for the operations a point of the format 2 input takes (15.84 symbols of tabled
# models and 3.52 raw reads, counted once with counters in ArithmeticDecoder at 3 M points): an
# estimate of the least time a decoder that runs one chain per chunk needs, not a bound.
"$cxx" -O3 -std=c++20 -I"$root/lib" "$src/laz_floor.cpp" -o "$work/laz_floor"
"$work/laz_floor" 15.84 3.52 2
python3 - "$work/times" "$points" <<'PY'
import statistics, sys
times, checks = {}, {}
for line in open(sys.argv[1]):
    f, t, name, s, check = line.split()
    times.setdefault((f, t, name), []).append(float(s))
    if check != '-':
        checks.setdefault((f, t), set()).add(check)
n = int(sys.argv[2])
rate = lambda k: n / statistics.median(times[k]) / 1e6
ok = True
print('format threads | M points/s: splatkit laz-perf LASzip | splatkit/laz-perf splatkit/LASzip'
      ' | whole splat-convert M points/s, /laz-perf decode')
for f in ('2', '7'):
    for t in ('1', '2'):
        if len(checks[(f, t)]) != 1:
            print(f'format {f}, {t} threads: the decoders give different records', checks[(f, t)])
            sys.exit(1)
        s, l, z, w = (rate((f, t, k)) for k in ('splatkit', 'laz-perf', 'LASzip', 'whole'))
        print(f'{f:>6} {t:>7} | {s:8.2f} {l:8.2f} {z:6.2f} | {s / l:16.2f}x {s / z:14.2f}x'
              f' | {w:6.2f} {w / l:5.2f}x')
        ok = ok and s / l >= 1.3 and w / l >= 0.8
for f in ('2', '7'):
    a, b = (rate((f, t, 'splatkit')) / rate((f, t, 'laz-perf')) for t in ('1', '2'))
    print(f'format {f}: second thread gains splatkit {rate((f, "2", "splatkit")) / rate((f, "1", "splatkit")):.2f}x,'
          f' laz-perf {rate((f, "2", "laz-perf")) / rate((f, "1", "laz-perf")):.2f}x,'
          f' LASzip {rate((f, "2", "LASzip")) / rate((f, "1", "LASzip")):.2f}x')
print('goals (decoding >= 1.3x laz-perf on 1 and 2 threads; whole command >= 0.8x laz-perf decode):',
      'met' if ok else 'MISSED')
sys.exit(0 if ok else 1)
PY

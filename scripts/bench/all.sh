#!/usr/bin/env bash
# Runs the benchmarks that compare a splatkit tool with a peer (PCL, nanoflann, OpenCV, laz-perf,
# a naive splatter, the original qsplat_make, PotreeConverter when installed) and writes
# docs/benchmarks.md: the machine, the CPU model, and per tool the command, date and output of
# each bench.
#
# usage: scripts/bench/all.sh [--full] [--page] [NAME...]
#   NAME: knn normals graph segmentation io laz qsplat spt ham render (default: all of them)
#   Sizes are small by default (the set ran in about 3 minutes on 2 busy cores, the bench
#   programs already built); --full gives each script its own defaults (much longer).
#   Each bench's result is kept in $RESULTS (default $BUILD_DIR/bench-results) as NAME.log with
#   its command, date and exit code; the page is made from every result kept there, so benches run
#   at different times appear with their own dates, and a bench never run says so.
#   BUILD_DIR (default build-bench, as the scripts) is passed on to every script; with an existing
#   build directory the bench programs are added to it (-DSPLATKIT_BUILD_BENCH=ON).
#   --page writes the page from the results kept, running nothing.
#   TIMEOUT (seconds, default 900) stops a bench that runs longer; its page entry says so.
set -uo pipefail
root=$(cd "$(dirname "$0")/../.." && pwd)
export BUILD_DIR=${BUILD_DIR:-$root/build-bench}
results=${RESULTS:-$BUILD_DIR/bench-results}
page=${PAGE:-$root/docs/benchmarks.md}
timeout_s=${TIMEOUT:-900}
full=0
names=()
for a in "$@"; do
  case $a in
    --full) full=1 ;;
    --page) names+=(-) ;;
    -h|--help) awk 'NR > 1 && !/^#/ { exit } NR > 1 { sub(/^# ?/, ""); print }' "$0"; exit 0 ;;
    *) names+=("$a") ;;
  esac
done

# NAME|TOOL|PEER|SCRIPT|QUICK ARGUMENTS|WHY IT MAY NOT RUN
benches=(
  "knn|spatial index (estimate-normals, build-splat-graph)|nanoflann 1.4.3, PCL KdTreeFLANN|knn.sh|200000 16 2 2|"
  "normals|estimate-normals|PCL NormalEstimationOMP|normals.sh|200000 16 2 2|"
  "graph|build-splat-graph|PCL KdTreeFLANN radius search|graph.sh|200000 2 2|"
  "segmentation|segment-surfaces|PCL RegionGrowing on CGAL's building scan|segmentation-real.sh|2|needs the CGAL sample scans (scripts/fetch-cgal-scans.sh, network)"
  "io|reading PLY (splat-convert, splat-info)|PCL PLYReader|io.sh|1000000 2|"
  "laz|reading LAZ (splat-convert, splat-info)|native laz-perf 3.4 and LASzip 3.5.1, built from source|laz.sh|3000000 5|needs their git repositories (LAZ_PERF_GIT, LASZIP_GIT: a clone, a mirror or network) and a build dir configured with -DSPLATKIT_BUILD_BENCH=ON"
  "qsplat|build-qsplat|the original qsplat_make (QSPLAT_MAKE, when built)|qsplat.sh|500000 2 2|"
  "spt|build-spt|PotreeConverter 2 (when installed)|spt.sh|500000 2 1|"
  "ham|build-ham|OpenCV Sobel passes|ham.sh|2048 2 2 4096|"
  "render|splat-view|a naive two-pass software splatter|render.sh|200000 2 3 2 8|"
)
[ ${#names[@]} -gt 0 ] || for b in "${benches[@]}"; do names+=("${b%%|*}"); done

mkdir -p "$results"
# Some scripts configure BUILD_DIR with SPLATKIT_BUILD_TESTS=OFF; a build directory that had the
# tests gets them back after each bench (laz.sh needs one of them, and ctest the rest).
tests_on=0
grep -q '^SPLATKIT_BUILD_TESTS:BOOL=ON' "$BUILD_DIR/CMakeCache.txt" 2>/dev/null && tests_on=1
for b in "${benches[@]}"; do
  IFS='|' read -r name tool peer script quick why <<<"$b"
  [[ " ${names[*]} " == *" $name "* ]] || continue
  args=$quick
  [ $full = 1 ] && args=""
  cmd="scripts/bench/$script${args:+ $args}"
  echo "== $name: $cmd" >&2
  start=$(date +%s)
  # shellcheck disable=SC2086
  (cd "$root" && timeout "$timeout_s" bash "scripts/bench/$script" $args) >"$results/$name.out" 2>&1
  code=$?
  {
    echo "command: $cmd"
    echo "date: $(date -u '+%Y-%m-%d %H:%M UTC')"
    echo "exit: $code"
    echo "seconds: $(($(date +%s) - start))"
    echo "load: $(cut -d' ' -f1-3 /proc/loadavg)"
  } >"$results/$name.meta"
  tail -5 "$results/$name.out" >&2
  if [ $tests_on = 1 ] && ! grep -q '^SPLATKIT_BUILD_TESTS:BOOL=ON' "$BUILD_DIR/CMakeCache.txt"; then
    cmake -B "$BUILD_DIR" -DSPLATKIT_BUILD_TESTS=ON >/dev/null
  fi
done

# The page.
cpu=$(lscpu | sed -n 's/^Model name: *//p' | head -1)
cores=$(nproc)
mem=$(free -g | awk '/^Mem:/ { print $2 " GiB" }')
kernel=$(uname -sr)
{
  echo "# Benchmarks"
  echo
  echo "Each splatkit tool against its peer, as measured by \`scripts/bench/all.sh\` (which runs the"
  echo "scripts of \`scripts/bench/\` at small sizes; \`--full\` uses each script's own sizes). Every"
  echo "figure below is a bench's own output, with the command, date and load it was taken at."
  echo "This page is generated: run \`BUILD_DIR=build scripts/bench/all.sh [NAME...]\` to renew it."
  echo
  echo "Machine: $cpu, $cores logical CPUs seen, $mem of memory, $kernel. The machine is shared:"
  echo "the load average at the start of each bench is given; times vary from run to run by"
  echo "10–30 %, so compare the ratios printed beside each pair, not absolute times across pages."
  echo "Measurements taken before this page existed, with their own conditions, are kept in"
  echo "[design/](design/README.md)."
  echo
  echo "| tool | peer | bench | run |"
  echo "|---|---|---|---|"
  for b in "${benches[@]}"; do
    IFS='|' read -r name tool peer script quick why <<<"$b"
    if [ -f "$results/$name.meta" ]; then
      code=$(sed -n 's/^exit: //p' "$results/$name.meta")
      when=$(sed -n 's/^date: //p' "$results/$name.meta")
      if [ "$code" = 0 ]; then state="$when"
      elif [ "$code" = 124 ]; then state="stopped after ${timeout_s} s ($when)"
      elif [ "$code" = 1 ]; then state="$when; exit 1: a goal the script checks was missed"
      else state="failed, exit $code ($when)"; fi
      if grep -Eqi '^(peer|PotreeConverter[^:]*|laz-perf): (qsplat_make )?not (found|installed)' "$results/$name.out"; then
        state="$state; peer not installed here: splatkit's side only"
      fi
    else
      state="not run${why:+: $why}"
    fi
    echo "| [$tool](#$name) | $peer | \`$script\` | $state |"
  done
  for b in "${benches[@]}"; do
    IFS='|' read -r name tool peer script quick why <<<"$b"
    echo
    echo "<a id=\"$name\"></a>"
    echo
    echo "## $tool"
    echo
    echo "Peer: $peer. What the bench measures: the header of [\`scripts/bench/$script\`](../scripts/bench/$script)."
    echo
    if [ ! -f "$results/$name.meta" ]; then
      echo "Not run for this page${why:+ ($why)}. Command: \`scripts/bench/$script $quick\`."
      continue
    fi
    echo "Command: \`$(sed -n 's/^command: //p' "$results/$name.meta")\`, run"
    echo "$(sed -n 's/^date: //p' "$results/$name.meta"), load $(sed -n 's/^load: //p' "$results/$name.meta"),"
    echo "exit $(sed -n 's/^exit: //p' "$results/$name.meta"), $(sed -n 's/^seconds: //p' "$results/$name.meta") s."
    echo
    echo '```text'
    # The bench's report; the build's and the tools' progress lines left out.
    grep -v -E '^\[[0-9]+/[0-9]+\]|^ninja:|^-- |^\*\* WARNING \*\*|: [0-9]+ (points|splats|samples|triangles) in ' \
      "$results/$name.out" | tail -60
    echo '```'
  done
} >"$page"
echo "wrote $page" >&2

#!/usr/bin/env bash
# The whole test suite in one command: installs what is missing, builds, runs ctest.
#  1. Release build (build/): unit tests, end-to-end tests on the real binaries.
#  2. clang + AddressSanitizer + UndefinedBehaviorSanitizer build (build-asan/): the same tests
#     again (e2e.max_memory on smaller clouds: the peak RSS is checked in stage 1 only), plus a
#     short libFuzzer run of every reader over its seed corpus. Line tables are all the debug
#     information the sanitizers' reports need (file:line), and they build faster.
# ctest starts the slowest tests first (their COST in tests/CMakeLists.txt), so that a fresh
# build directory does not end a stage with one core idle behind the last long test.
# Each stage prints its time; the end, the 10 slowest tests of each stage.
# SPLATKIT_TEST_SANITIZE=0 skips stage 2. Works from any directory.
# SPLATKIT_SIMD=portable|sse2|avx2|avx512 caps the vector code of every kernel for the whole suite
# (docs/design/spatial-index.md); the tests that compare vector paths run at each level up to the
# cap that the CPU has and skip the others loudly. The summary lines say which levels ran.
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$top/scripts/install-deps.sh"
jobs=${SPLATKIT_JOBS:-$(nproc)}

# simd_summary LOG: the SIMD levels this CPU offers, the cap, and per level how many of the
# level-parametrised tests (named .../portable, .../avx2, ...) passed, failed or were skipped.
simd_summary() {
  local flags offers="portable"
  flags=$(grep -m1 '^flags' /proc/cpuinfo 2>/dev/null || true)
  for f in sse2 avx2 avx512f; do
    [[ " $flags " == *" $f "* ]] && offers+=" ${f%f}"
  done
  echo "SIMD: this CPU offers: $offers; SPLATKIT_SIMD=${SPLATKIT_SIMD:-(unset)}"
  for level in portable sse2 avx2 avx512; do
    printf '  %-8s %3d passed, %3d failed, %3d skipped\n' "$level" \
      "$(grep -cE "Test +#[0-9]+: [^ ]+/$level .*Passed" "$1" || true)" \
      "$(grep -cE "Test +#[0-9]+: [^ ]+/$level .*(Failed|Exception|Timeout)" "$1" || true)" \
      "$(grep -cE "Test +#[0-9]+: [^ ]+/$level .*Skipped" "$1" || true)"
  done
}

# laz-perf (LASzip compiled to WebAssembly, from the npm registry) is the LAZ tests' oracle; it
# goes into each build dir's node/ (SPLATKIT_LAZ_PERF_DIR's default). Without node or the
# registry the LAZ comparisons are skipped with a message.
install_laz_perf() {
  [ -d "$1/node/node_modules/laz-perf" ] && return 0
  if ! command -v npm >/dev/null; then
    echo "note: npm not found; the laz-perf comparisons will be skipped"
    return 0
  fi
  mkdir -p "$1/node"
  npm install --silent --no-audit --no-fund --prefix "$1/node" laz-perf@0.0.7 >/dev/null 2>&1 ||
    echo "note: npm could not install laz-perf; the laz-perf comparisons will be skipped"
}

# slowest LOG LABEL: the 10 tests of a ctest log that took longest (where CI's time goes).
slowest() {
  echo "10 slowest tests ($2):"
  grep -E 'Test +#[0-9]+: ' "$1" | sed -E 's/.*Test +#[0-9]+: ([^ ]+).* ([0-9.]+) sec$/\2 \1/' |
    sort -rn | head -10 | awk '{ printf "  %8.2f s  %s\n", $1, $2 }' || true
}

# stage_time WHAT: how long WHAT took since the last call (CI's budget is the sum).
stage_time() { echo "== $1: $((SECONDS - stage_start)) s"; stage_start=$SECONDS; }
stage_start=0
stage_time "dependencies"

echo "== Release build and tests =="
"$top/scripts/build.sh" "$top/build" -DSPLATKIT_BUILD_TESTS=ON
stage_time "Release build"
install_laz_perf "$top/build"
log=$(mktemp)
asan_log=$(mktemp)
trap 'rm -f "$log" "$asan_log"' EXIT
status=0
(cd "$top/build" && ctest --output-on-failure -j "$jobs") | tee "$log" || status=$?
simd_summary "$log"
stage_time "Release tests"
[ "$status" -eq 0 ] || exit "$status"

if [ "${SPLATKIT_TEST_SANITIZE:-1}" = 1 ]; then
  echo "== ASan + UBSan build, tests and fuzzers =="
  CC=clang CXX=clang++ "$top/scripts/build.sh" "$top/build-asan" -DSPLATKIT_BUILD_TESTS=ON \
    -DSPLATKIT_SANITIZE=ON -DSPLATKIT_BUILD_FUZZERS=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo \
    "-DCMAKE_CXX_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG" \
    "-DCMAKE_C_FLAGS_RELWITHDEBINFO=-O2 -gline-tables-only -DNDEBUG"
  install_laz_perf "$top/build-asan"
  stage_time "ASan build"
  # LeakSanitizer's exit-time tracer crashed ("Tracer caught signal 11", after the test had
  # passed) on the test that reads a 1201² SRTM GeoTIFF through the OpenImageIO module, on the
  # AMD EPYC machine; that test runs with the leak check off (ASan and UBSan still on).
  no_leak_check='TerrainTessFactors.SharedEdgesAgreeForRandomCamerasRealSrtm'
  (cd "$top/build-asan" && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
     ctest --output-on-failure -j "$jobs" -E "^($no_leak_check)\$") | tee "$asan_log"
  (cd "$top/build-asan" && ASAN_OPTIONS=detect_leaks=0 UBSAN_OPTIONS=print_stacktrace=1 \
     ctest --output-on-failure -R "^($no_leak_check)\$") | tee -a "$asan_log"
  stage_time "ASan tests"
fi
slowest "$log" "Release"
[ -s "$asan_log" ] && slowest "$asan_log" "ASan + UBSan"
exit 0

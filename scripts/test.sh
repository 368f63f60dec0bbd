#!/usr/bin/env bash
# The whole test suite in one command: installs what is missing, builds, runs ctest.
#  1. Release build (build/): unit tests, end-to-end tests on the real binaries.
#  2. clang + AddressSanitizer + UndefinedBehaviorSanitizer build (build-asan/): the same tests
#     again, plus a short libFuzzer run of every reader over its seed corpus.
# SPLATKIT_TEST_SANITIZE=0 skips stage 2. Works from any directory.
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
"$top/scripts/install-deps.sh"
jobs=${SPLATKIT_JOBS:-$(nproc)}

echo "== Release build and tests =="
"$top/scripts/build.sh" "$top/build" -DSPLATKIT_BUILD_TESTS=ON
(cd "$top/build" && ctest --output-on-failure -j "$jobs")

if [ "${SPLATKIT_TEST_SANITIZE:-1}" = 1 ]; then
  echo "== ASan + UBSan build, tests and fuzzers =="
  CC=clang CXX=clang++ "$top/scripts/build.sh" "$top/build-asan" -DSPLATKIT_BUILD_TESTS=ON \
    -DSPLATKIT_SANITIZE=ON -DSPLATKIT_BUILD_FUZZERS=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
  (cd "$top/build-asan" && ASAN_OPTIONS=detect_leaks=1 UBSAN_OPTIONS=print_stacktrace=1 \
     ctest --output-on-failure -j "$jobs")
fi

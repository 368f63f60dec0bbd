#!/usr/bin/env bash
# Longer fuzzing of one reader or all: scripts/fuzz.sh [SECONDS] [READER...]
# (readers: the tests/fuzz/fuzz_<reader>.cpp targets). New inputs go to fuzz-corpus-work/<reader>;
# crashes to fuzz-corpus-work/crash-*. Add the interesting ones to tests/fuzz/corpus/<reader>/.
set -euo pipefail
top=$(cd "$(dirname "${BASH_SOURCE[0]}")/.." && pwd)
seconds=${1:-600}
shift || true
"$top/scripts/install-deps.sh"
CC=clang CXX=clang++ "$top/scripts/build.sh" "$top/build-asan" -DSPLATKIT_BUILD_TESTS=ON \
  -DSPLATKIT_SANITIZE=ON -DSPLATKIT_BUILD_FUZZERS=ON -DCMAKE_BUILD_TYPE=RelWithDebInfo
readers=("$@")
if [ ${#readers[@]} -eq 0 ]; then
  for f in "$top"/tests/fuzz/fuzz_*.cpp; do r=$(basename "$f" .cpp); readers+=("${r#fuzz_}"); done
fi
for r in "${readers[@]}"; do
  work=$top/fuzz-corpus-work/$r
  mkdir -p "$work"
  echo "== fuzz_$r for $seconds s =="
  "$top/build-asan/tests/fuzz/fuzz_$r" -max_total_time="$seconds" -artifact_prefix="$top/fuzz-corpus-work/crash-$r-" \
    "$work" "$top/tests/fuzz/corpus/$r"
done

#!/usr/bin/env bash
# ctest wrapper: runs one fuzz target for a short time over its seed corpus. New inputs go to a
# scratch directory, never into the source tree. Usage: run_fuzzer.sh BINARY SEED_DIR SECONDS
# A failing run keeps what libFuzzer wrote (crash-*, leak-*, timeout-*, oom-*) in
# ${SPLATKIT_FUZZ_ARTIFACTS:-./fuzz-artifacts}/<target>/ (ctest runs this in the build directory)
# and prints how to replay it.
set -euo pipefail
bin=$1 seeds=$2 seconds=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
if "$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=0 \
  -artifact_prefix="$work/artifact-" "$work" "$seeds" 2>"$work/log"; then
  grep -E "^#[0-9]+ *DONE" "$work/log" || tail -n 2 "$work/log"
  exit 0
fi
tail -n 60 "$work/log"
keep=${SPLATKIT_FUZZ_ARTIFACTS:-$PWD/fuzz-artifacts}/$(basename "$bin")
mkdir -p "$keep"
kept=0
for f in "$work"/artifact-*; do
  [ -e "$f" ] || continue
  name=${f##*/artifact-}
  mv "$f" "$keep/$name"
  echo "reproducer kept: $keep/$name (replay: $bin $keep/$name)"
  kept=$((kept + 1))
done
[ "$kept" -gt 0 ] || echo "the fuzzer failed without writing a reproducer (see the log above)"
exit 1

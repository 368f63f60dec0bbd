#!/usr/bin/env bash
# ctest wrapper: runs one fuzz target for a short time over its seed corpus. New inputs go to a
# scratch directory, never into the source tree. Usage: run_fuzzer.sh BINARY SEED_DIR SECONDS
set -euo pipefail
bin=$1 seeds=$2 seconds=$3
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
"$bin" -max_total_time="$seconds" -timeout=10 -rss_limit_mb=2048 -print_final_stats=0 \
  -artifact_prefix="$work/" "$work" "$seeds" 2>"$work/log" || { tail -n 60 "$work/log"; exit 1; }
grep -E "^#[0-9]+ *DONE" "$work/log" || tail -n 2 "$work/log"

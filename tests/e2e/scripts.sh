# The helper scripts, with stand-ins for the programs they drive: scripts/build.sh re-runs cmake
# when it is given options for an existing build directory; tests/fuzz/run_fuzzer.sh keeps the
# reproducer of a failing fuzz run where it can be replayed.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"

# A fake cmake that logs its arguments (one call per line).
mkdir -p "$WORK/bin" "$WORK/build"
cat > "$WORK/bin/cmake" <<'SH'
#!/usr/bin/env bash
echo "$*" >> "$CMAKE_LOG"
SH
chmod +x "$WORK/bin/cmake"
export CMAKE_LOG=$WORK/cmake.log

# A fresh directory is configured, with Release and Ninja.
PATH=$WORK/bin:$PATH SPLATKIT_JOBS=1 bash "$SRC/scripts/build.sh" "$WORK/fresh" -DX=1
expect_eq "fresh: configure" "$(grep -c -- '-G Ninja -DCMAKE_BUILD_TYPE=Release -DX=1' "$CMAKE_LOG")" 1
expect_eq "fresh: build" "$(grep -c -- "--build $WORK/fresh -j 1" "$CMAKE_LOG")" 1

# An existing directory with new options is configured again, then built.
: > "$CMAKE_LOG"
touch "$WORK/build/build.ninja"
PATH=$WORK/bin:$PATH SPLATKIT_JOBS=1 bash "$SRC/scripts/build.sh" "$WORK/build" -DSPLATKIT_BUILD_BENCH=ON
expect_eq "existing + options: calls" "$(wc -l < "$CMAKE_LOG")" 2
expect_eq "existing + options: configure" \
  "$(sed -n 1p "$CMAKE_LOG")" "-S $SRC -B $WORK/build -DSPLATKIT_BUILD_BENCH=ON"
expect_eq "existing + options: build" "$(sed -n 2p "$CMAKE_LOG")" "--build $WORK/build -j 1"

# An existing directory without options is only built (no reconfigure).
: > "$CMAKE_LOG"
PATH=$WORK/bin:$PATH SPLATKIT_JOBS=1 bash "$SRC/scripts/build.sh" "$WORK/build"
expect_eq "existing, no options" "$(cat "$CMAKE_LOG")" "--build $WORK/build -j 1"

# run_fuzzer.sh with a fake fuzzer that finds a crash: exit 1, reproducer kept and named.
cat > "$WORK/bin/fuzz_fake" <<'SH'
#!/usr/bin/env bash
for a in "$@"; do case $a in -artifact_prefix=*) prefix=${a#-artifact_prefix=} ;; esac; done
printf 'boom' > "${prefix}crash-0123abcd"
echo "==1== ERROR: libFuzzer: deadly signal" >&2
exit 77
SH
chmod +x "$WORK/bin/fuzz_fake"
mkdir -p "$WORK/seeds" "$WORK/fuzzrun"
(cd "$WORK/fuzzrun" && bash "$SRC/tests/fuzz/run_fuzzer.sh" "$WORK/bin/fuzz_fake" "$WORK/seeds" 1) \
  > "$WORK/fuzz.out" 2>&1
expect_eq "failing fuzz run: exit" "$?" 1
kept=$WORK/fuzzrun/fuzz-artifacts/fuzz_fake/crash-0123abcd
[ -f "$kept" ] && [ "$(cat "$kept")" = boom ] && pass || fail "reproducer not kept at $kept"
grep -qF "reproducer kept: $kept" "$WORK/fuzz.out" && pass || fail "path not printed: $(cat "$WORK/fuzz.out")"
grep -qF "deadly signal" "$WORK/fuzz.out" && pass || fail "fuzzer log not shown"

# A clean fuzz run: exit 0, nothing kept.
cat > "$WORK/bin/fuzz_clean" <<'SH'
#!/usr/bin/env bash
echo "#42	DONE   cov: 10 ft: 10 corp: 1/1b" >&2
SH
chmod +x "$WORK/bin/fuzz_clean"
(cd "$WORK/fuzzrun" && bash "$SRC/tests/fuzz/run_fuzzer.sh" "$WORK/bin/fuzz_clean" "$WORK/seeds" 1) \
  > "$WORK/fuzz.out" 2>&1
expect_eq "clean fuzz run: exit" "$?" 0
[ ! -e "$WORK/fuzzrun/fuzz-artifacts/fuzz_clean" ] && pass || fail "a clean run kept artifacts"

finish

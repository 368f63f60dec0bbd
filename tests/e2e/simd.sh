# The SIMD switch and far outliers, on the real binaries: every SPLATKIT_SIMD level gives the same
# bytes (estimate-normals, build-splat-graph); a bad SPLATKIT_SIMD is a usage error naming the
# variable and the accepted values; a cloud with a few points at 1e20 and 1e30 finishes as fast as
# one without (a generous timeout: a grid blown up by the outlier took minutes) and its graph has
# the same edges (the far splats overlap nothing).
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"

expect_exit 0 "$BIN/splat-synth" -q torus "$WORK/t.xyz" -n 60000 --random --no-color
# The points alone, for estimate-normals.
awk '!/^#/ { print $1, $2, $3 }' "$WORK/t.xyz" >"$WORK/p.xyz"

# Every level, the same bytes as the best level this CPU runs (levels it lacks are lowered).
expect_exit 0 "$BIN/estimate-normals" -q "$WORK/p.xyz" "$WORK/n.splk" --threads 2
expect_exit 0 "$BIN/build-splat-graph" -q "$WORK/t.xyz" "$WORK/g.splk" --threads 2
for level in portable sse2 avx2 avx512; do
  expect_exit 0 env SPLATKIT_SIMD=$level "$BIN/estimate-normals" -q "$WORK/p.xyz" \
    "$WORK/n-$level.splk" --threads 2
  cmp -s "$WORK/n.splk" "$WORK/n-$level.splk" && pass || fail "estimate-normals: $level differs"
  expect_exit 0 env SPLATKIT_SIMD=$level "$BIN/build-splat-graph" -q "$WORK/t.xyz" \
    "$WORK/g-$level.splk" --threads 2
  cmp -s "$WORK/g.splk" "$WORK/g-$level.splk" && pass || fail "build-splat-graph: $level differs"
done

# A bad value: exit 1, one line naming the variable, the value and the accepted ones.
for tool in estimate-normals:p.xyz build-splat-graph:t.xyz; do
  expect_exit 1 env SPLATKIT_SIMD=avx3 "$BIN/${tool%:*}" -q "$WORK/${tool#*:}" "$WORK/bad.splk"
  expect_stderr "SPLATKIT_SIMD=avx3: not one of portable, sse2, avx2, avx512"
  [ -e "$WORK/bad.splk" ] && fail "${tool%:*}: output written despite a bad SPLATKIT_SIMD" || pass
done

# Far outliers: one splat at 1e20, one at -1e30 (radii like the others').
cp "$WORK/t.xyz" "$WORK/far.xyz"
echo "1e20 0 0 0 0 1 0.01 0" >>"$WORK/far.xyz"
echo "-1e30 0.5 0.5 0 0 1 0.01 0" >>"$WORK/far.xyz"
awk '!/^#/ { print $1, $2, $3 }' "$WORK/far.xyz" >"$WORK/far-p.xyz"
edges() { tr -d ' \n' <"$1" | grep -o '"edges":[0-9]*' | head -1 | cut -d: -f2; }
for level in portable avx2 avx512; do
  expect_exit 0 env SPLATKIT_SIMD=$level timeout 10 "$BIN/build-splat-graph" -q "$WORK/t.xyz" \
    "$WORK/near.splk" --threads 2 --report "$WORK/near.json"
  expect_exit 0 env SPLATKIT_SIMD=$level timeout 10 "$BIN/build-splat-graph" -q \
    "$WORK/far.xyz" "$WORK/far.splk" --threads 2 --report "$WORK/far.json"
  expect_eq "far outliers add no edge ($level)" "$(edges "$WORK/far.json")" \
    "$(edges "$WORK/near.json")"
  expect_exit 0 env SPLATKIT_SIMD=$level timeout 10 "$BIN/estimate-normals" -q \
    "$WORK/far-p.xyz" "$WORK/far-n.splk" --threads 2
done
finish

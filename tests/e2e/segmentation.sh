# Segmentation quality through the tools at a size that runs in seconds: splat-synth
# cad 50 k with Gaussian noise of 0.125 % of the bounding-box diagonal -> estimate-normals
# --method robust -> build-splat-graph -> segment-surfaces .ply; IoU of every true patch
# (patch_id) with its best surface. Robust surfaces with the refined borders (the defaults)
# recover every patch with IoU >= 0.95 in at most 1.5 × 9 surfaces; the robust surfaces alone
# (--refine-rounds 0 --merge-below 1 --coplanar-scales 0) recover >= 80 % of the patches, the
# components of [IvoMSc] §5.4 (--method components) fewer; on the same part without noise robust and
# components give identical bytes. Also the options' errors.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"

# recovered PLY: how many true patches have a surface with IoU >= 0.95, as "K of P".
recovered() {
  patch_iou "$1" | awk '/^patch/ { n++; if ($8 >= 0.95) k++ } END { printf "%d of %d\n", k, n }'
}

for noise in 0 0.00125; do
  expect_exit 0 "$BIN/splat-synth" -q cad "$WORK/in-$noise.ply" -n 50000 --noise "$noise" --no-color
  expect_exit 0 "$BIN/estimate-normals" -q "$WORK/in-$noise.ply" "$WORK/n-$noise.ply" \
    --method robust
  expect_exit 0 "$BIN/build-splat-graph" -q "$WORK/n-$noise.ply" "$WORK/g-$noise.splk" \
    --report "$WORK/g-$noise.json"
  for method in robust components; do
    expect_exit 0 "$BIN/segment-surfaces" -q "$WORK/g-$noise.splk" "$WORK/s-$noise-$method.ply" \
      --method "$method" --report "$WORK/s-$noise-$method.json"
    expect_exit 0 "$BIN/segment-surfaces" -q "$WORK/g-$noise.splk" \
      "$WORK/u-$noise-$method.ply" --method "$method" --refine-rounds 0 --merge-below 1 \
      --coplanar-scales 0
  done
done
clean=$(recovered "$WORK/s-0-robust.ply")
noisy=$(recovered "$WORK/s-0.00125-robust.ply")
noisy_segments=$(patch_iou "$WORK/s-0.00125-robust.ply" | awk '/^segments/ { print $2 }')
unrefined=$(recovered "$WORK/u-0.00125-robust.ply")
noisy_components=$(recovered "$WORK/u-0.00125-components.ply")
echo "clean: $clean; noisy: refined $noisy in $noisy_segments surfaces; unrefined: robust" \
  "$unrefined, components $noisy_components"
expect_eq "clean patches recovered" "$clean" "9 of 9"
expect_eq "noisy patches recovered" "$noisy" "9 of 9"
[ "$noisy_segments" -le 13 ] && pass || fail "noisy: $noisy_segments surfaces (want <= 13)"
[ "${unrefined%% *}" -ge 8 ] && pass || fail "noisy: robust alone recovers $unrefined (want >= 8)"
[ "${noisy_components%% *}" -lt "${unrefined%% *}" ] && pass ||
  fail "noisy: components recover $noisy_components, robust $unrefined (want fewer)"
# Clean normals: the automatic core threshold is w_s, the surfaces are the components'.
cmp -s "$WORK/s-0-robust.ply" "$WORK/s-0-components.ply" && pass ||
  fail "clean: robust and components surfaces differ"
grep -Eq '"core_threshold": *0.(9|8999999)' "$WORK/s-0-robust.json" && pass ||
  fail "clean: core threshold is not w_s: $(grep core_threshold "$WORK/s-0-robust.json")"
grep -q '"core_threshold": *0.97' "$WORK/s-0.00125-robust.json" && pass ||
  fail "noisy: core threshold is not half the sharp angle"

# Option errors: out of range, unknown method.
expect_exit 1 "$BIN/segment-surfaces" "$WORK/g-0.splk" "$WORK/x.splk" --core 1.5
expect_exit 1 "$BIN/segment-surfaces" "$WORK/g-0.splk" "$WORK/x.splk" --method bfs
expect_exit 1 "$BIN/segment-surfaces" "$WORK/g-0.splk" "$WORK/x.splk" --min-core 0
expect_exit 1 "$BIN/segment-surfaces" "$WORK/g-0.splk" "$WORK/x.splk" --merge-below 0
expect_exit 1 "$BIN/segment-surfaces" "$WORK/g-0.splk" "$WORK/x.splk" --refine-rounds -1
expect_exit 1 "$BIN/segment-surfaces" "$WORK/g-0.splk" "$WORK/x.splk" --coplanar-scales -1
expect_exit 1 "$BIN/build-splat-graph" "$WORK/n-0.ply" "$WORK/x.splk" --surfaces bfs
finish

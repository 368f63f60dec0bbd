# workflows/Snakefile run by Snakemake on one machine: a survey of four LAZ files cut along
# arbitrary lines through the objects goes tile -> normals -> graph -> surfaces -> merge, and per
# tile .spt and .qs merged into one each (tests/e2e/lod_merge.sh compares merged and whole renders).
# OUT/splats.splk holds exactly the input points, with the positions, radii and normals of one
# estimate-normals run over the whole survey (signs decided per tile, and the normals of points
# where faces meet follow the signs around them: at most 0.1 % differ); the
# models and the report are there; a second run has nothing to do.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
cd "$WORK"
command -v snakemake >/dev/null || { fail "snakemake is not installed (scripts/install-deps.sh)"; finish; }
# i.i.d. samples (a regular grid's equidistant neighbours are ranked by point order, which tiles
# change) of a CAD part and a torus, in four LAZ files.
bash "$SRC/scripts/make-test-survey.sh" "$WORK" "$BIN" 40000
total=40000
expect_exit 0 snakemake -s "$SRC/workflows/Snakefile" --cores 2 -q \
  --config input="$WORK/scans/*.laz" outdir="$WORK/OUT" tile_size=12 bin="$BIN"
for f in splats.splk model.spt model.qs report.json tiled/tiles.json; do
  [ -s "OUT/$f" ] && pass || fail "no OUT/$f"
done
tiles=$(jq '.tiles | length' OUT/tiled/tiles.json)
[ "$tiles" -ge 4 ] && pass || fail "only $tiles tiles"
expect_eq "report: tiles" "$(jq .tiles OUT/report.json)" "$tiles"
expect_eq "report: jobs" "$(jq '.jobs | length' OUT/report.json)" "$((5 * tiles + 4))"
expect_eq "LOD files per tile" "$(ls OUT/lod | wc -l)" "$((2 * tiles))"
expect_eq "model.spt: every point once" "$(jq .input_points OUT/reports/spt.json)" "$total"
expect_eq "model.qs: every point once" "$(jq .leaves OUT/reports/qsplat.json)" "$total"
jq -e '[.jobs[] | select(.job != "merge") | .peak_rss_bytes > 0 and .peak_rss_bytes < 2e9] | all' \
  OUT/report.json >/dev/null && pass || fail "report: peak RSS missing or absurd"
expect_eq "surfaces per tile" "$(ls OUT/surfaces | wc -l)" "$tiles"
# The whole survey in one process.
"$BIN/splat-convert" -q scans/scan0.laz scans/scan1.laz scans/scan2.laz scans/scan3.laz whole-in.splk
"$BIN/estimate-normals" -q whole-in.splk whole.splk
"$BIN/splat-convert" -q whole.splk whole.xyz
"$BIN/splat-convert" -q OUT/splats.splk tiled.xyz
expect_eq "points" "$(grep -vc '^#' tiled.xyz)" "$total"
python3 - whole.xyz tiled.xyz <<'PY' && pass || fail "the tiled run's splats differ from the whole run's"
import sys
def rows(name):
    out = {}
    for l in open(name):
        if l[0] == "#": continue
        v = l.split()
        out.setdefault(tuple(v[:3]), []).append(v[3:])
    return out
a, b = rows(sys.argv[1]), rows(sys.argv[2])
ok = a.keys() == b.keys()
flipped = 0  # normals not equal to the whole run's
lines = 0    # of those, normals not equal up to their sign either
radii = 0
for k in a:
    if not ok: break
    for p, q in zip(sorted(a[k]), sorted(b[k])):
        n, m = [float(c) for c in p[:3]], [float(c) for c in q[:3]]
        if p[3] != q[3]:
            radii += 1
            if radii < 4: print("radius differs:", k, p, q, file=sys.stderr)
        if m != n and m != [-c for c in n]:
            lines += 1
            if lines < 4: print("normal differs:", k, p, q, file=sys.stderr)
        flipped += m != n
print("points", len(a), "normals differing from the whole run's", flipped, "of which not up to",
      "their sign", lines, "radii differing", radii, file=sys.stderr)
# The signs are decided per tile, the views not looking through the borders where the survey
# goes on (a view through the cut of a closed part sees its inside: 20 % of the signs differed
# without that); measured: 0 and 3 of 40 000 differ on two samplings. A point where faces meet
# takes the mean of its oriented neighbours' normals (orient_normals_mst.h), so where a tile's
# halo is signed otherwise than in the whole run, its line differs too: 16 of 40 000 on the
# CAD part's thin edge.
ok = ok and radii == 0 and flipped <= len(a) // 1000
sys.exit(0 if ok else 1)
PY
# The tiles' surfaces joined across their halos (splat-convert): one set of ids, as one
# segment-surfaces run over the whole survey gives them. Measured: 10 surfaces from the tiles'
# 55, as in the whole run; 14 of the 40 000 points on another surface than the whole run's.
jq -e '.surfaces.surfaces > 0 and .surfaces.tile_surfaces > .surfaces.surfaces' OUT/report.json \
  >/dev/null && pass || fail "report: no joined surfaces: $(jq -c .surfaces OUT/report.json)"
"$BIN/build-splat-graph" -q whole.splk whole-graph.splk
"$BIN/segment-surfaces" -q whole-graph.splk whole-surfaces.splk
"$BIN/splat-convert" -q whole-surfaces.splk whole-surfaces.xyz
python3 - whole-surfaces.xyz tiled.xyz <<'PY' && pass || fail "the joined surfaces differ from the whole run's"
import collections, sys
def surfaces(name):
    out = {}
    for l in open(name):
        if l[0] == "#":
            column = l[1:].split().index("surface_id")
            continue
        v = l.split()
        out[tuple(v[:3])] = v[column]
    return out
a, b = surfaces(sys.argv[1]), surfaces(sys.argv[2])
assert a.keys() == b.keys()
# Each whole-run surface's points: how many lie on the joined surface most of them lie on, and
# the other way round (a surface split or two joined would lower one of the two).
def agreement(x, y):
    groups = collections.defaultdict(collections.Counter)
    for k in x: groups[x[k]][y[k]] += 1
    return sum(c.most_common(1)[0][1] for c in groups.values()) / len(x)
whole, joined = agreement(a, b), agreement(b, a)
print("surfaces: whole", len(set(a.values())), "joined", len(set(b.values())),
      "agreement %.5f / %.5f" % (whole, joined), file=sys.stderr)
sys.exit(0 if len(set(a.values())) == len(set(b.values())) and min(whole, joined) >= 0.999 else 1)
PY
# Nothing left to do on a second run.
snakemake -s "$SRC/workflows/Snakefile" --cores 2 -n --config input="$WORK/scans/*.laz" \
  outdir="$WORK/OUT" tile_size=12 bin="$BIN" >dry.txt 2>&1
grep -q "Nothing to be done" dry.txt && pass || fail "a second run would redo: $(tail -3 dry.txt)"
finish

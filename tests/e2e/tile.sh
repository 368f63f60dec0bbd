# splat-tile: a survey cut along arbitrary lines into several LAZ files, then into square tiles.
# Every input point is the own point of exactly one tile, inside its square; every tile's halo is
# exactly the other points within H of its square in plan; the output is the same for any thread
# count and run; tiles can be cut again; bad input and options fail cleanly, leaving no partial
# output.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
cd "$WORK"
# A noisy CAD part and a torus side by side, moved to UTM-like coordinates (LAS scale 1 mm).
"$BIN/splat-synth" -q cad cad.xyz -n 30000 --random --seed 3 --no-color
"$BIN/splat-synth" -q torus torus.xyz -n 20000 --random --seed 4 --no-color
python3 - cad.xyz torus.xyz <<'PY'
import sys
pts = []
for name, dx in ((sys.argv[1], 0.0), (sys.argv[2], 3.2)):
    for l in open(name):
        if l.strip() and l[0] != "#":
            x, y, z = (float(v) for v in l.split()[:3])
            pts.append((500000 + 100 * (x + dx), 4100000 + 100 * y, 300 + 100 * z))
# Three survey files cut along two slanted lines (through the part and the torus).
files = [open("part%d.xyz" % k, "w") for k in range(3)]
for x, y, z in pts:
    u = (x - 500000) + 0.4 * (y - 4100000)
    k = 0 if u < 60 else (1 if u < 260 else 2)
    files[k].write("%.3f %.3f %.3f\n" % (x, y, z))
PY
for k in 0 1 2; do "$BIN/splat-convert" -q --columns x,y,z "part$k.xyz" "part$k.laz"; done
cat part0.xyz part1.xyz part2.xyz >all.xyz
total=$(wc -l <all.xyz)

expect_exit 0 "$BIN/splat-tile" -q part0.laz part1.laz part2.laz -o out --tile-size 70 \
  --report r.json --threads 2
expect_eq "report: points" "$(jq .points r.json)" "$total"
expect_eq "tiles.json: points" "$(jq .points out/tiles.json)" "$total"
expect_eq "tiles.json: inputs" "$(jq -c '[.inputs[].name]' out/tiles.json)" '["part0.laz","part1.laz","part2.laz"]'
expect_eq "tiles.json: bytes of part1.laz" "$(jq .inputs[1].bytes out/tiles.json)" "$(stat -c %s part1.laz)"
ntiles=$(jq '.tiles | length' out/tiles.json)
[ "$ntiles" -ge 8 ] && pass || fail "only $ntiles tiles"
expect_eq "tile files" "$(ls out/tiles | wc -l)" "$ntiles"
halo=$(jq .halo out/tiles.json)
python3 -c "import sys; h = float(sys.argv[1]); sys.exit(0 if 1 < h < 40 else 1)" "$halo" && pass ||
  fail "auto halo $halo (the spacing is about 1)"
for f in $(jq -r '.tiles[].file' out/tiles.json); do
  "$BIN/splat-convert" -q "out/$f" "$(basename "$f" .splk).xyz"
done
jq -r '.tiles[] | "\(.name) \(.i) \(.j) \(.own_points) \(.halo_points)"' out/tiles.json >tiles.txt
python3 - all.xyz tiles.txt 70 "$halo" <<'PY' && pass || fail "tiles do not partition the survey or halos are wrong"
import sys
from collections import Counter
allp = [tuple(round(float(v), 3) for v in l.split()[:3]) for l in open(sys.argv[1])]
size, halo = float(sys.argv[3]), float(sys.argv[4])
own_all = Counter()
ok = True
def dist2(p, i, j):
    x0, y0 = i * size, j * size
    dx = max(x0 - p[0], 0, p[0] - (x0 + size)); dy = max(y0 - p[1], 0, p[1] - (y0 + size))
    return dx * dx + dy * dy
for line in open(sys.argv[2]):
    name, i, j, n_own, n_halo = line.split(); i, j = int(i), int(j)
    own, hal = [], []
    for l in open(name + ".xyz"):
        if l[0] == "#": continue
        v = l.split()
        p = tuple(round(float(x), 3) for x in v[:3])
        (hal if v[-1] == "1" else own).append(p)
    if len(own) != int(n_own) or len(hal) != int(n_halo):
        print(name, "counts", len(own), n_own, len(hal), n_halo); ok = False
    for p in own:
        if not (i * size <= p[0] < (i + 1) * size and j * size <= p[1] < (j + 1) * size):
            print(name, "own point outside its square", p); ok = False; break
    own_all.update(own)
    # The halo: every other point within H of the square (a margin of 1 mm for the LAS rounding).
    want = Counter(p for p in allp if not (i * size <= p[0] < (i + 1) * size and
                                           j * size <= p[1] < (j + 1) * size)
                   and dist2(p, i, j) <= (halo - 0.002) ** 2)
    got = Counter(hal)
    if any(got[p] < c for p, c in want.items()):
        print(name, "halo misses points"); ok = False
    if any(dist2(p, i, j) > (halo + 0.002) ** 2 for p in hal):
        print(name, "halo holds far points"); ok = False
if own_all != Counter(allp):
    print("own points differ from the survey:", sum(own_all.values()), len(allp)); ok = False
sys.exit(0 if ok else 1)
PY

# No seam: estimate-normals on each tile (its halo as neighbours), the tiles' own points merged by
# splat-convert: the same points, normals (unoriented: PCA's canonical sign) and radii as one run
# over the whole survey.
mkdir -p normals
for t in out/tiles/*.splk; do
  "$BIN/estimate-normals" -q --orient none "$t" "normals/$(basename "$t")" 2>>normals.err ||
    fail "normals of $t"
done
# The default halo holds every neighbourhood: no tile warns.
expect_eq "estimate-normals' warnings on the tiles" "$(cat normals.err)" ""
expect_exit 0 "$BIN/splat-convert" -q normals/*.splk merged.xyz
expect_exit 0 "$BIN/splat-convert" -q part0.laz part1.laz part2.laz whole.splk
expect_exit 0 "$BIN/estimate-normals" -q --orient none whole.splk whole-n.splk
expect_exit 0 "$BIN/splat-convert" -q whole-n.splk whole.xyz
expect_eq "merged columns" "$(head -1 merged.xyz)" "$(head -1 whole.xyz)"
expect_eq "merged points" "$(grep -vc '^#' merged.xyz)" "$total"
cmp <(grep -v '^#' merged.xyz | sort) <(grep -v '^#' whole.xyz | sort) >/dev/null && pass ||
  fail "tiles' normals or radii differ from the whole run's: $(diff <(grep -v '^#' merged.xyz | sort) <(grep -v '^#' whole.xyz | sort) | grep -c '^<') lines"

# Segmented tiles (graph and surfaces per tile, with its halo) gathered by splat-convert: their
# surfaces joined across the halos into one set of ids (SURF), fewer than the tiles' together;
# with one input that has no surface ids, the points are gathered without any.
mkdir -p surf
for t in normals/*.splk; do
  "$BIN/build-splat-graph" -q "$t" "surf/graph-$(basename "$t")" &&
    "$BIN/segment-surfaces" -q "surf/graph-$(basename "$t")" "surf/$(basename "$t")" ||
    fail "surfaces of $t"
done
expect_exit 0 "$BIN/splat-convert" -q surf/tile_*.splk joined.splk --report joined.json
jq -e '.points == '"$total"' and .surfaces.surfaces > 0 and
       .surfaces.surfaces < .surfaces.tile_surfaces and .surfaces.halo_points_matched > 0' \
  joined.json >/dev/null && pass || fail "no surfaces joined: $(jq -c .surfaces joined.json)"
"$BIN/splat-info" joined.splk >joined.info
grep -q '"type":"SURF"' joined.info && pass || fail "joined.splk: no SURF"
set -- surf/tile_*.splk
expect_exit 0 "$BIN/splat-convert" -q "$1" "normals/$(basename "$2")" mixed.splk --report mixed.json
jq -e '.surfaces == null' mixed.json >/dev/null && pass || fail "mixed inputs joined surfaces"
"$BIN/splat-info" mixed.splk >mixed.info
grep -q '"type":"SURF"' mixed.info && fail "mixed.splk has surface ids" || pass

# A halo narrower than the neighbourhoods: estimate-normals says so, how many points and what
# halo would do, in its warning and its report.
expect_exit 0 "$BIN/splat-tile" -q part0.laz part1.laz part2.laz -o narrow --tile-size 70 --halo 0.3
t=narrow/tiles/$(jq -r '.tiles | max_by(.own_points) | .name' narrow/tiles.json).splk
"$BIN/estimate-normals" -q --orient none "$t" narrow.splk --report narrow.json 2>narrow.err ||
  fail "normals of $t"
grep -q "warning: $t: the tile's halo (0.3) does not hold the neighbourhoods of [0-9]* of its points" \
  narrow.err && pass || fail "no warning of the narrow halo: $(cat narrow.err)"
jq -e '.tile_halo.points_short > 0 and .tile_halo.halo_needed > 0.3' narrow.json >/dev/null && pass ||
  fail "report: $(jq -c .tile_halo narrow.json)"

# The same bytes for another thread count and another run.
expect_exit 0 "$BIN/splat-tile" -q part0.laz part1.laz part2.laz -o again --tile-size 70 --threads 1
diff -r out again >/dev/null && pass || fail "a second run (1 thread) differs"

# Tiles cut again at twice the size (their halo points are dropped): the same own points.
expect_exit 0 "$BIN/splat-tile" -q out/tiles/*.splk -o retiled --tile-size 140 --halo 2
expect_eq "retiled points" "$(jq .points retiled/tiles.json)" "$total"
expect_eq "retiled halo" "$(jq .halo retiled/tiles.json)" "2"
# Into the same folder at another size: the earlier tiles are gone.
expect_exit 0 "$BIN/splat-tile" -q part0.laz part1.laz part2.laz -o out --tile-size 140 --halo 2
expect_eq "stale tiles removed" "$(ls out/tiles | wc -l)" "$(jq '.tiles | length' out/tiles.json)"
[ -z "$(ls -A out | grep -v '^tiles')" ] && pass || fail "left behind: $(ls -A out)"

# Bad input and options.
"$BIN/estimate-normals" -q part2.laz part2n.splk --orient none
expect_exit 2 "$BIN/splat-tile" -q part0.laz part2n.splk -o mixed --tile-size 70
expect_stderr "part2n.splk: has normals, the earlier inputs do not"
[ ! -e mixed/tiles.json ] && [ -z "$(ls -A mixed/tiles)" ] && [ -z "$(ls -A mixed | grep -v '^tiles$')" ] &&
  pass || fail "a failed run left files: $(ls -AR mixed)"
printf 'ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nend_header\n' >bad.ply
expect_exit 2 "$BIN/splat-tile" -q part0.laz bad.ply -o bad --tile-size 70
expect_stderr "bad.ply"
expect_exit 2 "$BIN/splat-tile" -q missing.laz -o m --tile-size 70
expect_stderr "missing.laz"
expect_exit 1 "$BIN/splat-tile" -q part0.laz -o m --tile-size 0
expect_exit 1 "$BIN/splat-tile" -q part0.laz -o m
expect_exit 1 "$BIN/splat-tile" -q part0.laz -o m --tile-size 10 --halo -1
expect_exit 1 "$BIN/splat-tile" -q part0.laz -o - --tile-size 10
expect_exit 1 "$BIN/splat-tile" -q part0.laz -o m --tile-size 10 --report part0.laz
expect_stderr "--report names the input"
expect_exit 4 "$BIN/splat-tile" -q part0.laz -o nowhere/m --tile-size 10
expect_stderr "nowhere/m: cannot create the folder"
cmp part0.laz <(cat part0.laz) && pass || fail "an input changed"
finish

# splat-info reads every sample in every format and prints the same counts and bounding box:
# each sample is converted to every writable format (and PLY's three encodings), and the
# counts and bounds splat-info prints for the copies must equal the original's.
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
S=$SRC/data-samples

summary() {  # points, faces and bounds lines of splat-info's text report
  "$BIN/splat-info" "$1" 2>"$WORK/stderr" | grep -E '^(Points|Faces|Bounds|        max)'
}

shopt -s nullglob
samples=("$S"/*.ply "$S"/*.xyz "$S"/*.off "$S"/*.pcd "$S"/*.las)
[ ${#samples[@]} -ge 5 ] && pass || fail "expected at least 5 samples, found ${#samples[@]}"
for f in "${samples[@]}"; do
  name=$(basename "$f")
  want=$(summary "$f")
  if [ -z "$want" ]; then fail "$name: splat-info printed no summary: $(cat "$WORK/stderr")"; continue; fi
  for variant in splk ply ascii.ply be.ply xyz off; do
    out=$WORK/$name.$variant
    opts=()
    [ "$variant" = ascii.ply ] && opts=(--ascii)
    [ "$variant" = be.ply ] && opts=(--big-endian)
    if ! "$BIN/splat-convert" -q "${opts[@]}" "$f" "$out" 2>"$WORK/stderr"; then
      fail "$name -> $variant: $(cat "$WORK/stderr")"; continue
    fi
    got=$(summary "$out")
    # OFF keeps faces only when there are some; compare points and bounds for every copy.
    if [ "$(grep -v '^Faces' <<<"$got")" != "$(grep -v '^Faces' <<<"$want")" ]; then
      fail "$name -> $variant: summary differs"; diff <(echo "$want") <(echo "$got") | head -6 >&2
    else
      pass
    fi
  done
  # Through a pipe the content decides the format, whatever the name.
  got=$(cat "$f" | "$BIN/splat-info" - 2>"$WORK/stderr" | grep -E '^(Points|Bounds|        max)')
  case "$name" in
    *.xyz) ;;  # text columns cannot be told from content; covered by --columns tests
    *) expect_eq "$name via stdin" "$got" "$(grep -v '^Faces' <<<"$want")" ;;
  esac
done

# The same points in PLY's three encodings give the same report.
expect_eq "ascii vs big-endian PLY" "$(summary "$S/torus-ascii.ply")" "$(summary "$S/torus-big-endian.ply")"

# Attributes survive a round trip through .splk and back to PLY (normals, radius, patch_id).
"$BIN/splat-convert" -q "$S/cad.ply" "$WORK/cad.splk"
"$BIN/splat-convert" -q "$WORK/cad.splk" "$WORK/cad-back.ply"
attrs() { "$BIN/splat-info" "$1" | sed -n '/^Attributes:/,/^Header:/p' | grep -v '^Header:'; }
expect_eq "attributes after .splk round trip" "$(attrs "$WORK/cad-back.ply")" "$(attrs "$S/cad.ply")"

# What a plainer format cannot hold is said in the summary line (and -q silences it).
expect_exit 0 "$BIN/splat-convert" "$S/cad.ply" "$WORK/cad.las"
expect_stderr "las does not keep normals, radii, attribute patch_id$"
expect_exit 0 "$BIN/splat-convert" "$S/cad.ply" "$WORK/cad.off"
expect_stderr "off does not keep radii, attribute patch_id$"
expect_exit 0 "$BIN/splat-convert" "$S/cad.ply" "$WORK/cad.xyz"
grep -q "does not keep" "$WORK/stderr" && fail "xyz keeps every field of cad.ply" || pass
"$BIN/build-splat-graph" -q "$WORK/cad.splk" "$WORK/cad-graph.splk"
expect_exit 0 "$BIN/splat-convert" "$WORK/cad-graph.splk" "$WORK/cad-graph.ply"
expect_stderr "ply does not keep neighbour graph \\(GRPH\\), clip partners \\(CLIP\\)$"
expect_exit 0 "$BIN/splat-convert" -q "$WORK/cad-graph.splk" "$WORK/cad-graph.las"
expect_eq "-q: no summary" "$(cat "$WORK/stderr")" ""

# PCL's io (and the VTK, Boost and libtiff it links) is loaded only by a run that reads a .pcd
# file, through the PCL module: no tool links it at start-up.
for tool in "$BIN"/*; do
  [ -x "$tool" ] && [ -f "$tool" ] || continue
  if ldd "$tool" 2>/dev/null | grep -q 'libpcl'; then
    fail "$(basename "$tool") links PCL at start-up"
  else
    pass
  fi
done

finish

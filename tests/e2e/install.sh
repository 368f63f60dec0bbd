# What README.md says `cmake --install build --prefix ~/.local` installs, installed into a private
# prefix: the eleven tools in bin/, the modules they load on demand in lib/splatkit/, and the man
# pages (when help2man made them) in share/man/man1; the installed tools run from another
# directory and find the modules they need (PCD input, EXR output).
source "$(dirname "${BASH_SOURCE[0]}")/common.bash"
S=$SRC/data-samples
P=$WORK/prefix
cmake --install "$BIN/.." --prefix "$P" >"$WORK/install.log" 2>&1 || fail "cmake --install: $(tail -3 "$WORK/install.log")"
tools="splat-info splat-convert splat-synth splat-tile estimate-normals build-splat-graph
       segment-surfaces build-qsplat build-spt build-ham splat-view"
for t in $tools; do
  [ -x "$P/bin/$t" ] && pass || fail "not installed: bin/$t"
  if [ -d "$BIN/../man1" ]; then
    [ -s "$P/share/man/man1/$t.1" ] && pass || fail "not installed: share/man/man1/$t.1"
  fi
done
for m in splatkit_pcl_pcd splatkit_oiio_images splatkit_terrain_images; do
  if [ -f "$(find "$BIN/../lib" -name "lib$m.so" | head -1)" ]; then
    [ -f "$P/lib/splatkit/lib$m.so" ] && pass || fail "not installed: lib/splatkit/lib$m.so"
  fi
done

mkdir -p "$WORK/elsewhere" && cd "$WORK/elsewhere" || exit 1
run() { env -i PATH="$P/bin:/usr/bin:/bin" HOME="$WORK" "$@" >"$WORK/stdout" 2>"$WORK/stderr"; }
run splat-info "$S/cad-pcl.pcd" && pass || fail "installed splat-info on PCD: $(cat "$WORK/stderr")"
run splat-synth -q sphere s.splk -n 2000 && pass || fail "installed splat-synth: $(cat "$WORK/stderr")"
run splat-view -q s.splk -o s.exr --width 64 --height 48 && [ -s s.exr ] && pass ||
  fail "installed splat-view to EXR: $(cat "$WORK/stderr")"
run build-ham -q "$S/rainier-srtm.tif" t.exr && [ -s t.exr ] && pass ||
  fail "installed build-ham: $(cat "$WORK/stderr")"
finish

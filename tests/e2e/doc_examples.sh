#!/usr/bin/env bash
# Every command of the documentation runs as written: the lines "$ command" of the sh code blocks
# of README.md and docs/tools/*.md, each file's in a fresh directory holding nothing but a link
# data-samples/ to the samples (as the top of a clone does), in order, with the tools first on
# PATH: exit code 0 and nothing on stderr but summary lines. README.md's make code blocks are
# written to ./Makefile and ./tiled.mk before its commands run. Every tool has a page that lists every option of
# its --help and holds commands that run.
HERE=$(cd "$(dirname "$0")" && pwd)
source "$HERE/common.bash"
S=$SRC/data-samples
export PATH=$BIN:$PATH
source "$HERE/run_example.bash"

# doc_commands FILE: the commands of FILE, one per line ("$ " and a trailing "  # comment" cut).
doc_commands() {
  awk '/^```sh *$/ { code = 1; next } /^```/ { code = 0; next }
       code && /^\$ / { sub(/^\$ /, ""); sub(/  +# .*$/, ""); print }' "$1"
}
# doc_makefile FILE N: the N-th make code block of FILE.
doc_makefile() {
  awk -v n="$2" '/^```make *$/ { if (++seen == n) { code = 1; next } }
                 code && /^```/ { exit } code { print }' "$1"
}

run_doc() {  # run_doc FILE: runs its commands in $WORK/<its name>/; DOC_RUN = how many ran
  local cmd
  DOC_RUN=0
  mkdir -p "$WORK/$(basename "$1" .md)" && cd "$WORK/$(basename "$1" .md)" || return
  ln -sfn "$S" data-samples
  while IFS= read -r cmd; do
    left_out "$cmd" && continue
    run_example "${1#"$SRC"/}" "$cmd"
    DOC_RUN=$((DOC_RUN + 1))
  done < <(doc_commands "$1")
}

mkdir -p "$WORK/README"
doc_makefile "$SRC/README.md" 1 > "$WORK/README/Makefile"
doc_makefile "$SRC/README.md" 2 > "$WORK/README/tiled.mk"
[ -s "$WORK/README/Makefile" ] && pass || fail "README.md has no make code block"
grep -q '^# tiled.mk' "$WORK/README/tiled.mk" && pass || fail "README.md's second make block is not tiled.mk"
run_doc "$SRC/README.md"
expect_eq "README commands run" "$([ "$DOC_RUN" -ge 15 ] && echo ok)" ok

for tool in splat-synth splat-info splat-convert splat-tile estimate-normals build-splat-graph \
            segment-surfaces build-qsplat build-spt build-ham splat-view; do
  page=$SRC/docs/tools/$tool.md
  if [ ! -f "$page" ]; then fail "no page docs/tools/$tool.md"; continue; fi
  run_doc "$page"
  expect_eq "docs/tools/$tool.md commands run" "$([ "$DOC_RUN" -ge 2 ] && echo ok)" ok
  # The page lists every option of --help (the page is the long form of the same facts).
  while IFS= read -r opt; do
    grep -q -- "\`$opt[ ,{\`]" "$page" && pass || fail "docs/tools/$tool.md does not list $opt"
  done < <("$tool" --help | sed -n '/^Options:/,/^$/p' | grep -Eo '^  -[-a-z0-9,]+' |
           sed 's/^  //; s/,.*//' | grep -v -- '^-h$')
done

# What the README's recipes promise.
cd "$WORK/README" || exit 1
for f in survey.splk survey.png survey-top.png frames/survey-0011.png kitten.qs kitten.spt \
         kitten-qs.png kitten-spt.png cad.splk cad.png cad-surfaces.png rainier-tiles.exr \
         rainier.png build/sphere.spt build/torus.png survey-tiled.splk; do
  [ -s "$f" ] && pass || fail "no $f after the README's commands"
done

finish

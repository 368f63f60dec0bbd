# Every tool has a man page (made at build time by help2man) that `man -l` renders without
# warnings: its NAME line, the synopsis, the options and examples of --help, SEE ALSO.
# usage: render_man_pages.sh MAN1_DIR BIN_DIR TOOL...
set -uo pipefail
man1=$1 bin=$2
shift 2
fails=0
fail() { echo "FAIL: $*" >&2; fails=$((fails + 1)); }
for tool in "$@"; do
  page=$man1/$tool.1
  [ -s "$page" ] || { fail "no $page"; continue; }
  out=$(MANWIDTH=100 LC_ALL=C.UTF-8 man --warnings -l "$page" 2>"$man1/$tool.err") ||
    fail "$tool: man -l exits $?"
  [ -s "$man1/$tool.err" ] && fail "$tool: man warns: $(head -3 "$man1/$tool.err")"
  rm -f "$man1/$tool.err"
  for section in NAME SYNOPSIS DESCRIPTION OPTIONS "SEE ALSO"; do
    grep -q "^$section" <<<"$out" || fail "$tool: no $section section"
  done
  grep -q "^ *$tool - " <<<"$out" || fail "$tool: NAME does not name it"
  # Every long option of --help is in the page.
  for opt in $("$bin/$tool" --help | grep -o -- '--[a-z][a-z-]*' | sort -u); do
    grep -q -- "$opt" <<<"$out" || fail "$tool: $opt of --help is not in the page"
  done
done
echo "$# man pages checked, $fails failures"
[ "$fails" -eq 0 ]

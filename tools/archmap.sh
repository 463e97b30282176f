#!/usr/bin/env bash
# archmap.sh [--check] - the large-scale shape of the source tree.
#
# Without options it prints the file list per folder, function-length
# statistics and the longest functions (needs universal-ctags), the arrows
# (#includes and calls) between the layers, and who calls whom among the
# daemon's modules (from tests/daemon/test_layers.sh, which owns the
# daemon's own layering rule: ctest daemon.layers). With --check it
# verifies the rules between folders and exits 1 naming every broken one
# (ctest `tree.layers` runs this):
#   - lib/ and include/wormgear/ include nothing of daemon/, clients/ or
#     lcmtypes/; only lib/ (and white-box tests) include lib/'s private
#     headers (internal.h, cont.h);
#   - daemon/ and clients/ are peers: neither includes the other's files;
#   - no source file in lib/, daemon/ or clients/ reaches 800 lines.
set -uo pipefail
export LC_ALL=C
. "$(dirname "$0")/args.sh"
args_help "$@"
cd "$(dirname "$0")/.."

MAX_LINES=800

# Resolve #include "x" of file f to a tracked file (or print nothing).
includes_of() {
  local f=$1 d
  d=$(dirname "$f")
  grep -oE '^#include "[^"]+"' "$f" | sed -E 's/#include "(.*)"/\1/' | while read -r inc; do
    local cands=("$d/$inc" "include/$inc" "lib/$inc" "tests/$inc")
    case $f in tests/*) cands+=("daemon/$inc" "clients/$inc");; esac
    for c in "${cands[@]}"; do
      if [ -f "$c" ]; then realpath --relative-to=. "$c"; break; fi
    done
    case $inc in lcmtypes/*) echo "lcmtypes/(generated)";; esac
  done
}

check() {
  local bad=0 f inc lines
  for f in $(git ls-files 'lib/*.[ch]' 'include/*.h'); do
    for inc in $(includes_of "$f"); do
      case $inc in
        include/wormgear/*|lib/*.h) ;;
        *) echo "layers: $f includes $inc (the library includes only include/wormgear/ and its own lib/*.h)"; bad=1;;
      esac
      case $f:$inc in include/*:lib/*)
        echo "layers: public header $f includes the private $inc"; bad=1;; esac
    done
  done
  for f in $(git ls-files 'daemon/*.[ch]' 'clients/*.[ch]'); do
    for inc in $(includes_of "$f"); do
      case $f:$inc in
        daemon/*:clients/*|clients/*:daemon/*)
          echo "layers: $f includes $inc (daemon/ and clients/ are peers)"; bad=1;;
        *:lib/*)
          echo "layers: $f includes $inc (the library's private headers are its own)"; bad=1;;
      esac
    done
  done
  for f in $(git ls-files 'lib/*.[ch]' 'daemon/*.[ch]' 'clients/*.[ch]'); do
    lines=$(wc -l < "$f")
    if [ "$lines" -ge "$MAX_LINES" ]; then
      echo "layers: $f has $lines lines (split it: files stay under $MAX_LINES)"; bad=1
    fi
  done
  [ $bad = 0 ] && echo "layers: ok (the library below daemon/ and clients/, which are peers; files under $MAX_LINES lines)"
  return $bad
}

folder() { # the layer a path belongs to: lib, daemon, tests/sys, ...
  echo "$1" | sed -E 's#^(lib|daemon|clients|include|lcmtypes)/.*#\1#; s#^(tests/[a-z]+)/.*#\1#; s#^tests/[a-z_]+\.h$#tests#'
}

report() {
  echo "== files (lines)"
  for d in include/wormgear lib daemon clients lcmtypes tests/lib tests/daemon tests/sys \
           tests/clients tests/bench tools; do
    fl=$(git ls-files "$d" | grep -E '\.(c|h|sh|js|html|css|lcm)$' | grep -v "^$d/.*/")
    [ -n "$fl" ] || continue
    printf '%-18s %3d files %6d lines  ' "$d/" "$(echo "$fl" | wc -l)" "$(cat $fl | wc -l)"
    echo "$fl" | xargs -n1 basename | tr '\n' ' ' | fold -s -w 200 | head -3; echo
  done
  if command -v ctags >/dev/null; then
    echo "== functions"
    ctags --fields=+ne --c-kinds=f -o - $(git ls-files '*.c') 2>/dev/null |
      awk -F'\t' '{ln=0;en=0; for(i=4;i<=NF;i++){if($i~/^line:/)ln=substr($i,6); if($i~/^end:/)en=substr($i,5)} if(en) print en-ln+1"\t"$2":"ln"\t"$1}' |
      sort -n > /tmp/archmap.f.$$
    awk -F'\t' '{a[NR]=$1; if($1>60) n++} END{printf "%d functions, median %d lines, %d over 60 lines\n", NR, a[int((NR+1)/2)], n}' /tmp/archmap.f.$$
    echo "longest:"; sort -rn /tmp/archmap.f.$$ | head -12 | sed 's/^/  /'
    rm -f /tmp/archmap.f.$$
  fi
  echo "== #include arrows between folders"
  for f in $(git ls-files '*.[ch]'); do
    for inc in $(includes_of "$f"); do
      echo "$(folder "$f") -> $(folder "$inc")"
    done
  done | awk '$1 != $3' |
    sort | uniq -c | sed 's/^/  /'
  echo "== daemon modules: who calls whom (tests/daemon/test_layers.sh)"
  sh tests/daemon/test_layers.sh daemon | sed 's/^/  /'
}

[ $# -le 1 ] || args_refuse archmap.sh "one argument at most (--check), got $#"
case ${1:-} in
  --check) check ;;
  "") report ;;
  *) args_refuse archmap.sh "unknown argument '$1' (--check, or none)" ;;
esac

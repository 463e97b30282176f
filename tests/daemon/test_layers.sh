#!/bin/sh
# test_layers.sh - the daemon's modules call only downward.
# usage: test_layers.sh DAEMON_DIR [CC]
#
# One module is one .c/.h pair whose public functions carry its name as a
# prefix (cmd.c: cmd_*). The layers, top first:
#   main > loop > lockstep > cmd > engine, report > stream, pace, auth >
#   lcmio, inbox, snap, wire, sdn, conf, log
# A module may call functions of, or include the header of, modules in lower
# layers only: never its own layer (engine and report are peers) nor above.
# What a lower module must tell an upper one, it returns or reports through
# a hook the upper one passes in. wgd.h (the one struct) is shared by all.
#
# (inbox: the commands waiting, below cmd; lockstep: TICK, above cmd, whose
# step path cmd_run it runs the owed steps through.)
#
# Checked: every daemon/*.c is placed in a layer; every non-static function
# a .c defines is declared in its own header with its prefix; no call,
# function reference or #include goes sideways or up. Prints the module
# edges (the architecture as it is) and exits 1 on a violation.
set -u
dir=${1:?usage: test_layers.sh DAEMON_DIR [CC]}
cc=${2:-cc}
layers="main:7 loop:6 lockstep:5 cmd:4 engine:3 report:3 stream:2 pace:2 auth:2 lcmio:1 inbox:1 snap:1 wire:1 sdn:1 conf:1 log:1"
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT

# Each file without comments, as "MODULE KIND<TAB>line" (KIND h or c).
for f in "$dir"/*.h "$dir"/*.c; do
  b=$(basename "$f")
  "$cc" -fpreprocessed -dD -E -P "$f" 2>/dev/null | sed "s/^/${b%.*} ${b##*.}	/"
done >"$tmp/all"

awk -F'\t' -v layers="$layers" '
BEGIN {
  n = split(layers, l, " ")
  for (i = 1; i <= n; i++) if (split(l[i], kv, ":") == 2) level[kv[1]] = kv[2]
  head = "^[a-z][a-z0-9_ *]*[ *][*]*[a-z_][a-z0-9_]*[(]"   # a declaration or definition head
  skip = "^(static|typedef|extern|struct|enum|union)[ ]"
}
function name_of(s) { sub(/[(].*/, "", s); sub(/.*[ *]/, "", s); return s }
function fail(msg) { print "FAIL: " msg; bad = 1 }
# pass 1: public functions are the prototypes in each module header
NR == FNR {
  split($1, mk, " ")
  if (mk[2] == "h" && $2 ~ head && $2 !~ skip) owner[name_of($2)] = mk[1]
  next
}
# pass 2: every line of every file, as its module
{
  split($1, mk, " "); m = mk[1]; line = $2
  if (m == "wgd") next                             # the one struct embeds lower types
  files[m] = 1
  if (mk[2] == "c" && line ~ head && line !~ skip && line !~ /;[ ]*$/) {
    f = name_of(line)
    if (!(m == "main" && f == "main")) {
      if (index(f, m "_") != 1) fail(m ".c defines " f " without the prefix " m "_")
      if (owner[f] != m) fail(m ".c defines " f ", not declared in " m ".h")
    }
  }
  if (match(line, /^#include "[a-z_]+[.]h"/)) {
    y = substr(line, 11, RLENGTH - 13)
    if (y != m && y != "wgd" && (y in level)) {
      use[m, y] = use[m, y] ""
      edge[m, y] = 1
    }
    next
  }
  gsub(/"([^"\\]|\\.)*"/, "\"\"", line)           # no identifiers inside strings
  gsub(/[^A-Za-z0-9_]+/, " ", line)
  k = split(line, w, " ")
  for (i = 1; i <= k; i++) {
    y = owner[w[i]]
    if (y == "" || y == m || seen[m, w[i]]++) continue
    use[m, y] = use[m, y] " " w[i]; edge[m, y] = 1
  }
}
END {
  for (m in files) if (!(m in level)) fail(m " is in no layer (add it to test_layers.sh)")
  for (e in edge) {
    split(e, p, SUBSEP)
    line = p[1] " -> " p[2] ":" (use[e] == "" ? " (#include only)" : use[e])
    print line | "sort"
    if (!(level[p[2]] < level[p[1]]))
      viol[++nv] = p[1] " (layer " level[p[1]] ") uses " p[2] " (layer " level[p[2]] ")"
  }
  close("sort")
  for (i = 1; i <= nv; i++) fail(viol[i])
  if (!bad) print "ok: every daemon module calls only downward"
  exit bad
}' "$tmp/all" "$tmp/all"

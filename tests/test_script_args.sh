#!/bin/sh
# test_script_args.sh SRC - the command lines of the scripts in tools/ (one
# rule, tools/args.sh): --help and -h print the script's header on standard
# output and exit 0 having done nothing else (tools/test.sh --help ran the
# whole suite, tools/setup.sh --help installed packages); an argument a
# script does not take gets one refusal naming it, exit 2, before anything
# is installed, built or run. Every script in tools/ is tried, so a new one
# without the rule fails here; and tools/chainbound.py, in Python.
src=$1
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
status=0
fail() { echo "FAIL: $*"; status=1; }

# refused SCRIPT PATTERN ARGS...: exit 2, nothing on standard output, one
# refusal matching PATTERN that points to --help
refused() {
    s=$1 pat=$2
    shift 2
    (cd "$tmp" && timeout 20 bash "$src/tools/$s" "$@" >"$tmp/o" 2>"$tmp/e")
    rc=$?
    [ $rc -eq 2 ] || fail "$s $*: exit $rc, not 2: $(head -3 "$tmp/e")"
    [ -s "$tmp/o" ] && fail "$s $*: ran: $(head -3 "$tmp/o")"
    grep -Eq -- "^$s: $pat" "$tmp/e" || fail "$s $*: no '$s: $pat' in: $(cat "$tmp/e")"
    grep -q "^(try $s --help)$" "$tmp/e" || fail "$s $*: the refusal does not point to --help"
}

n=0
for f in "$src"/tools/*.sh; do
    s=$(basename "$f")
    [ "$s" = args.sh ] && continue # sourced, not run
    n=$((n + 1))
    first=$(sed -n '2s/^# \{0,1\}//p' "$f")
    [ -n "$first" ] || fail "$s: no header comment on line 2"
    for h in --help -h; do
        # --help by its full path from elsewhere, -h by a relative one from the
        # tree's parent (a script that changes directory first must not lose $0)
        if [ $h = --help ]; then
            (cd "$tmp" && timeout 20 bash "$f" $h >"$tmp/o" 2>"$tmp/e")
        else
            (cd "$src/.." && timeout 20 bash "$(basename "$src")/tools/$s" $h >"$tmp/o" 2>"$tmp/e")
        fi
        rc=$?
        [ $rc -eq 0 ] || fail "$s $h: exit $rc: $(head -3 "$tmp/e")"
        [ "$(head -1 "$tmp/o")" = "$first" ] || fail "$s $h: not its header: $(head -2 "$tmp/o")"
        [ -s "$tmp/e" ] && fail "$s $h wrote to standard error: $(head -3 "$tmp/e")"
    done
done
[ $n -ge 8 ] || fail "only $n scripts in tools/"
[ -z "$(ls -A "$tmp" | grep -v '^[oe]$')" ] || fail "--help left files: $(ls "$tmp")"

refused test.sh "takes no arguments, got 'x'" x
refused bench.sh "takes no arguments, got '--check'" --check
refused setup.sh "unknown argument '--chek' \(--check, or none\)" --chek
refused setup.sh "one argument at most" --check x
refused archmap.sh "unknown argument '-x'" -x
refused archmap.sh "one argument at most" --check x
refused channel_rates.sh "BUILD \[SECONDS\], got 0 arguments"
refused channel_rates.sh "BUILD '$tmp/none': not a directory" "$tmp/none"
refused channel_rates.sh "SECONDS '0': a whole number, 1 to 600" "$tmp" 0
refused channel_rates.sh "SECONDS 'x': " "$tmp" x
refused golden.sh "BUILD_DIR, one argument, got 0"
refused golden.sh "BUILD_DIR '$tmp': no wgsim in it" "$tmp"
refused kloop.sh "BUILD_DIR, one argument, got 2" "$tmp" x
refused kloop.sh "BUILD_DIR '$tmp': no lib/ in it" "$tmp"
# tools/chainbound.py: the same rule in Python
python3 "$src/tools/chainbound.py" --help >"$tmp/o" 2>"$tmp/e" && grep -q '^usage: tools/chainbound.py' "$tmp/o" ||
    fail "chainbound.py --help: $(head -2 "$tmp/e")"
python3 "$src/tools/chainbound.py" 3 x 1 >"$tmp/o" 2>"$tmp/e"
[ $? -eq 2 ] && [ ! -s "$tmp/o" ] && grep -q "^chainbound.py: MUL 'x': a latency" "$tmp/e" ||
    fail "chainbound.py 3 x 1: $(cat "$tmp/e")"
# run.sh passes its arguments to wormgeard: only --help is its own
(cd "$tmp" && timeout 20 bash "$src/tools/run.sh" --help >"$tmp/o" 2>"$tmp/e")
grep -q "^wormgeard's options" "$tmp/o" || fail "run.sh --help does not say where wormgeard's options are"
[ $status -eq 0 ] && echo "ok: $n scripts: --help and -h print their headers; refusals exit 2"
exit $status

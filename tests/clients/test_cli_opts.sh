#!/bin/sh
# test_cli_opts.sh WGSIM WGSWEEP WGCONT WGMON WGRIG WGLOG WGWEB - an option
# getopt refuses, in every client (cli_getopt_error): one line naming the
# option as typed and what is wrong with it (its value missing, unknown,
# given a value it does not take, ambiguous), then "(try PROG --help)",
# exit 2, nothing on stdout. wgsim said "option -s needs an argument or is
# unknown" for --scene (-s: a code of its option table, not an option),
# the others "unknown option or missing argument: '--scene'" for both. And a
# udpm:// URL with port 0, refused before LCM opens it.
status=0
tmp=$(mktemp -d) || exit 1
trap 'rm -rf "$tmp"' EXIT
cd "$tmp" || exit 1
fail() { echo "FAIL: $*"; status=1; }
refused() { # WANT PROG ARGS...: exit 2, "PROG: WANT" and the hint, nothing else
    want=$1 prog=$2
    shift 2
    name=${prog##*/}
    "$prog" "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$?
    if [ $rc -eq 2 ] && [ "$(sed -n 1p "$tmp/err")" = "$name: $want" ] &&
        [ "$(sed -n 2p "$tmp/err")" = "(try $name --help)" ] &&
        [ "$(wc -l <"$tmp/err")" -eq 2 ] && [ ! -s "$tmp/out" ]; then
        echo "ok   $name $*: $want"
    else
        fail "$name $* -> exit $rc, want 2 and '$name: $want': $(cat "$tmp/err" "$tmp/out")"
    fi
}
SIM=$1 SWEEP=$2 CONT=$3 MON=$4 RIG=$5 LOG=$6 WEB=$7

# a value missing: the long option typed, not getopt's code for it
refused "option --scene needs a value" "$SIM" --scene
refused "option --periods needs a value" "$SIM" --periods
refused "option --events needs a value" "$SIM" --periods 5 --events
refused "option --scene needs a value" "$SIM" --sce # an abbreviation: the option it is
refused "option --scene needs a value" "$SWEEP" --scene
refused "option --to needs a value" "$SWEEP" --from 1 --to
refused "option --scene needs a value" "$CONT" --scene
refused "option --periods needs a value" "$MON" --periods
refused "option --from needs a value" "$RIG" --from
refused "option --allow-origin needs a value" "$WEB" --allow-origin
refused "option -o needs a value" "$LOG" -o
refused "option -o needs a value" "$LOG" -qo # the last of a cluster
# unknown: the word typed (its name, without a value given with '=')
refused "unknown option '--frobnicate'" "$SIM" --frobnicate
refused "unknown option '-x'" "$SIM" -x
refused "unknown option '--bogus'" "$SWEEP" --bogus=3
refused "unknown option '--bogus'" "$CONT" --from 1 --to 2 --bogus
refused "unknown option '--bogus'" "$MON" --bogus
refused "unknown option '--bogus'" "$RIG" --bogus
refused "unknown option '--bogus'" "$WEB" --bogus
refused "unknown option '--bogus'" "$LOG" --bogus
refused "unknown option '-z'" "$LOG" -qz
refused "unknown option '-z'" "$LOG" -zq # the first of a cluster
# a value to an option that takes none; an abbreviation of two options
refused "option --quiet takes no value, got '--quiet=yes'" "$SWEEP" --quiet=yes
refused "option --help takes no value, got '--help=1'" "$SIM" --help=1
refused "option '--st' is ambiguous: --steps-per-period, --stepper (give more of the name)" \
    "$SIM" --st 64
# a udpm:// URL with port 0, refused at once (LCM's own self-test failed after 10 s, and
# wg_mcast_guard only then named it): exit 2, the reason, in under 3 s
port0() { # PROG ARGS...
    name=${1##*/}
    t0=$(date +%s)
    "$@" >"$tmp/out" 2>"$tmp/err"
    rc=$? t=$(($(date +%s) - t0))
    if [ $rc -eq 2 ] && [ $t -lt 3 ] &&
        grep -q "^$name: a udpm:// URL with port 0: give the bus's port" "$tmp/err"; then
        echo "ok   $name port 0: exit 2 in ${t} s"
    else
        fail "$name port 0 -> exit $rc in $t s: $(cat "$tmp/err" "$tmp/out")"
    fi
}
port0 "$MON" --url 'udpm://239.255.76.67:0?ttl=0' --once
port0 "$RIG" --url 'udpm://239.255.76.67:0?ttl=0' --from 0.5 --to 1
port0 "$LOG" record "$tmp/port0.lcmlog" --url 'udpm://239.255.76.67:0'
exit $status

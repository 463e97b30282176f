#!/bin/sh
# channel_rates.sh BUILD [SECONDS] - what each channel of wormgeard costs at
# physical real time (table3, omega = 1.2: period-2, mesh and bearings
# impacting), for each `contacts` setting: messages, samples and bytes per
# second per channel, from an lcm-logger log read by wglog summary. Runs a
# daemon on a host-local URL (ttl=0, a port of its own); run it through
# tests/netns.sh to keep even that off the host's interfaces.
# Exit 0, 1 when something did not run or CONTACT did not carry fewer events
# per mesh period at each setting (all > all 100 > mesh > none = 0).
# SECONDS: each setting's run, 1 to 600 (default 5). --help: this text.
set -u
. "$(dirname "$0")/args.sh"
args_help "$@"
[ $# -ge 1 ] && [ $# -le 2 ] || args_refuse channel_rates.sh "BUILD [SECONDS], got $# arguments"
[ -d "$1" ] || args_refuse channel_rates.sh "BUILD '$1': not a directory (a build, e.g. build/release)"
args_int channel_rates.sh SECONDS "${2:-5}" 1 600 "a whole number, 1 to 600"
B=$(cd "$1" && pwd) T=${2:-5}
D=$B/daemon/wormgeard C=$B/clients/wgctl L=$B/clients/wglog
tmp=$(mktemp -d) || exit 1
pid= lp=
trap 'kill $pid $lp 2>/dev/null; rm -rf "$tmp"' EXIT
export WORMGEAR_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0" WORMGEAR_PREFIX=RATE_
last=
for setting in "all" "all 100" "mesh" "none"; do
    "$D" --rate 1 --state-dir "$tmp" 2>"$tmp/log" &
    pid=$!
    i=0
    until "$C" --timeout 0.5 get >/dev/null 2>&1; do
        i=$((i + 1))
        [ $i -lt 20 ] || { echo "channel_rates: no daemon: $(cat "$tmp/log")"; exit 1; }
    done
    "$C" set omega=1.2 >/dev/null && "$C" contacts $setting >/dev/null || exit 1
    sleep 1 # past the change
    lcm-logger --lcm-url="$WORMGEAR_URL" -q "$tmp/run.lcmlog" &
    lp=$!
    sleep "$T"
    kill -INT $lp && wait $lp
    lp=
    kill -TERM $pid && wait $pid
    pid=
    echo "== contacts $setting: $T s at physical real time, table3, omega 1.2"
    # per channel over the log's span: messages, samples and kB per second
    "$L" summary "$tmp/run.lcmlog" | awk 'NR == 1 { dur = $5; next }
        NR == 2 { printf "%-20s %10s %10s %10s\n", "channel", "msgs/s", "samples/s", "kB/s"; next }
        dur > 0 { printf "%-20s %10.1f %10.0f %10.1f\n", $1, $6, $4 / dur, $5 / dur / 1e3
                  tot += $5 / dur / 1e3 }
        END { printf "%-20s %10s %10s %10.1f\n", "total", "", "", tot }'
    # contact events per mesh period (a measure of the setting, not of how
    # fast this machine ran the daemon): strictly fewer at each setting
    ct=$("$L" summary "$tmp/run.lcmlog" | awk '$1 ~ /CONTACT$/ { c = $4 } $1 ~ /POINCARE$/ { p = $4 }
        END { printf "%.6f\n", (p > 0 ? c / p : -1) }')
    echo "contact events per mesh period: $ct"
    if [ "$ct" = "-1.000000" ]; then
        echo "channel_rates: no POINCARE in the log"
        exit 1
    fi
    if [ -n "$last" ] && ! awk -v a="$ct" -v b="$last" 'BEGIN { exit !(a < b || (a == 0 && b == 0)) }'; then
        echo "channel_rates: $ct contact events per period with contacts $setting, $last before"
        exit 1
    fi
    last=$ct
    rm -f "$tmp/run.lcmlog"
done
[ "$last" = "0.000000" ] || { echo "channel_rates: contacts none still sent $last events per period"; exit 1; }

#!/bin/sh
# web_bench.sh WORMGEARD WGWEB [SECONDS] [SCREENSHOT] - the dashboard at
# physical real time: wormgeard (table3, rate 1, omega 1.2), wgweb, and the
# dashboard in headless Chromium for SECONDS (default 20); prints the
# dashboard's frame rate and frame intervals, publish-to-screen latency, and
# the CPU share of the bridge, the daemon and Chromium over the run. Figures
# only, never pass/fail. Run host-locally:
#   tests/netns.sh sh tests/bench/web_bench.sh build/release/daemon/wormgeard build/release/clients/wgweb 20
# SECONDS: 8 to 3600. SCREENSHOT: a PNG file the page is saved to at the end.
# --help (or -h): this text.
. "$(dirname "$0")/../../tools/args.sh"
args_help "$@"
D=${1:-} W=${2:-} S=${3:-20} SHOT=${4:-}
usage() { args_refuse web_bench.sh "$1"; }
[ $# -le 4 ] || usage "'$5': an operand too many (at most 4)"
[ -n "$D" ] && [ -n "$W" ] || usage "WORMGEARD and WGWEB missing: the daemon's and the bridge's executables"
[ -x "$D" ] && [ -f "$D" ] || usage "WORMGEARD '$D': not an executable file (the daemon)"
[ -x "$W" ] && [ -f "$W" ] || usage "WGWEB '$W': not an executable file (the bridge, clients/wgweb)"
args_int web_bench.sh SECONDS "$S" 8 3600 "a whole number of seconds, 8 to 3600 (default 20)"
here=$(cd "$(dirname "$0")" && pwd)
js=$here/../../web/test/bench.mjs
tmp=$(mktemp -d) || exit 1
dpid= wpid=
trap 'kill $wpid $dpid 2>/dev/null; rm -rf "$tmp"' EXIT
export WORMGEAR_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0" WORMGEAR_PREFIX=WEBB_
export WG_SCENE_PATH=${WG_SCENE_PATH:-$here/../../scenes}
"$D" --state-dir "$tmp" --set omega=1.2 >"$tmp/d.log" 2>&1 &
dpid=$!
"$W" --port 0 >"$tmp/w.out" 2>"$tmp/w.err" &
wpid=$!
. "$here/../wait.sh" # wait_until
wait_until 5 grep -q "http://" "$tmp/w.out"
port=$(sed -n 's|.*http://127.0.0.1:\([0-9]*\)/.*|\1|p' "$tmp/w.out")
[ -n "$port" ] || { echo "wgweb did not start"; cat "$tmp/w.err"; exit 1; }
ticks() { awk '{print $14 + $15}' "/proc/$1/stat"; }
tree_ticks() { # a process and its children (Chromium is a tree)
    t=0
    for p in $(pgrep -P "$1") "$1"; do t=$((t + $(ticks "$p" 2>/dev/null || echo 0))); done
    echo $t
}
hz=$(getconf CLK_TCK)
sleep 2
node "$js" "http://127.0.0.1:$port/" "$S" $SHOT >"$tmp/page.out" 2>&1 &
npid=$!
sleep 6 # Chromium starting and the page filling; then measure over the same window as the page
w0=$(ticks $wpid) d0=$(ticks $dpid) t0=$(date +%s.%N)
c0=0; for p in $(pgrep -f -- "--user-data-dir=.*playwright" | head -50); do c0=$((c0 + $(ticks "$p" 2>/dev/null || echo 0))); done
sleep $((S - 4))
w1=$(ticks $wpid) d1=$(ticks $dpid) t1=$(date +%s.%N)
c1=0; for p in $(pgrep -f -- "--user-data-dir=.*playwright" | head -50); do c1=$((c1 + $(ticks "$p" 2>/dev/null || echo 0))); done
wait $npid
cat "$tmp/page.out"
awk -v w=$((w1 - w0)) -v d=$((d1 - d0)) -v c=$((c1 - c0)) -v hz="$hz" -v t0="$t0" -v t1="$t1" 'BEGIN {
    dt = t1 - t0
    printf "CPU share over %.1f s (1 = one core): wgweb %.3f, wormgeard %.3f, Chromium (all processes) %.3f\n", dt, w / hz / dt, d / hz / dt, c / hz / dt }'
grep -o '"rtf":[0-9.e-]*' "$tmp/d.log" | tail -1 >/dev/null
echo "load average: $(cut -d' ' -f1-3 /proc/loadavg)"

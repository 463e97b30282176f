#!/bin/sh
# test_wglog_daemon.sh WORMGEARD WGLOG WGTAP WGCTL LCM_LOGGER - record a short
# daemon run with lcm-logger (--lcm-url=, as 1.3.1's -l is broken) while a
# subscriber (wgtap) prints what it receives; export the log with wglog and
# check every STATE and POINCARE sample that both saw is identical in the CSV
# (the shortest text that reads back exactly), the summary has the channels, and a set command
# shows up in CMD/ACK. Run through netns.sh (host-local URL only).
D=$1 W=$2 T=$3 C=$4 L=$5
code=0
tmp=$(mktemp -d) || exit 1
dpid= lpid=
cleanup() {
    for p in $dpid $lpid; do kill -KILL "$p" 2>/dev/null; done
    rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; code=1; }
. "$(dirname "$0")/../wait.sh" # wait_until
export WORMGEAR_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0" WORMGEAR_PREFIX=LOGT_

"$L" --lcm-url="$WORMGEAR_URL" "$tmp/run.lcmlog" >"$tmp/logger.out" 2>&1 &
lpid=$!
"$D" --rate 0.01 --set omega=0.7 --state-dir "$tmp" >"$tmp/d.out" 2>&1 &
dpid=$!
# until the daemon answers (it then takes commands)
wait_until 10 "$C" --timeout 0.5 status >/dev/null 2>&1 || fail "no daemon: $(cat "$tmp/d.out")"
"$T" "$WORMGEAR_URL" LOGT_ 2.5 >"$tmp/tap.txt" &
tpid=$!
sleep 1
"$C" set omega=0.75 >/dev/null || fail "wgctl set: $(cat "$tmp/d.out")"
wait $tpid
kill -TERM $dpid; wait $dpid; dpid=
sleep 0.3
kill -INT $lpid; wait $lpid; lpid=

"$W" summary "$tmp/run.lcmlog" >"$tmp/sum.txt" || fail "wglog summary: exit $?"
cat "$tmp/sum.txt"
for ch in STATE POINCARE CONTACT STATUS PARAMS CMD ACK; do
    grep -q "^LOGT_$ch " "$tmp/sum.txt" || fail "summary lacks LOGT_$ch"
done
"$W" export "$tmp/run.lcmlog" --out "$tmp/csv" -q || fail "wglog export: exit $?"
# seq,i,tau,xn (STATE columns 3,6,7,10) and seq,i,period,xn (POINCARE 3,4,5,9)
awk -F, 'NR > 1 { print "STATE," $3 "," $6 "," $7 "," $10 }' "$tmp/csv/LOGT_STATE.csv" >"$tmp/log.txt"
awk -F, 'NR > 1 { print "POINCARE," $3 "," $4 "," $5 "," $9 }' "$tmp/csv/LOGT_POINCARE.csv" >>"$tmp/log.txt"
# compare on the messages both saw (the tap and the logger start and stop apart)
awk -F, 'NR == FNR { seen[$1 "," $2] = 1; next } ($1 "," $2) in seen' "$tmp/log.txt" "$tmp/tap.txt" | sort >"$tmp/a"
awk -F, 'NR == FNR { seen[$1 "," $2] = 1; next } ($1 "," $2) in seen' "$tmp/tap.txt" "$tmp/log.txt" | sort >"$tmp/b"
n=$(wc -l <"$tmp/a")
np=$(grep -c '^POINCARE' "$tmp/a")
echo "samples seen by both the subscriber and the log: $n ($np Poincare)"
[ "$n" -gt 1000 ] || fail "too few common samples: $n"
[ "$np" -gt 20 ] || fail "too few common Poincare samples: $np"
cmp -s "$tmp/a" "$tmp/b" || fail "CSV differs from what was received: $(diff "$tmp/a" "$tmp/b" | head -5 | tr '\n' ' ')"
grep -q ',set,omega=0.75,' "$tmp/csv/LOGT_CMD.csv" || fail "CMD.csv lacks the set: $(cat "$tmp/csv/LOGT_CMD.csv")"
grep -q ',OK,' "$tmp/csv/LOGT_ACK.csv" || fail "ACK.csv lacks the OK: $(cat "$tmp/csv/LOGT_ACK.csv")"
# omega in STATE goes 0.7 -> 0.75 once
awk -F, 'NR > 1 && $9 != last { n++; last = $9 } END { exit !(n == 2) }' "$tmp/csv/LOGT_STATE.csv" ||
    fail "STATE omega does not step once from 0.7 to 0.75"
exit $code

#!/bin/sh
# test_wglog_daemon.sh WORMGEARD WGLOG WGTAP WGCTL WGSPOOF - record a short daemon run
# with `wglog record` while a subscriber (wgtap) prints what it receives; export
# the log with wglog and check every STATE and POINCARE sample that both saw is
# identical in the CSV (the shortest text that reads back exactly), the summary
# has the channels, and a set command shows up in CMD/ACK. Halfway, a hostile
# sender (wgspoof) sends, among its bytes, fragments whose offset + size wraps
# 32 bits, which end an unfiltered LCM receiver (lcm-logger) with SIGSEGV: the
# recorder records on through them. Then what `wglog record` refuses: an
# existing file without --force, a write that fails (/dev/full). Run through
# netns.sh (host-local URL only).
D=$1 W=$2 T=$3 C=$4 SPOOF=$5
code=0
tmp=$(mktemp -d) || exit 1
dpid= lpid= spid=
cleanup() {
    for p in $dpid $lpid $spid; do kill -KILL "$p" 2>/dev/null; done
    rm -rf "$tmp"
}
trap cleanup EXIT
fail() { echo "FAIL: $*"; code=1; }
. "$(dirname "$0")/../wait.sh" # wait_until
export WORMGEAR_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0" WORMGEAR_PREFIX=LOGT_

"$W" record "$tmp/run.lcmlog" >"$tmp/logger.out" 2>&1 &
lpid=$!
"$D" --rate 0.01 --set omega=0.7 --state-dir "$tmp" >"$tmp/d.out" 2>&1 &
dpid=$!
# until the daemon answers (it then takes commands)
wait_until 10 "$C" --timeout 0.5 status >/dev/null 2>&1 || fail "no daemon: $(cat "$tmp/d.out")"
"$T" "$WORMGEAR_URL" LOGT_ 2.5 >"$tmp/tap.txt" &
tpid=$!
sleep 1
"$C" set omega=0.75 >/dev/null || fail "wgctl set: $(cat "$tmp/d.out")"
# the hostile sender, on other channels of the same group and port
"$SPOOF" "$WORMGEAR_URL" LOGS_ 1 >"$tmp/spoof.out" 2>&1 &
spid=$!
wait $tpid || fail "wgtap exit $? (the hostile fragments reached it?)"
wait $spid || fail "wgspoof: $(cat "$tmp/spoof.out")"; spid=
kill -TERM $dpid; wait $dpid; dpid=
sleep 0.3
kill -0 $lpid 2>/dev/null || fail "wglog record ended before SIGINT: $(cat "$tmp/logger.out")"
kill -INT $lpid; wait $lpid; rc=$?; lpid=
[ $rc = 0 ] || fail "wglog record exit $rc: $(cat "$tmp/logger.out")"
cat "$tmp/logger.out"
grep -q "^wglog: recorded [0-9]* messages" "$tmp/logger.out" || fail "no closing line"

"$W" summary "$tmp/run.lcmlog" >"$tmp/sum.txt" || fail "wglog summary: exit $?"
cat "$tmp/sum.txt"
for ch in STATE POINCARE CONTACT STATUS PARAMS CMD ACK; do
    grep -q "^LOGT_$ch " "$tmp/sum.txt" || fail "summary lacks LOGT_$ch"
done
"$W" export "$tmp/run.lcmlog" --channel 'LOGT_.*' --out "$tmp/csv" -q || fail "wglog export: exit $?"
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
# the hostile sender's channels are in the log (it recorded on through the wrapping
# fragments), and the daemon's STATE goes on after them: its last sample is after
# wgspoof's first message
grep -q "^LOGS_STATUS " "$tmp/sum.txt" || fail "summary lacks the hostile sender's LOGS_STATUS"
"$W" export "$tmp/run.lcmlog" --channel 'LOGS_STATE' --out "$tmp/spoofcsv" -q ||
    fail "wglog export LOGS_STATE: exit $?"
first_spoof=$(awk -F, 'NR == 2 { print $1 }' "$tmp/spoofcsv/LOGS_STATE.csv")
last_state=$(awk -F, 'END { print $1 }' "$tmp/csv/LOGT_STATE.csv")
echo "first hostile STATE received at $first_spoof us, last STATE at $last_state us"
[ -n "$first_spoof" ] && [ "$last_state" -gt "$first_spoof" ] 2>/dev/null ||
    fail "no STATE recorded after the hostile sender began"

# refusals: an existing file, without --force; with it, the file is written
"$W" record "$tmp/run.lcmlog" --duration 0.2 >"$tmp/r.out" 2>&1; rc=$?
[ $rc = 1 ] || fail "record onto an existing log: exit $rc, expected 1"
grep -q "run.lcmlog exists; give another name, or --force to overwrite it" "$tmp/r.out" ||
    fail "record onto an existing log said: $(cat "$tmp/r.out")"
"$W" summary "$tmp/run.lcmlog" | grep -q "^LOGT_STATE " || fail "the refused record changed the log"
"$W" record "$tmp/run.lcmlog" --force --duration 0.3 >"$tmp/r.out" 2>&1 ||
    fail "record --force: exit $?: $(cat "$tmp/r.out")"
grep -q "recorded no message in 0.3 s: nothing was heard on $WORMGEAR_URL" "$tmp/r.out" ||
    fail "record with no sender said: $(cat "$tmp/r.out")"
[ ! -s "$tmp/run.lcmlog" ] || fail "record --force did not empty the log"
# options of the other commands, and a URL LCM refuses (no file left behind)
"$W" record "$tmp/o.lcmlog" --out "$tmp" >"$tmp/r.out" 2>&1; rc=$?
[ $rc = 2 ] && grep -q "wglog: --out is an option of export, not of record" "$tmp/r.out" ||
    fail "record --out: exit $rc: $(cat "$tmp/r.out")"
"$W" summary "$tmp/run.lcmlog" --duration 1 >"$tmp/r.out" 2>&1; rc=$?
[ $rc = 2 ] && grep -q "wglog: --duration is an option of record, not of summary" "$tmp/r.out" ||
    fail "summary --duration: exit $rc: $(cat "$tmp/r.out")"
"$W" record "$tmp/o.lcmlog" --url 'udpm://239.255.76.67:x' >"$tmp/r.out" 2>&1; rc=$?
[ $rc = 2 ] && grep -q "cannot open LCM URL 'udpm://239.255.76.67:x'" "$tmp/r.out" ||
    fail "record with a bad URL: exit $rc: $(cat "$tmp/r.out")"
"$W" record "$tmp/o.lcmlog" --url 'udpm://239.255.76.67:0?ttl=0' >"$tmp/r.out" 2>&1; rc=$?
[ $rc = 2 ] && grep -q "a udpm:// URL with port 0: give the bus's port" "$tmp/r.out" ||
    fail "record on port 0: exit $rc: $(cat "$tmp/r.out")"
[ ! -e "$tmp/o.lcmlog" ] || fail "record with a bad URL left a file"
# a write that fails: /dev/full, while the daemon publishes
"$D" --rate 0.01 --state-dir "$tmp" >"$tmp/d.out" 2>&1 &
dpid=$!
wait_until 10 "$C" --timeout 0.5 status >/dev/null 2>&1 || fail "no daemon: $(cat "$tmp/d.out")"
# --channel: only the channels matching, the others counted as left out
"$W" record "$tmp/ch.lcmlog" --channel 'LOGT_STATUS' --duration 1.5 >"$tmp/r.out" 2>&1 ||
    fail "record --channel: exit $?: $(cat "$tmp/r.out")"
grep -q "messages on channels not matching --channel left out" "$tmp/r.out" ||
    fail "record --channel said: $(cat "$tmp/r.out")"
"$W" summary "$tmp/ch.lcmlog" >"$tmp/chsum.txt" || fail "summary of the --channel log: exit $?"
grep -q "^LOGT_STATUS " "$tmp/chsum.txt" && [ "$(grep -c '^LOGT_' "$tmp/chsum.txt")" = 1 ] ||
    fail "record --channel LOGT_STATUS wrote: $(cat "$tmp/chsum.txt")"
"$W" record /dev/full --force --duration 3 >"$tmp/r.out" 2>&1; rc=$?
[ $rc = 1 ] || fail "record to /dev/full: exit $rc, expected 1"
grep -q "writing /dev/full failed: No space left on device" "$tmp/r.out" ||
    fail "record to /dev/full said: $(cat "$tmp/r.out")"
kill -TERM $dpid; wait $dpid; dpid=
exit $code

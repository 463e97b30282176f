#!/bin/sh
# test_java.sh decode WGENC JAR LCMJAR JAVAC JAVA SRCDIR
#   the Java classes of our types decode the bytes the C bindings encode,
#   with equal fingerprints (java/DecodeTest.java).
# test_java.sh spy WORMGEARD JAR LCMJAR JAVAC JAVA SRCDIR WGSPY PRELOAD WGSPOOF
#   under Xvfb: lcm-spy (in-process, java/SpyCheck.java) lists the daemon's
#   channels with our types and counts messages; then, with the socket
#   filter wgspy preloads (PRELOAD, WG_MCAST_BIND=whole), it counts on
#   after wgspoof's hostile datagrams (unfiltered, one wrapping fragment
#   pair ended LCM's Java reader thread, and the counts stood still); the
#   wgspy launcher starts and runs beside wgspoof without a Java exception.
#   Exit 77 (skip) without Xvfb. Run through netns.sh (host-local URL only).
# test_java.sh launcher WGSPY [JAR]
#   wgspy from the build tree, with or without a JDK (JAR: the build's type
#   jar, when it built one): a --jar or WORMGEAR_JAR that is not there is
#   named; with no display it says so in one line before starting Java (it
#   died in a HeadlessException's stack trace); with no route to a udpm://
#   URL's group (a network namespace of its own) it says so in one line, as
#   the C clients do, and with one it starts Java; with JAR and lcm.jar,
#   --print-cp finds the build's jar by itself (it looked only where an
#   installed copy finds one, and said "not found").
mode=$1; shift
code=0
tmp=$(mktemp -d) || exit 1
pids=
cleanup() { for p in $pids; do kill -KILL "$p" 2>/dev/null; done; rm -rf "$tmp"; }
trap cleanup EXIT
fail() { echo "FAIL: $*"; code=1; }
. "$(dirname "$0")/../wait.sh" # wait_until

if [ "$mode" = launcher ]; then
    SPY=$1 JAR=${2:-}
    unset WORMGEAR_JAR
    "$SPY" --jar /nonexist.jar --print-cp >"$tmp/out" 2>"$tmp/err"; rc=$?
    [ $rc -eq 1 ] && grep -q "^wgspy: --jar /nonexist.jar: no such file$" "$tmp/err" ||
        fail "--jar /nonexist.jar: exit $rc: $(cat "$tmp/err")"
    WORMGEAR_JAR=/nonexist2.jar "$SPY" --print-cp >"$tmp/out" 2>"$tmp/err"; rc=$?
    [ $rc -eq 1 ] && grep -q "^wgspy: WORMGEAR_JAR=/nonexist2.jar: no such file$" "$tmp/err" ||
        fail "WORMGEAR_JAR=/nonexist2.jar: exit $rc: $(cat "$tmp/err")"
    # no display: one line, and Java never started (a stand-in that says if it was)
    : >"$tmp/fake.jar"
    printf '#!/bin/sh\necho "Exception in thread main java.awt.HeadlessException" >&2\nexit 1\n' \
        >"$tmp/java"
    chmod +x "$tmp/java"
    env -u DISPLAY -u WAYLAND_DISPLAY JAVA="$tmp/java" "$SPY" --jar "$tmp/fake.jar" \
        >"$tmp/out" 2>"$tmp/err"; rc=$?
    [ $rc -eq 1 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] &&
        grep -q "^wgspy: lcm-spy needs a display" "$tmp/err" ||
        fail "no display: exit $rc, want 1 and one line: $(cat "$tmp/err")"
    grep -q Exception "$tmp/err" && fail "no display: Java was started: $(cat "$tmp/err")"
    env -u DISPLAY -u WAYLAND_DISPLAY "$SPY" --jar "$tmp/fake.jar" --print-cp >"$tmp/out" \
        2>"$tmp/err" && grep -q "needs a display" "$tmp/err" &&
        fail "--print-cp asked for a display: $(cat "$tmp/err")"
    # no route to the group (a network namespace of its own, nothing in it): one line, Java
    # never started; with a route on lo, the launcher goes on to start Java (a stand-in)
    printf '#!/bin/sh\necho "java started"\n' >"$tmp/java-ok"
    chmod +x "$tmp/java-ok"
    if unshare -n true 2>/dev/null && command -v ip >/dev/null; then
        # each URL with the group it names (LCM's default when empty)
        for ug in "udpm://239.255.76.67:7667?ttl=0 239.255.76.67" "udpm://?ttl=0 239.255.76.67" \
                  "udpm://239.1.2.3 239.1.2.3"; do
            url=${ug% *} g=${ug#* }
            DISPLAY=:0 JAVA="$tmp/java-ok" unshare -n "$SPY" --jar "$tmp/fake.jar" --url "$url" \
                >"$tmp/out" 2>"$tmp/err"; rc=$?
            [ $rc -eq 1 ] && [ "$(wc -l <"$tmp/err")" -eq 1 ] &&
                grep -q "^wgspy: no route to the multicast group $g (Network is unreachable)" \
                    "$tmp/err" && ! grep -q "java started" "$tmp/out" ||
                fail "no route, --url $url: exit $rc, want 1 and one line: $(cat "$tmp/err")"
        done
        DISPLAY=:0 JAVA="$tmp/java-ok" WGSPY="$SPY" JARF="$tmp/fake.jar" unshare -n sh -c \
            'ip link set lo up && ip route add 239.0.0.0/8 dev lo &&
             "$WGSPY" --jar "$JARF" --url "udpm://239.255.76.67:7667?ttl=0"' >"$tmp/out" \
            2>"$tmp/err"; rc=$?
        [ $rc -eq 0 ] && grep -q "java started" "$tmp/out" ||
            fail "a route on lo: exit $rc, Java not started: $(cat "$tmp/out" "$tmp/err")"
        echo "no route: one line and exit 1 for 3 URLs; a route on lo: Java started"
    else
        echo "no unshare -n here (not root?): the route check not tried"
    fi
    if [ -n "$JAR" ] && [ -f "$JAR" ] && { [ -f /usr/share/java/lcm.jar ] ||
                                          [ -f /usr/local/share/java/lcm.jar ]; }; then
        "$SPY" --print-cp >"$tmp/out" 2>"$tmp/err" ||
            fail "build tree, no --jar: exit $?: $(cat "$tmp/err")"
        grep -q ":$JAR\(:\|$\)" "$tmp/out" ||
            fail "build tree, no --jar: not the build's $JAR: $(cat "$tmp/out" "$tmp/err")"
        echo "build tree: --print-cp $(cat "$tmp/out")"
    else
        echo "no type jar in this build (or no lcm.jar): the build tree's own jar not checked"
    fi
    exit $code
fi

if [ "$mode" = decode ]; then
    ENC=$1 JAR=$2 LCMJAR=$3 JAVAC=$4 JAVA=$5 SRC=$6
    "$ENC" "$tmp" || { echo "FAIL: wgenc"; exit 1; }
    mkdir "$tmp/cls"
    "$JAVAC" -nowarn -cp "$JAR:$LCMJAR" -d "$tmp/cls" "$SRC/DecodeTest.java" || exit 1
    "$JAVA" -cp "$tmp/cls:$JAR:$LCMJAR" DecodeTest "$tmp" || code=1
    exit $code
fi

D=$1 JAR=$2 LCMJAR=$3 JAVAC=$4 JAVA=$5 SRC=$6 SPY=$7 PRELOAD=$8 SPOOF=$9
command -v Xvfb >/dev/null || { echo "no Xvfb (Debian: xvfb): skipped"; exit 77; }
n=90
while [ -e /tmp/.X11-unix/X$n ] || [ -e /tmp/.X$n-lock ]; do n=$((n + 1)); done
Xvfb :$n -screen 0 1280x1024x24 -nolisten tcp >"$tmp/xvfb.log" 2>&1 &
pids="$pids $!"
export DISPLAY=:$n WORMGEAR_URL="udpm://239.255.76.67:$((20000 + $$ % 20000))?ttl=0" WORMGEAR_PREFIX=SPYT_
"$D" --rate 0.01 --state-dir "$tmp" >"$tmp/d.out" 2>&1 &
pids="$pids $!"
mkdir "$tmp/cls"
"$JAVAC" -nowarn -cp "$LCMJAR" -d "$tmp/cls" "$SRC/SpyCheck.java" || exit 1
cp=$("$SPY" --jar "$JAR" --print-cp) || { echo "FAIL: wgspy --print-cp"; exit 1; }
if command -v xdpyinfo >/dev/null; then
    wait_until 5 xdpyinfo >/dev/null 2>&1
else
    sleep 1
fi
"$JAVA" -Djava.net.preferIPv4Stack=true -cp "$tmp/cls:$cp" SpyCheck 4 "$WORMGEAR_URL" \
    >"$tmp/spy.out" 2>"$tmp/spy.err" || fail "SpyCheck exit $?: $(cat "$tmp/spy.err")"
cat "$tmp/spy.out"
grep -q "Found 9 LCM types" "$tmp/spy.out" || fail "lcm-spy did not find our 9 types"
for t in STATE POINCARE CONTACT STATUS PARAMS SCOPE; do
    lt=$(echo $t | tr 'A-Z' 'a-z')
    grep -q "row: | SPYT_$t | ${lt}_t | .* | 0$" "$tmp/spy.out" ||
        fail "lcm-spy lists no SPYT_$t decoded as ${lt}_t with 0 undecodable"
done
# hostile datagrams between two looks at the table, lcm-spy filtered as wgspy runs it
status_count() { sed -n 's/^row: | SPYT_STATUS | status_t | \([0-9]*\) .*/\1/p' "$1"; }
round0() { grep -q "round 0 done" "$tmp/spy2.out"; }
env LD_PRELOAD="$PRELOAD" WG_MCAST_BIND=whole "$JAVA" -Djava.net.preferIPv4Stack=true \
    -cp "$tmp/cls:$cp" SpyCheck 3 "$WORMGEAR_URL" 3 >"$tmp/spy2.out" 2>"$tmp/spy2.err" &
spid=$!
wait_until 30 round0 || fail "SpyCheck's first look never came: $(cat "$tmp/spy2.err")"
"$SPOOF" "$WORMGEAR_URL" SPYT_ 1 >/dev/null 2>&1
wait_exit "$spid" 30
[ "$exit_status" = 0 ] || fail "SpyCheck beside wgspoof -> exit $exit_status"
sed -n '/round 0 done/,$p' "$tmp/spy2.out" >"$tmp/spy2.after"
n0=$(status_count "$tmp/spy2.out" | head -1) n1=$(status_count "$tmp/spy2.after")
echo "lcm-spy, filtered, beside wgspoof: SPYT_STATUS messages $n0 before, $n1 after"
[ "${n1:-0}" -gt "${n0:-0}" ] ||
    fail "lcm-spy counted no STATUS after wgspoof's datagrams ($n0, then $n1)"
grep "Exception in thread" "$tmp/spy2.err" &&
    fail "LCM's Java reader died on wgspoof's datagrams"
# the launcher itself: starts, runs 3 s beside wgspoof, no exception, its filter found
"$SPOOF" "$WORMGEAR_URL" SPYT_ 3 >/dev/null 2>&1 &
pids="$pids $!"
timeout 3 "$SPY" --jar "$JAR" >"$tmp/wgspy.out" 2>&1
rc=$?
[ $rc -eq 124 ] || fail "wgspy exited early ($rc): $(cat "$tmp/wgspy.out")"
grep -q "Exception in thread\|Unrecognized option\|not found" "$tmp/wgspy.out" &&
    fail "wgspy: $(cat "$tmp/wgspy.out")"
exit $code

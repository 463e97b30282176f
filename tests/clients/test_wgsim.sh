#!/usr/bin/env bash
# wgsim command line: CSV headers, row counts, exit codes, --help.
# usage: test_wgsim.sh WGSIM SCENEDIR
set -u
WGSIM=$1
export WG_SCENE_PATH=$2
tmp=$(mktemp -d)
trap 'rm -rf "$tmp"' EXIT
fail=0
check() { # check DESCRIPTION COMMAND...
    local what=$1; shift
    if "$@"; then echo "ok   $what"; else echo "FAIL $what"; fail=1; fi
}
expect_exit() { # expect_exit CODE PATTERN ARGS...
    local code=$1 pat=$2; shift 2
    "$WGSIM" "$@" >"$tmp/out" 2>"$tmp/err"
    local rc=$?
    if [ "$rc" -ne "$code" ]; then
        echo "FAIL wgsim $* exited $rc, expected $code"; cat "$tmp/err"; fail=1; return
    fi
    if ! grep -q -- "$pat" "$tmp/err" "$tmp/out"; then
        echo "FAIL wgsim $*: no '$pat' in output:"; cat "$tmp/err"; fail=1; return
    fi
    echo "ok   wgsim $* -> $code ($pat)"
}

# --help lists every option and every parameter of MODEL.md s2 with a range
"$WGSIM" --help >"$tmp/help"; check "--help exits 0" test $? -eq 0
for opt in --scene --set --periods --transient --steps-per-period --stepper --model \
           --poincare --events --trace --units; do
    grep -q -- "$opt" "$tmp/help" || { echo "FAIL --help lacks $opt"; fail=1; }
done
for p in omega xi_p xi_g k_a phi1 e_m phi2 f_m f_e phi b b_j a1 a2 a3 mu1 mu2 \
         k1x k1y k1z k2x k2y k2z xi1x xi1y xi1z xi2x xi2y xi2z z1 z2 rho1 rho2 j1 j2; do
    grep -qE "^  $p +[^ ]+ +\[" "$tmp/help" || { echo "FAIL --help lacks parameter $p"; fail=1; }
done

# CSV headers, exactly
"$WGSIM" --set omega=0.7 --transient 5 --periods 12 --poincare "$tmp/p.csv" \
    --events "$tmp/e.csv" --trace "$tmp/t.csv"
check "run with outputs exits 0" test $? -eq 0
check "poincare header" test "$(head -1 "$tmp/p.csv")" = \
    "period,tau,omega,x_n,dx_n,F,x1,y1,z1,x2,y2,z2,s,dx1,dy1,dz1,dx2,dy2,dz2,ds,theta1,theta2"
check "events header" test "$(head -1 "$tmp/e.csv")" = "tau,contact,kind,velocity"
check "trace header" test "$(head -1 "$tmp/t.csv")" = "tau,omega,x_n,dx_n,F,theta1,theta2"
# theta1, theta2 in [0, 2 pi); over the 12 recorded periods (z1 = 3, z2 = 37) the
# worm turns 4 times and the wheel 12/37 of a turn, up to the elastic change
check "trace angles in [0, 2 pi)" \
    bash -c "awk -F, 'NR>1 && (\$6 < 0 || \$6 >= 6.283185307179586 || \$7 < 0 || \$7 >= 6.283185307179586) { bad=1 } END { exit bad }' '$tmp/t.csv'"
check "trace angles: the worm 4 turns, the wheel 12/37 turn in 12 periods" \
    bash -c "awk -F, 'function w(d) { while (d > 3.141592653589793) d -= 6.283185307179586; while (d <= -3.141592653589793) d += 6.283185307179586; return d }
        NR==2 { a=\$6; b=\$7 } NR>2 { t1 += w(\$6-a); t2 += w(\$7-b); a=\$6; b=\$7 }
        END { t1 /= 6.283185307179586; t2 /= 6.283185307179586; exit !(t1 > 3.98 && t1 < 4.01 && t2 > 0.32 && t2 < 0.329) }' '$tmp/t.csv'"
check "poincare theta1 at a section: 2 pi (period mod 3) / 3 + a small elastic part" \
    bash -c "awk -F, 'NR>1 { r = 6.283185307179586 * (\$1 % 3) / 3; d = \$21 - r; if (d > 3.14) d -= 6.283185307179586; if (d < -0.001 || d > 0.05) bad=1 } END { exit bad }' '$tmp/p.csv'"
check "one poincare row per recorded period" test "$(tail -n +2 "$tmp/p.csv" | wc -l)" -eq 12
check "period column counts from the run start" test "$(sed -n 2p "$tmp/p.csv" | cut -d, -f1)" = 6
check "trace has every recorded step" test "$(tail -n +2 "$tmp/t.csv" | wc -l)" -eq $((12 * 128))
check "events name contacts and kinds" \
    bash -c "tail -n +2 '$tmp/e.csv' | cut -d, -f2,3 | grep -qE '^mesh,(separation|drive_impact)$'"
check "no event kind outside the four" \
    bash -c "! tail -n +2 '$tmp/e.csv' | cut -d, -f3 | grep -vqE '^(separation|drive_impact|back_impact|back_release)$'"
"$WGSIM" --units physical --periods 3 --transient 0 --poincare - >"$tmp/pp.csv"
check "physical units header" bash -c "head -1 '$tmp/pp.csv' | grep -q '^period,t_s,f_mesh_hz,x_n_um,dx_n_m_s,F_N,x1_um'"
check "physical x_n in micrometres (~100-200 um)" \
    bash -c "awk -F, 'NR==2 { exit !(\$4 > 50 && \$4 < 400) }' '$tmp/pp.csv'"

# summary
"$WGSIM" --periods 20 --transient 10 >"$tmp/sum"
for key in "omega_n = 31901" "steps/s" "ns/step" "motion " "impacts " "kernel full"; do
    grep -q -- "$key" "$tmp/sum" || { echo "FAIL summary lacks '$key'"; cat "$tmp/sum"; fail=1; }
done

# exit codes and messages
expect_exit 2 "unknown option" --frobnicate
expect_exit 2 "allowed values are default, rk4, rk4-event" --stepper euler
expect_exit 2 "allowed values are consistent, printed" --model fancy
expect_exit 2 "omega = 99 out of range \[0.01, 10\]" --set omega=99
# a value a double cannot hold: the text typed is quoted beside what it became
expect_exit 2 "omega = 0 out of range \[0.01, 10\] (typed '1e-400', which a double holds as 0)" --set omega=1e-400
expect_exit 2 "unknown parameter 'nope'" --set nope=1
expect_exit 2 "z2 = 37.5 must be a whole number in \[4, 1000\]" --set z2=37.5
expect_exit 2 "must be an integer in \[8, 65536\]" --steps-per-period 4
expect_exit 2 "need N >= " --set omega=0.05 --steps-per-period 64
expect_exit 2 "supports the rk4 stepper only" --model printed --stepper rk4-event
# the stability refusal names the option that sets N
expect_exit 2 "need N >= 1062 .*; --steps-per-period sets N" --set omega=0.01
# two CSVs on stdout would interleave: refused before anything is written
expect_exit 2 "--poincare and --events both write to '-': at most one output may go to stdout" \
    --poincare - --events - --periods 2 --transient 0
check "two outputs on stdout: nothing written there" test ! -s "$tmp/out"
expect_exit 2 "--poincare, --events and --trace all write to '-'" \
    --poincare - --events - --trace - --periods 2 --transient 0
expect_exit 2 "--events and --trace both write to '-'" --events - --trace - --periods 2
expect_exit 2 "scene 'nosuch' not found" --scene nosuch
printf '[params]\nomega = 1\nxi_p = 7\n' >"$tmp/bad.ini"
# a scene file that cannot be run is a --scene to correct: exit 2, as
# wgsweep, wgcont and wormgeard (it was 1 by path, 2 by name)
expect_exit 2 "bad.ini:3: xi_p: value 7 out of range \[0, 2\]" --scene "$tmp/bad.ini"
# a scene file that cannot be opened: the reason is said
expect_exit 2 "cannot open scene file .*no-dir/good: No such file or directory" \
    --scene "$tmp/no-dir/good"
# a directory is not a scene (it ran the defaults under its name, exit 0),
# by path or by name, and the scenes listed leave it out
mkdir -p "$tmp/sp/x.ini"
expect_exit 2 "scene file .*sp/x.ini is a directory, not a regular file" \
    --scene "$tmp/sp/x.ini"
WG_SCENE_PATH="$tmp/sp" expect_exit 2 "sp/x.ini is a directory, not a regular file" --scene x
WG_SCENE_PATH="$tmp/sp" expect_exit 2 "scenes there: lowfreq, realistic" --scene nosuch
# a key given twice: refused where it was (the later value won, silently)
printf '[params]\nomega = 1\nomega = 0.5\n' >"$tmp/dup.ini"
expect_exit 2 "dup.ini:3: \[params\] omega: given twice (first at line 2)" --scene "$tmp/dup.ini"
expect_exit 0 "motion" --model printed --periods 5 --transient 0

# Stops.
. "$(dirname "$0")/../wait.sh" # wait_exit
whole_rows() { # whole_rows FILE FIELDS: ends in a newline, every line FIELDS fields
    [ "$(tail -c1 "$1" | od -An -tx1 | tr -d ' ')" = 0a ] &&
        awk -F, -v n="$2" 'NF != n { bad = 1 } END { exit bad }' "$1"
}
# Ctrl-C (SIGINT; a background job ignores it, wgsim's handler does not)
# stops the run at the end of a chunk of whole periods: exit 130, every row
# whole, one line saying after how many periods. It used to end by the
# signal's default action with the last row torn.
"$WGSIM" --periods 100000000 --transient 0 --poincare "$tmp/int.csv" 2>"$tmp/int.err" &
pid=$!
sleep 1
kill -INT $pid
wait_exit $pid 10; rc=$exit_status
rows=$(($(wc -l <"$tmp/int.csv") - 1))
check "Ctrl-C: exit 130 ($rc)" test "$rc" = 130
check "Ctrl-C: $rows rows, every one whole" whole_rows "$tmp/int.csv" 22
said_rows() { # one line on stderr, naming the periods run
    [ "$(wc -l <"$tmp/int.err")" -eq 1 ] &&
        grep -q "^wgsim: interrupted after $rows of 100000000 periods" "$tmp/int.err"
}
check "Ctrl-C: one line, interrupted after $rows periods" said_rows
# Blocked writing to a full pipe (a FIFO nobody reads): the first SIGTERM
# leaves wgsim there (the write goes on after the handler: it would fail
# with EINTR and stdio drop a buffer of rows); a second ends it at once.
# blocked PID: wait until it is blocked writing to the pipe (its handlers are
# installed by then; under a loaded sanitizer build 0.5 s was not always
# enough, and a SIGTERM before them ended it by the default action), where
# the kernel says so (/proc/PID/wchan); else half a second
blocked() { wait_until 10 grep -q pipe_write "/proc/$1/wchan" 2>/dev/null || sleep 0.5; }
mkfifo "$tmp/fifo1" "$tmp/fifo2"
exec 3<>"$tmp/fifo1"
"$WGSIM" --periods 100000000 --transient 0 --trace "$tmp/fifo1" 2>"$tmp/f1.err" 3>&- &
pid=$!
blocked $pid
kill -TERM $pid
sleep 0.5
check "first SIGTERM, blocked on a full pipe: still running" kill -0 $pid
kill -TERM $pid
wait_exit $pid 10; rc=$exit_status
exec 3>&-
check "second SIGTERM: ends it at once, by the signal ($rc)" test "$rc" = 143
# ... and once the pipe drains, the first SIGTERM's stop: no row lost or torn
exec 3<>"$tmp/fifo2"
"$WGSIM" --periods 100000000 --transient 0 --trace "$tmp/fifo2" 2>"$tmp/f2.err" 3>&- &
pid=$!
blocked $pid
kill -TERM $pid
sleep 0.3
exec 4<"$tmp/fifo2" # the reader, open before our end closes (else SIGPIPE)
timeout 30 cat <&4 >"$tmp/f2.csv" 3>&- 4<&- &
cat=$!
exec 3>&- 4<&-
wait_exit $pid 20; rc=$exit_status
wait $cat
p=$(sed -n 's/^wgsim: interrupted after \([0-9]*\) of .*/\1/p' "$tmp/f2.err")
check "SIGTERM blocked on a pipe, then drained: exit 130 ($rc)" test "$rc" = 130
drained() { # every trace row whole, N = 128 of them for each period said
    whole_rows "$tmp/f2.csv" 7 && [ "${p:-0}" -gt 0 ] &&
        [ $(($(wc -l <"$tmp/f2.csv") - 1)) -eq $((p * 128)) ]
}
check "... every trace row whole, 128 for each of the $p periods" drained

# --model printed over a scene whose start state is given for the consistent
# model: refused (its 14 values were read in the printed model's 16 places)
printf '[initial]\nstate = given\n' >"$tmp/given.ini"
for k in x1 y1 z1 x2 y2 z2 s dx1 dy1 dz1 dx2 dy2 dz2 ds; do echo "$k = 0.01" >>"$tmp/given.ini"; done
expect_exit 0 "motion" --scene "$tmp/given.ini" --periods 2 --transient 0
# a dimensionless parameter's unit reads "-" in the help, as in wgctl params
expect_exit 0 "^  xi_p  -   \[0, 2\] 0.08: mesh damping ratio" --help
# the printed form has no RK4 limit: not claimed as "N >= 1"
expect_exit 0 "no RK4 limit checked (the printed form grows by design)" --model printed --periods 2
expect_exit 0 "RK4 limit N >= 11;" --periods 2
# a printed form that blows up (a1 > a3: its theta1 coupling wins) does so at
# tau ~45.7 at any N: the advice is the model's, not "Try more
# --steps-per-period", which it gave
printed="--model printed --set a1=0.8 --set a2=0.1 --set a3=0.5916079783099616 --periods 200"
for n in 128 1024; do
    expect_exit 1 "^wgsim: step [0-9]* (tau = 45\.7[0-9]*): .*the state blew up; the last good state is kept\. The printed equations (--model printed) are not energy-consistent (their theta1 coupling is anti-restoring: the mesh force does net work) and grow at any --steps-per-period: twice the steps blowing up at about the same tau is the model, not the step; --model consistent is the energy-consistent form" \
        $printed --steps-per-period $n
    check "printed, N = $n: no 'Try more --steps-per-period'" \
        bash -c "! grep -q 'Try more' '$tmp/err' && [ \$(wc -l <'$tmp/err') -eq 1 ]"
done
expect_exit 2 "^wgsim: --model printed: scene given gives its start state (state = given) for the consistent model, 14 values" \
    --scene "$tmp/given.ini" --model printed --periods 2

# one file named for two outputs: refused (the two streams clobbered it)
expect_exit 2 "^wgsim: --poincare and --events both write $tmp/same.csv: give each its own file" \
    --periods 5 --poincare "$tmp/same.csv" --events "$tmp/same.csv"

# a write that fails (a full disk) is said and fails the run; it exited 0
# with the file cut short
if [ -w /dev/full ]; then
    expect_exit 1 "^wgsim: writing /dev/full failed.*the file is incomplete" --periods 200 --poincare /dev/full
    # the summary on a standard output that takes nothing: said once, exit 1
    # (it exited 0); the CSV on it (--poincare -): its own one message
    "$WGSIM" --periods 10 >/dev/full 2>"$tmp/err"; rc=$?
    if [ $rc -eq 1 ] && [ "$(grep -c . "$tmp/err")" -eq 1 ] &&
        grep -q "^wgsim: writing the standard output failed: No space left on device" "$tmp/err"; then
        echo "ok   wgsim --periods 10 >/dev/full -> 1, one message"
    else
        echo "FAIL wgsim --periods 10 >/dev/full: exit $rc: $(cat "$tmp/err")"; fail=1
    fi
    "$WGSIM" --periods 10 --poincare - >/dev/full 2>"$tmp/err"; rc=$?
    if [ $rc -eq 1 ] && [ "$(grep -c . "$tmp/err")" -eq 1 ]; then
        echo "ok   wgsim --poincare - >/dev/full -> 1, one message"
    else
        echo "FAIL wgsim --poincare - >/dev/full: exit $rc: $(cat "$tmp/err")"; fail=1
    fi
fi

exit $fail

# wait.sh - sourced by the test scripts (sh or bash) that wait for
# something to happen: a line in a log, a daemon that answers, a process
# that ends. Every wait is bounded in wall time, so a test fails on what
# did not happen, saying so, instead of hanging until ctest's timeout; and
# none is a fixed sleep, which is either too long or, on a loaded machine,
# too short.

# wait_until SECONDS CMD [ARG...]: run CMD until it succeeds, every 0.1 s,
# for SECONDS (a whole number) of wall time at most, however long CMD
# itself takes. Returns 0 once CMD has succeeded, 1 if it never did. A
# condition that is a pipeline or a negation goes in a small function.
wait_until() {
    local wait_end_ms
    wait_end_ms=$(($(date +%s%N) / 1000000 + $1 * 1000))
    shift
    until "$@"; do
        [ $(($(date +%s%N) / 1000000)) -lt $wait_end_ms ] || return 1
        sleep 0.1
    done
}

# wait_gone PID: true once PID (a child of this shell) has ended.
wait_gone() { ! kill -0 "$1" 2>/dev/null; }

# wait_exit PID SECONDS: wait up to SECONDS for PID (a child of this shell)
# to end, and set exit_status to its exit status, or to "timeout" if it
# was still running (it is then killed). Not in $(...): wait needs this
# shell.
wait_exit() {
    if wait_until "$2" wait_gone "$1"; then
        wait "$1"
        exit_status=$?
    else
        kill -9 "$1"
        wait "$1" 2>/dev/null
        exit_status=timeout
    fi
}

# stop PID SIG: send SIG to PID and wait_exit it, 10 s at most.
stop() {
    kill "-$2" "$1"
    wait_exit "$1" 10
}

# A program stopped at a known point of its start: stderr_stall FIFO makes
# FIFO (a new name) a pipe already full (64 KiB, Linux's default capacity),
# held open at both ends on this shell's fd 3, so that a program started
# with 2>FIFO 3>&- blocks in its first write to stderr; `cat <&3` drains it
# (it never sees an end: wait for what it must have read), `exec 3>&-`
# closes it. Polling /proc for a moment instead hit the sanitizer runtime's
# own start before main, where no code of ours runs.
stderr_stall() {
    rm -f "$1" && mkfifo "$1" || return 1
    exec 3<>"$1"
    timeout 5 dd if=/dev/zero bs=65536 count=1 >&3 2>/dev/null
}

# in_stderr_write PID: true while PID is blocked in write(2, ...) (write is
# syscall 1 on x86-64, 64 on arm64 and riscv64: looked up once, not a poll).
case $(uname -m) in aarch64 | riscv64) write_nr=64 ;; *) write_nr=1 ;; esac
in_stderr_write() {
    case $(cat "/proc/$1/syscall" 2>/dev/null) in "$write_nr 0x2 "*) return 0 ;; esac
    return 1
}

# thread_unheld PID MASK: "TID SIGBLK" of the first thread of PID whose
# blocked signals lack a bit of MASK (hex, e.g. 0x4002: INT and TERM), or
# nothing.
thread_unheld() {
    for t in /proc/$1/task/*; do
        b=$(sed -n "s/^SigBlk:[[:space:]]*//p" "$t/status" 2>/dev/null)
        [ -z "$b" ] || [ $((0x$b & $2)) -eq $(($2)) ] || { echo "${t##*/} $b"; return; }
    done
}

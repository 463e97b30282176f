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

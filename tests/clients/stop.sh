# stop.sh - sourced by the client tests that stop a program by a signal.
# stop_rc PID SIG: send SIG to PID (a child of this shell), wait up to 10 s
# for it to end, and set stop_status to its exit status, or to "timeout"
# if it was still running (it is then killed, so a test fails on a hang
# instead of at ctest's timeout). Not in $(...): wait needs this shell.
stop_rc() {
    local pid=$1 t0
    kill "-$2" "$pid"
    t0=$(date +%s)
    while kill -0 "$pid" 2>/dev/null && [ $(($(date +%s) - t0)) -lt 10 ]; do sleep 0.1; done
    if kill -0 "$pid" 2>/dev/null; then
        kill -9 "$pid"
        wait "$pid" 2>/dev/null
        stop_status=timeout
    else
        wait "$pid"
        stop_status=$?
    fi
}

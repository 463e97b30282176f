/* report.h - what the daemon reports about itself: the STATUS heartbeat,
 * PARAMS, the foreground status line, and the loop's bookkeeping (flush
 * cadence, decimation, health).
 *
 * Figures are over the last STATUS interval: real-time factor, steps/s,
 * CPU share (process CPU time over wall time, all threads), loop duration
 * mean/max, impacts per period. Health: FAULT after a blow-up or policy
 * stop (until resume/reset/restore), LAGGING in realtime mode when behind
 * the pace target by more than lag_warn_ms or when an overrun happened in
 * the interval, else OK. */
#ifndef WGD_REPORT_H
#define WGD_REPORT_H

#include <stdint.h>

struct wgd;

/* Start the intervals at now; PARAMS "start" is published by the caller. */
void report_init(struct wgd *d);

/* Nothing to release. */
void report_fini(struct wgd *d);

/* Account one loop iteration of dur_ns (stepping and publishing). */
void report_loop(struct wgd *d, int64_t dur_ns);

/* Periodic work due at now: stream flush (50 Hz), STATE decimation, STATUS
 * (status_hz), PARAMS (1 Hz), foreground line (1 Hz). */
void report_tick(struct wgd *d, int64_t now_ns);

/* Compute and publish a STATUS message now (shutdown, tests). */
void report_status(struct wgd *d);

/* A fault was raised (engine_fault): publish the stream batches, which end
 * at the last good state, then a STATUS with health fault, at once. */
void report_fault(struct wgd *d);

/* Publish the full parameter set; reason as in params_t, client, cmd_seq
 * and cmd_utime of the causing command ("", -1, 0 if none). */
void report_params(struct wgd *d, const char *reason, const char *client, int64_t cmd_seq,
                   int64_t cmd_utime);

/* One-line human summary (foreground, sd_notify STATUS=): the same motion,
 * regime and impacts per period as STATUS. */
void report_line(const struct wgd *d, char *buf, unsigned len);

/* Recompute the STATE decimation from state_rate_hz and the step rate. */
void report_decimation(struct wgd *d);

/* What a change touched, for report_change. */
enum { REPORT_ORBIT = 1, REPORT_RATE = 2 };

/* After a change: with REPORT_ORBIT the regime tracker and the impacts per
 * period restart (they describe the new orbit only: set, ramp, reset,
 * restore); with REPORT_RATE the STATE decimation is recomputed (the step
 * rate moved); then PARAMS is published as report_params. */
void report_change(struct wgd *d, int what, const char *reason, const char *client,
                   int64_t cmd_seq, int64_t cmd_utime);

/* Names: "ok" "lagging" "fault"; "running" "paused", "stepping" (a step
 * command, or the steps TICKs owe in lockstep, being run) and "waiting"
 * (lockstep, running, nothing owed: for the next step command or TICK). */
const char *report_health_name(int health);
const char *report_run_name(const struct wgd *d);

#endif

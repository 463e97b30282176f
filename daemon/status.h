/* status.h - STATUS heartbeat, PARAMS publishing, the foreground status
 * line, and the loop's bookkeeping (flush cadence, decimation, health).
 *
 * Figures are over the last STATUS interval: real-time factor, steps/s,
 * CPU share (process CPU time over wall time, all threads), loop duration
 * mean/max, impacts per period. Health: FAULT after a blow-up or policy
 * stop (until resume/reset/restore), LAGGING in realtime mode when behind
 * the pace target by more than lag_warn_ms or when an overrun happened in
 * the interval, else OK. */
#ifndef WGD_STATUS_H
#define WGD_STATUS_H

#include <stdint.h>

struct wgd;

/* Start the intervals at now; PARAMS "start" is published by the caller. */
void status_init(struct wgd *d);

/* Nothing to release. */
void status_fini(struct wgd *d);

/* Account one loop iteration of dur_ns (stepping and publishing). */
void status_loop(struct wgd *d, int64_t dur_ns);

/* Periodic work due at now: stream flush (50 Hz), STATE decimation, STATUS
 * (status_hz), PARAMS (1 Hz), foreground line (1 Hz). */
void status_tick(struct wgd *d, int64_t now_ns);

/* Compute and publish a STATUS now (faults, tests). */
void status_publish(struct wgd *d);

/* Publish the full parameter set; reason as in params_t, client/cmd_seq of
 * the causing command ("" / -1 if none). */
void status_params(struct wgd *d, const char *reason, const char *client, int64_t cmd_seq);

/* One-line human summary (foreground, sd_notify STATUS=). */
void status_line(const struct wgd *d, char *buf, unsigned len);

/* Recompute the STATE decimation from state_rate_hz and the step rate. */
void status_decimation(struct wgd *d);

/* Names: "ok" "lagging" "fault"; "running" "paused" "stepping". */
const char *status_health_name(int health);
const char *status_run_name(const struct wgd *d);

#endif

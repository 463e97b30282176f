/* loop.h - the libev loop: LCM fd and timerfd in ev_io watchers, an
 * ev_idle for the stepping work, ev_signal for SIGINT/SIGTERM/SIGHUP.
 *
 * The timerfd (CLOCK_MONOTONIC, TFD_TIMER_ABSTIME, period tick_us) drives
 * pacing and housekeeping; the steps due come from pace_steps_due on the
 * monotonic clock, never from counting expirations. All stepping (a step
 * job, steps owed to TICKs, realtime steps due, fast mode) runs in chunks
 * of about a millisecond, and the LCM watcher has the higher priority, so
 * a command is answered between two chunks whatever the mode, rate or
 * backlog. Signal callbacks only set flags and break or wake the loop; the
 * tick does the work (reload). After each handler the work watcher is
 * started or stopped to match what is pending, so commands never reach
 * into the loop. */
#ifndef WGD_LOOP_H
#define WGD_LOOP_H

struct wgd;

/* SIGINT, SIGTERM and SIGHUP held (1) in the calling thread, pending, or
 * taken again (0): main holds them from its first line, before any thread
 * starts (every thread inherits the mask), and loop_init lets them through
 * once its watchers are there, one that came meanwhile first. One during
 * the start killed the daemon (exit 143, a HUP 129). */
void loop_hold_signals(int hold);

/* Create the loop, the timerfd and the watchers. WG_OK or WG_EIO with d->init_why. */
int loop_init(struct wgd *d);

/* Stop the watchers, close the timerfd, destroy the loop. */
void loop_fini(struct wgd *d);

/* Run until SIGINT/SIGTERM. */
void loop_run(struct wgd *d);

#endif

/* pace.h - how many steps are due: a pure function of the monotonic clock.
 *
 * Realtime pacing keeps simulated time on a line through an anchor:
 * target(now) = tau0 + (now - t0) * tau_per_ns, with tau_per_ns = rate *
 * omega_n / 1e9. At each tick the steps due are those whose end lies on or
 * before the target. Timer callbacks are never counted (libev merges late
 * ticks): a late tick simply finds more steps due. At most `cap` ticks'
 * worth of steps run in one tick; a tick that hits the cap is an overrun.
 * Policies: continue (keep catching up), freeze (drop the backlog: the
 * anchor moves, simulated time falls behind for good), stop (after N
 * consecutive overruns the caller pauses). Overruns within the start-up
 * grace after an anchor are counted apart and do not trigger the policy.
 * No I/O, no clock reads: tests feed fake time. */
#ifndef WGD_PACE_H
#define WGD_PACE_H

#include <stddef.h>
#include <stdint.h>

struct conf;

typedef struct pace_cfg {
    double tau_per_ns;     /* simulated tau per wall nanosecond (rate * omega_n / 1e9) */
    int64_t tick_ns;       /* tick period */
    double catchup_ticks;  /* cap, in ticks' worth of steps (>= 1) */
    int policy;            /* POLICY_* (conf.h) */
    int stop_after;        /* consecutive overruns for POLICY_STOP */
    int64_t grace_ns;      /* start-up grace after each anchor */
} pace_cfg;

typedef struct pace {
    pace_cfg cfg;
    int64_t t0_ns;         /* anchor: wall time ... */
    double tau0;           /* ... and simulated time on the line there */
    uint64_t overruns;     /* ticks that hit the cap (outside grace) */
    uint64_t grace_overruns; /* the same within the grace */
    uint64_t consecutive;  /* current run of overruns */
    double lag_tau;        /* backlog left after the last call, tau */
    double behind_tau;     /* backlog at the last call, before its steps, tau */
} pace;

typedef struct pace_due {
    uint64_t steps;        /* steps to run now */
    int overrun;           /* the cap was hit */
    int stop;              /* POLICY_STOP: the run should stop */
} pace_due;

/* Configure and anchor at (now_ns, tau); counters cleared. */
void pace_init(pace *p, const pace_cfg *cfg, int64_t now_ns, double tau);

/* Configure from the daemon's configuration (mode keys: rate, tick_us,
 * catchup_ticks, overrun_policy, overrun_stop_after, startup_grace_s) for a
 * scene whose unit of tau is 1/omega_n_rad_s, and anchor at (now_ns, tau);
 * the overrun counters are kept (start, mode command, reload). */
void pace_configure(pace *p, const struct conf *c, double omega_n_rad_s, int64_t now_ns,
                    double tau);

/* Move the anchor to (now_ns, tau) and restart the grace (resume, reset,
 * restore, rate change); counters kept. */
void pace_anchor(pace *p, int64_t now_ns, double tau);

/* Change the rate keeping simulated time continuous: re-anchors. */
void pace_set_rate(pace *p, double tau_per_ns, int64_t now_ns, double tau);

/* Steps due at now_ns for a simulation at time tau taking steps of h > 0.
 * Updates the overrun counters, the anchor (freeze) and lag_tau. */
pace_due pace_steps_due(pace *p, int64_t now_ns, double tau, double h);

/* The pace target at now_ns (simulated tau). */
double pace_target(const pace *p, int64_t now_ns);

/* Lag behind the target after the last call, in wall seconds. */
double pace_lag_s(const pace *p);

/* What the loop measured over one tick's interval (the start of the last
 * tick to the start of this one), for the overrun warning. */
typedef struct pace_load {
    int64_t gap_ns;        /* wall time (0: the first tick, nothing measured) */
    int64_t cpu_ns;        /* the loop thread's CPU time in it */
    int64_t busiest_ns;    /* its longest handler (wall) */
    uint64_t steps;        /* steps run in it */
    double ns_per_step;    /* measured cost of one step (<= 0: unknown) */
    double h;              /* step size, tau */
    double rate;           /* the rate key, for the message */
} pace_load;

/* The overrun warning after pace_steps_due reported an overrun, one line
 * in buf (after "overrun: "): how far behind the pace the tick found the run (the whole
 * backlog, not the part left over the cap), the cap and policy, the
 * measurement, and whose time it was, as the figures say: the daemon was
 * not scheduled (its loop ran under half the interval), the rate is more
 * than the model can run here (stepping alone needs 90 % of a core or
 * more at the measured cost of a step), the loop catching up a backlog
 * that an earlier stall left (most of its time went to steps), or the
 * daemon's other work. */
void pace_overrun_text(const pace *p, const pace_load *l, char *buf, size_t len);

/* Fast mode: steps for one chunk of about chunk_ns, given the measured cost
 * per step (ns; <= 0 when unknown). At least 64, at most 10 million. */
uint64_t pace_fast_chunk(double ns_per_step, int64_t chunk_ns);

#endif

/* pace.c - pacing as a pure function of the monotonic clock. */
#include "pace.h"

#include "conf.h"

#include <math.h>
#include <stdio.h>

void pace_init(pace *p, const pace_cfg *cfg, int64_t now_ns, double tau)
{
    *p = (pace){.cfg = *cfg};
    pace_anchor(p, now_ns, tau);
}

void pace_configure(pace *p, const conf *c, double omega_n_rad_s, int64_t now_ns, double tau)
{
    p->cfg = (pace_cfg){.tau_per_ns = c->rate * omega_n_rad_s * 1e-9,
                        .tick_ns = (int64_t)c->tick_us * 1000,
                        .catchup_ticks = c->catchup_ticks,
                        .policy = c->overrun_policy,
                        .stop_after = c->overrun_stop_after,
                        .grace_ns = (int64_t)(c->startup_grace_s * 1e9)};
    pace_anchor(p, now_ns, tau);
}

void pace_anchor(pace *p, int64_t now_ns, double tau)
{
    p->t0_ns = now_ns;
    p->tau0 = tau;
    p->consecutive = 0;
    p->lag_tau = 0.0;
}

void pace_set_rate(pace *p, double tau_per_ns, int64_t now_ns, double tau)
{
    p->cfg.tau_per_ns = tau_per_ns;
    pace_anchor(p, now_ns, tau);
}

double pace_target(const pace *p, int64_t now_ns)
{
    return p->tau0 + (double)(now_ns - p->t0_ns) * p->cfg.tau_per_ns;
}

double pace_lag_s(const pace *p)
{
    return p->cfg.tau_per_ns > 0 ? p->lag_tau / p->cfg.tau_per_ns * 1e-9 : 0.0;
}

/* Steps allowed in one tick: catchup_ticks ticks' worth, at least one. */
static uint64_t cap_steps(const pace *p, double h)
{
    double c = ceil(p->cfg.catchup_ticks * (double)p->cfg.tick_ns * p->cfg.tau_per_ns / h);
    return c < 1.0 ? 1 : c > 1e12 ? (uint64_t)1e12 : (uint64_t)c;
}

pace_due pace_steps_due(pace *p, int64_t now_ns, double tau, double h)
{
    pace_due d = {0, 0, 0};
    double backlog = pace_target(p, now_ns) - tau;
    p->behind_tau = backlog > 0 ? backlog : 0.0;
    /* steps whose end is on or before the target (tolerate rounding of tau) */
    double n = backlog > 0 ? floor(backlog / h + 1e-9) : 0.0;
    uint64_t cap = cap_steps(p, h);
    if (n > (double)cap) {
        d.overrun = 1;
        n = (double)cap;
        if (now_ns - p->t0_ns < p->cfg.grace_ns) {
            p->grace_overruns++;
        } else {
            p->overruns++;
            p->consecutive++;
            d.stop = p->cfg.policy == POLICY_STOP &&
                     p->consecutive >= (uint64_t)p->cfg.stop_after;
        }
        if (p->cfg.policy == POLICY_FREEZE) { /* drop the backlog, keep the grace clock */
            p->tau0 = tau + n * h - (double)(now_ns - p->t0_ns) * p->cfg.tau_per_ns;
        }
    } else {
        p->consecutive = 0;
    }
    d.steps = (uint64_t)n;
    double left = pace_target(p, now_ns) - (tau + n * h);
    p->lag_tau = left > 0 ? left : 0.0;
    return d;
}

/* Whose time the interval was, from the figures (see pace.h). */
static void overrun_cause(const pace *p, const pace_load *l, char *buf, size_t len)
{
    double gap = (double)l->gap_ns, cpu = (double)l->cpu_ns;
    /* a step's cost: the smoothed wall-clock figure, or the interval's CPU
     * time a step when lower (a chunk preempted on a busy machine reads as
     * a dear step: "rate 1 is more than the model can run here" was said
     * of a daemon using 14 % of a core) */
    double per = l->ns_per_step > 0 && l->steps > 0 && cpu > 0
                     ? fmin(l->ns_per_step, cpu / (double)l->steps) : l->ns_per_step;
    double need = per > 0 && l->h > 0 ? p->cfg.tau_per_ns / l->h * per : 0;
    double stepping = (double)l->steps * per; /* of cpu, ns */
    if (l->gap_ns <= 0)
        snprintf(buf, len, "%s", "");
    else if (cpu < 0.5 * gap)
        snprintf(buf, len, ": the daemon was not scheduled (a busy or full machine)");
    else if (need <= 0) /* no step measured yet */
        snprintf(buf, len, ": the daemon's own work");
    else if (need >= 0.9)
        snprintf(buf, len, ": rate %g is more than the model can run here (it needs %.3g "
                 "steps/s, %.0f ns a step: %.0f %% of a core; lower the rate, or use mode fast)",
                 l->rate, p->cfg.tau_per_ns / l->h * 1e9, per, 100 * need);
    else if (stepping >= 0.5 * cpu)
        snprintf(buf, len, ": the loop catching up a backlog (rate %g needs %.0f %% of a core: "
                 "an earlier stall left it, not the rate)", l->rate, 100 * need);
    else
        snprintf(buf, len, ": the daemon's own work besides stepping (which needs %.0f %% of a "
                 "core at rate %g)", 100 * need, l->rate);
}

void pace_overrun_text(const pace *p, const pace_load *l, char *buf, size_t len)
{
    char cause[200];
    double ms_per_tau = p->cfg.tau_per_ns > 0 ? 1e-6 / p->cfg.tau_per_ns : 0;
    overrun_cause(p, l, cause, sizeof cause);
    snprintf(buf, len, "%.3f ms behind the pace, over the catch-up cap of %g ticks "
             "(%.1f ms; policy %s): %.1f ms since the last tick, the loop ran %.1f ms of it (the "
             "longest handler %.1f ms)%s", p->behind_tau * ms_per_tau, p->cfg.catchup_ticks,
             p->cfg.catchup_ticks * (double)p->cfg.tick_ns * 1e-6,
             conf_policy_name(p->cfg.policy), (double)l->gap_ns * 1e-6,
             (double)l->cpu_ns * 1e-6, (double)l->busiest_ns * 1e-6, cause);
}

uint64_t pace_fast_chunk(double ns_per_step, int64_t chunk_ns)
{
    if (!(ns_per_step > 0))
        return 64;
    double n = (double)chunk_ns / ns_per_step;
    return n < 64 ? 64 : n > 1e7 ? 10000000 : (uint64_t)n;
}

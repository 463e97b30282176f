/* wg_sim_check.c - whether a snapshot's own fields describe a state some
 * run could be in: phase, state, time, counters, period statistics and an
 * active ramp's position on its line (wg_sim_restore asks, then checks the
 * parameters and the ramp as the live path would, in wg_sim.c). */
#include "internal.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>

/* A period's impacts: bounded so that the period's own still fit an int (a
 * file with 2^31 - 1 was taken, and the next impact overflowed). */
enum { IMPACTS_MAX = 1000000000 };

/* Finite and not absurd: one sum catches NaN, Inf and runaway values. */
int sim_finite_state(const double *y, int n)
{
    double sum = 0.0;
    for (int j = 0; j < n; j++)
        sum += fabs(y[j]);
    return sum < ABSURD;
}

#define TAU_MAX 1e15     /* tau of a snapshot: ~1000 years of table3's physical time */
#define TAU_C_REL 1e-12  /* |tau_c| <= TAU_C_REL (1 + tau): Kahan's term is ulps of tau */
#define STEPS_MAX 1000000000000000000ULL /* 1e18 steps: 30 years at 1e9 a second; the
                                            counters then never wrap (UINT64_MAX did) */

int sim_refuse(int rc, char *why, size_t whylen, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, whylen, fmt, ap);
    va_end(ap);
    return rc;
}

/* Phase, state, time and counters. */
static int restore_time(const wg_snapshot *w, char *why, size_t whylen)
{
    char a[32], b[32];
    if (w->k >= (uint32_t)w->steps_per_period)
        return sim_refuse(WG_EINVAL, why, whylen, "snapshot k = %u out of range [0, %d)", w->k,
                          w->steps_per_period);
    if (!sim_finite_state(w->y, wg_model_nstate(w->model)))
        return sim_refuse(WG_EINVAL, why, whylen, "snapshot state is not finite (or |y| >= %g)",
                          ABSURD);
    if (!(w->tau >= 0.0 && w->tau <= TAU_MAX))
        return sim_refuse(WG_EINVAL, why, whylen, "snapshot tau = %s out of range [0, %g]",
                          wg_num_format(w->tau, a, sizeof a), TAU_MAX);
    double cmax = TAU_C_REL * (1.0 + w->tau);
    if (!(fabs(w->tau_c) <= cmax))
        return sim_refuse(WG_EINVAL, why, whylen, "snapshot tau_c = %s out of range: |tau_c| <= "
                          "%g (1 + tau) = %s (Kahan's compensation term)",
                          wg_num_format(w->tau_c, a, sizeof a), TAU_C_REL,
                          wg_num_format(cmax, b, sizeof b));
    if (w->steps > STEPS_MAX)
        return sim_refuse(WG_EINVAL, why, whylen, "snapshot steps = %llu out of range [0, %llu]",
                          (unsigned long long)w->steps, STEPS_MAX);
    if (w->period > w->steps)
        return sim_refuse(WG_EINVAL, why, whylen, "snapshot period = %llu exceeds steps = %llu "
                          "(each period takes steps)", (unsigned long long)w->period,
                          (unsigned long long)w->steps);
    return WG_OK;
}

static int period_stats_ok(const wg_period *p, const char *name, char *why, size_t whylen)
{
    char a[32], b[32];
    if (p->motion < WG_MOTION_NO_IMPACT || p->motion > WG_MOTION_DOUBLE)
        return sim_refuse(WG_EINVAL, why, whylen, "snapshot %s.motion = %d is not a motion class "
                          "(0 no impact, 1 single-sided, 2 double-sided)", name, p->motion);
    if (p->impacts < 0 || p->impacts > IMPACTS_MAX)
        return sim_refuse(WG_EINVAL, why, whylen, "snapshot %s.impacts = %d, must be in [0, %d]",
                          name, p->impacts, IMPACTS_MAX);
    for (int j = 0; j < WG_NBEARING; j++)
        if (p->bimpacts[j] < 0 || p->bimpacts[j] > IMPACTS_MAX ||
            !(p->bvmax[j] >= 0 && p->bvmax[j] < ABSURD))
            return sim_refuse(WG_EINVAL, why, whylen, "snapshot %s.%s bearing statistics: impacts "
                              "in [0, %d] and a finite impact speed >= 0 (|v| < %g)", name,
                              wg_contact_name(WG_C_X1 + j), IMPACTS_MAX, ABSURD);
    if (!(fabs(p->min_xn) < ABSURD && fabs(p->max_xn) < ABSURD && p->min_xn <= p->max_xn))
        return sim_refuse(WG_EINVAL, why, whylen, "snapshot %s.min_xn = %s, %s.max_xn = %s: both "
                          "finite (|x| < %g) with min_xn <= max_xn", name,
                          wg_num_format(p->min_xn, a, sizeof a), name,
                          wg_num_format(p->max_xn, b, sizeof b), ABSURD);
    return WG_OK;
}

int sim_snapshot_fields_ok(const wg_snapshot *w, char *why, size_t whylen)
{
    int rc = restore_time(w, why, whylen);
    if (rc)
        return rc;
    if (w->cur.period != w->period)
        return sim_refuse(WG_EINVAL, why, whylen, "snapshot cur.period = %llu, must equal period = "
                          "%llu (the period in progress)", (unsigned long long)w->cur.period,
                          (unsigned long long)w->period);
    rc = period_stats_ok(&w->cur, "cur", why, whylen);
    return rc ? rc : period_stats_ok(&w->last, "last", why, whylen);
}

/* An active ramp's time and current value agree with the ramp line: omega
 * is on it, another parameter at most one step behind (it is updated at the
 * start of a step). */
int sim_ramp_now_ok(const wg_snapshot *w, char *why, size_t whylen)
{
    const wg_ramp *r = &w->ramp;
    char a[32], b[32], c[32], d[32], e[32];
    double el = w->tau - r->tau0;
    if (!(r->tau0 >= 0.0 && el >= 0.0 && el <= r->dur))
        return sim_refuse(WG_EINVAL, why, whylen, "snapshot ramp tau0 = %s: must be in [tau - "
                          "duration, tau] = [%s, %s] (started, not ended)",
                          wg_num_format(r->tau0, a, sizeof a),
                          wg_num_format(w->tau - r->dur, b, sizeof b),
                          wg_num_format(w->tau, c, sizeof c));
    double om = r->id == WG_P_OMEGA ? dmin(r->v0, r->v1) : w->p.v[WG_P_OMEGA];
    double step = TWO_PI / (om * w->steps_per_period), v = w->p.v[r->id];
    double line = r->v0 + (r->v1 - r->v0) * el / r->dur;
    double tol = fabs(r->v1 - r->v0) * step / r->dur + 1e-12 * (fabs(r->v0) + fabs(r->v1));
    if (fabs(v - line) <= tol)
        return WG_OK;
    return sim_refuse(WG_EINVAL, why, whylen, "snapshot %s = %s is not on the ramp: %s at tau - "
                      "tau0 = %s (from %s to %s, within one step)", wg_param_info_get(r->id)->name,
                      wg_num_format(v, a, sizeof a), wg_num_format(line, b, sizeof b),
                      wg_num_format(el, c, sizeof c), wg_num_format(r->v0, d, sizeof d),
                      wg_num_format(r->v1, e, sizeof e));
}


/* wg_sweep.c - per-point regime analysis: a point's transient, period,
 * classification and step-halving check, in a workspace a chain keeps
 * (sweep.h; the chains and their threads are wg_chains.c). Memory is
 * allocated per workspace (sims, record buffer), never per step or per
 * point. */
#include "sweep.h"
#include "wormgear/wg_sweep.h"
#include "wormgear/wg_shoot.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define LOOSE_TOL WG_TOL_FLOOR_MAX /* period tolerance once the LLE says "converging" */
#define SETTLE_EVERY 16 /* periods between the early-stop tests of a transient */

void wg_sweep_opts_default(wg_sweep_opts *o)
{
    *o = (wg_sweep_opts){.model = WG_MODEL_CONSISTENT, .stepper = WG_STEPPER_DEFAULT,
                         .steps = 256, .transient = 300, .settle = 0, .record = 128,
                         .extend = 3, .pair = 8,
                         .lle_periods = 300, .lle_d0 = 1e-7, .lle_tol = 0.01,
                         .tol_factor = 10.0, .tol_floor = 1e-9, .floquet = 0};
}

int wg_sweep_opts_check(const wg_sweep_opts *o, const char **field, char *why, size_t whylen)
{
    static const struct {
        const char *field, *what;
        double lo, hi;
    } r[3] = {{"tol_floor", "a period tolerance floor (states in b_c)", WG_TOL_MIN,
               WG_TOL_FLOOR_MAX},
              {"tol_factor", "a factor on the one-period error", WG_TOL_FACTOR_MIN,
               WG_TOL_FACTOR_MAX},
              {"lle_tol", "an |LLE| threshold per mesh period", WG_LLE_TOL_MIN, WG_LLE_TOL_MAX}};
    double v[3] = {o->tol_floor, o->tol_factor, o->lle_tol};
    for (int i = 0; i < 3; i++)
        if (!(v[i] >= r[i].lo && v[i] <= r[i].hi)) {
            snprintf(why, whylen, "need %s in [%g, %g], got %g", r[i].what, r[i].lo, r[i].hi,
                     v[i]);
            if (field)
                *field = r[i].field;
            return WG_ERANGE;
        }
    return WG_OK;
}

/* Steps per period for p: the requested N, raised to 1.25x the RK4 limit.
 * The limit depends only on the linear part, so a sweep of omega (or of a
 * phase, the forcing, the TE, a clearance) computes it once. */
static int steps_for(work *w, const wg_params *p)
{
    if (!w->hvalid || !wg_params_same_linear(&w->hkey, p)) {
        w->hmax = wg_rk4_hmax(w->o->model, p);
        w->hkey = *p;
        w->hvalid = 1;
    }
    int need = wg_min_steps(w->hmax, p->v[WG_P_OMEGA]);
    int n = w->o->steps, lim = (int)ceil(1.25 * need);
    if (n < lim)
        n = (lim + 7) / 8 * 8;
    return n > WG_STEPS_MAX ? WG_STEPS_MAX : n;
}

/* Make *s a sim with N steps for parameters p (re-init when N differs). */
static int ensure_sim(const work *w, wg_sim *s, int *built, int n, const wg_params *p,
                      char *why, size_t whylen)
{
    if (*built == n)
        return wg_sim_set_params(s, p, why, whylen);
    if (*built)
        wg_sim_fini(s);
    *built = 0;
    wg_sim_config cfg = {w->o->model, w->o->stepper, n};
    int rc = wg_sim_init(s, p, &cfg, why, whylen);
    if (rc == WG_OK)
        *built = n;
    return rc;
}

void sweep_work_fini(work *w)
{
    if (w->n_sim)
        wg_sim_fini(&w->sim);
    if (w->n_twin)
        wg_sim_fini(&w->twin);
    if (w->n_fine)
        wg_sim_fini(&w->fine);
    free(w->rec);
    free(w->stats);
    w->rec = NULL;
    w->stats = NULL;
}

int sweep_work_init(work *w, const wg_sweep_opts *o, volatile sig_atomic_t *stop, duo *d)
{
    memset(w, 0, sizeof *w);
    w->o = o;
    w->stop = stop;
    w->duo = d;
    w->nstate = wg_model_nstate(o->model);
    w->cap = o->record > 2 * o->settle + SETTLE_EVERY ? o->record : 2 * o->settle + SETTLE_EVERY;
    w->rec = malloc(sizeof(double) * (size_t)w->cap * (size_t)w->nstate);
    w->stats = malloc(sizeof(wg_period) * (size_t)w->cap);
    if (!w->rec || !w->stats) {
        sweep_work_fini(w);
        return WG_ENOMEM;
    }
    return WG_OK;
}

static void on_record(void *ctx, const wg_section *sec)
{
    work *w = ctx;
    if (w->nrec >= w->cap)
        return;
    memcpy(w->rec + (size_t)w->nrec * w->nstate, sec->y, sizeof(double) * (size_t)w->nstate);
    w->stats[w->nrec++] = sec->stats;
}

/* The main sim's runs: paired with another chain's when the thread runs
 * several (the same bits either way). */
static int run_periods(work *w, long periods, const wg_sink *sink)
{
    uint64_t n = (uint64_t)periods * (uint64_t)w->sim.cfg.steps_per_period;
    return w->duo ? duo_run(w->duo, &w->sim, n, sink) : wg_sim_run(&w->sim, n, sink, NULL);
}

/* Record o->record periods into w->rec / w->stats. */
static int record(work *w)
{
    wg_sink sink = {w, NULL, on_record, NULL};
    w->nrec = 0;
    return run_periods(w, w->o->record, &sink);
}

static wg_record record_of(const work *w)
{
    return (wg_record){w->nstate, w->nrec, w->rec, w->stats};
}

/* wg_record_period_error with the fine sim's period run by sm (its run
 * hook, if any). */
static int period_error_by(wg_simmap *sm, const wg_record *r, double *err)
{
    if (r->n < 2)
        return WG_EINVAL;
    double x[WG_NSTATE_MAX];
    const double *a = r->y + (size_t)(r->n - 2) * r->nstate, *b = a + r->nstate;
    memcpy(x, a, sizeof(double) * (size_t)r->nstate);
    int rc = wg_simmap_step(sm, x);
    if (rc)
        return rc;
    double e = 0.0;
    for (int j = 0; j < r->nstate; j++)
        e = fmax(e, fabs(x[j] - b[j]));
    *err = e;
    return WG_OK;
}

int wg_record_period_error(wg_sim *fine, const wg_record *r, double *err)
{
    wg_simmap sm = {fine, 1, NULL, NULL};
    return period_error_by(&sm, r, err);
}

static int duo_sim_run(void *d, wg_sim *s, uint64_t n) { return duo_run(d, s, n, NULL); }

/* One-period error of the N solution from the recorded sections. */
static int period_error(work *w, const wg_params *p, double *err, char *why, size_t whylen)
{
    int n2 = 2 * w->sim.cfg.steps_per_period;
    if (n2 > WG_STEPS_MAX)
        n2 = WG_STEPS_MAX;
    int rc = ensure_sim(w, &w->fine, &w->n_fine, n2, p, why, whylen);
    if (rc)
        return rc;
    wg_record r = record_of(w);
    wg_simmap sm = {&w->fine, 1, NULL, NULL};
    if (w->duo) /* batched with other chains' runs when the thread runs several */
        sm.run = duo_sim_run, sm.run_ctx = w->duo;
    return period_error_by(&sm, &r, err);
}

static int duo_sim_run2(void *d, wg_sim *a, wg_sim *b, uint64_t n) { return duo_run2(d, a, b, n); }

/* Largest Lyapunov exponent from the main sim's current state: both
 * trajectories advance at once (batched with other chains' runs when the
 * thread runs several). */
static int point_lle(work *w, const wg_params *p, double *lle, char *why, size_t whylen)
{
    int rc = ensure_sim(w, &w->twin, &w->n_twin, w->sim.cfg.steps_per_period, p, why, whylen);
    if (rc)
        return rc;
    double x[WG_NSTATE_MAX];
    memcpy(x, w->sim.y, sizeof x);
    return wg_lle_sims(&w->sim, &w->twin, x, w->o->lle_periods, w->o->lle_d0,
                       w->duo ? duo_sim_run2 : NULL, w->duo, lle);
}

void wg_record_stats(const wg_record *r, wg_point *pt)
{
    pt->min_xn = INFINITY;
    pt->max_xn = -INFINITY;
    pt->motion = 0;
    long imp = 0, bimp[WG_NBEARING] = {0};
    for (int j = 0; j < WG_NBEARING; j++)
        pt->bvmax[j] = 0.0;
    for (int i = 0; i < r->n; i++) {
        const wg_period *st = &r->stats[i];
        pt->min_xn = fmin(pt->min_xn, st->min_xn);
        pt->max_xn = fmax(pt->max_xn, st->max_xn);
        if (st->motion > pt->motion)
            pt->motion = st->motion;
        imp += st->impacts;
        for (int j = 0; j < WG_NBEARING; j++) {
            bimp[j] += st->bimpacts[j];
            pt->bvmax[j] = fmax(pt->bvmax[j], st->bvmax[j]);
        }
    }
    pt->impacts = r->n ? (double)imp / r->n : 0.0;
    for (int j = 0; j < WG_NBEARING; j++)
        pt->bimpacts[j] = r->n ? (double)bimp[j] / r->n : 0.0;
}

/* Store the last Poincare x_n, x_n' (recomputed from the stored states). */
static void point_sections(const work *w, const wg_params *p, wg_point *pt)
{
    int k0 = w->nrec > WG_POINT_NSEC ? w->nrec - WG_POINT_NSEC : 0;
    wg_exc e;
    wg_exc_eval(p, 0.0, p->v[WG_P_OMEGA], &e);
    pt->nsec = w->nrec - k0;
    for (int i = 0; i < pt->nsec; i++) {
        wg_outputs out;
        wg_outputs_eval(w->o->model, p, &e, w->rec + (size_t)(k0 + i) * w->nstate, &out);
        pt->xn[i] = out.xn;
        pt->dxn[i] = out.dxn;
    }
}

/* Period tolerance from the one-period error at the last two sections
 * stored. */
static int window_tol(work *w, const wg_params *p, double *tol, char *why, size_t whylen)
{
    double err;
    int rc = period_error(w, p, &err, why, whylen);
    *tol = fmax(w->o->tol_floor, w->o->tol_factor * err);
    return rc;
}

static double dist_max(const double *a, const double *b, int n)
{
    double d = 0.0;
    for (int j = 0; j < n; j++)
        d = fmax(d, fabs(a[j] - b[j]));
    return d;
}

/* Largest distance between sections n apart, the later one in [i0, i1). */
static double lag_max(const double *x, int d, int n, int i0, int i1)
{
    double r = 0.0;
    for (int i = i0; i < i1; i++)
        r = fmax(r, dist_max(x + (size_t)i * d, x + (size_t)(i - n) * d, d));
    return r;
}

/* The lag-n residuals of sections x[0..W) by eighths of their pairs: the
 * first eighth's, the least of the next six and the last's; returns the
 * largest |x| of the last section (the round-off scale, at least 1). */
static double lag_eighths(const double *x, int d, int n, int W, double *first, double *least,
                          double *last)
{
    const int m = W - n;
    double scale = 1.0;
    *first = lag_max(x, d, n, n, n + m / 8);
    *least = *first;
    for (int q = 1; q < 7; q++)
        *least = fmin(*least, lag_max(x, d, n, n + q * m / 8, n + (q + 1) * m / 8));
    *last = lag_max(x, d, n, n + 7 * m / 8, W);
    for (int j = 0; j < d; j++)
        scale = fmax(scale, fabs(x[(size_t)(W - 1) * d + j]));
    return scale;
}

/* Is the record's lag-n residual growing (its last eighth over 1.25x the
 * least of the earlier ones, above round-off): an orbit being left. */
static int record_leaving(const work *w, int n)
{
    double first, least, last;
    if (w->nrec - n < 8) /* fewer than one pair an eighth */
        return 0;
    double scale = lag_eighths(w->rec, w->nstate, n, w->nrec, &first, &least, &last);
    return last > 1e-13 * scale && last > 1.25 * least;
}

/* The period n the last o->settle sections stored repeat with, 0 if none.
 * Every pair n apart within tol (wg_period_detect), and the trajectory
 * within tol / 2 of the period-n orbit it tends to. That distance is at
 * most r / (1 - rho^n), r the last lag-n residual and rho its decay per
 * period, measured from the window's first eighth of pairs to its last:
 * a slowly decaying mode (multiplier near -1 makes x_k+2 - x_k small while
 * x_k is far from a period-1 orbit) is not taken for period 2, as a lag-1
 * residual over tol means a distance over tol / 2. The residual must also
 * not be growing: over the last eighth at most 1.25x its least over the
 * earlier eighths (an orbit being slowly left, just past a period
 * doubling). Residuals at round-off level pass. */
static int window_period(const work *w, double tol)
{
    const int W = w->o->settle, d = w->nstate;
    const double *x = w->rec + (size_t)(w->nrec - W) * d;
    double resid;
    int n = wg_period_detect(x, W, d, WG_PERIOD_MAX, tol, &resid);
    if (n == 0)
        return 0;
    const int m = W - n;
    double first, least, last, scale = lag_eighths(x, d, n, W, &first, &least, &last);
    if (last <= 1e-13 * scale)
        return n;
    if (!(last <= 1.25 * least && last < first))
        return 0;
    double rho = pow(last / first, 1.0 / (7 * m / 8));
    return last / (1.0 - pow(rho, n)) <= 0.5 * tol ? n : 0;
}

/* A point's transient: o->transient periods, or fewer once the last
 * o->settle Poincare sections repeat with a period n <= WG_PERIOD_MAX within
 * the period tolerance (window_period), tested every SETTLE_EVERY periods.
 * The tolerance is the record's rule, max(floor, factor x one-period error),
 * the error taken when the window first fills and again at a candidate stop
 * (which must pass with it). The stop is then put off to a multiple of n
 * periods short of the full transient, so the state the record (and the
 * next point of a chain) starts from is the full transient's, within tol:
 * a period-n orbit is entered at the same one of its n phases. */
static int transient(work *w, const wg_params *p, int *ran, char *why, size_t whylen)
{
    const int W = w->o->settle, T = w->o->transient;
    *ran = T;
    w->cut = 0;
    if (W <= 0 || T <= W)
        return run_periods(w, T, NULL);
    wg_sink sink = {w, NULL, on_record, NULL};
    double tol = -1.0;
    w->nrec = 0;
    for (int done = 0; done < T;) {
        int chunk = done < W ? W : T - done < SETTLE_EVERY ? T - done : SETTLE_EVERY;
        if (w->nrec + chunk > w->cap) { /* keep the last W */
            memmove(w->rec, w->rec + (size_t)(w->nrec - W) * w->nstate,
                    sizeof(double) * (size_t)W * (size_t)w->nstate);
            memmove(w->stats, w->stats + (w->nrec - W), sizeof(wg_period) * (size_t)W);
            w->nrec = W;
        }
        int rc = run_periods(w, chunk, &sink);
        if (rc)
            return rc;
        done += chunk;
        if (tol < 0 && (rc = window_tol(w, p, &tol, why, whylen)))
            return rc;
        if (done < T && window_period(w, tol) > 0) {
            if ((rc = window_tol(w, p, &tol, why, whylen)))
                return rc;
            int n = window_period(w, tol);
            if (n > 0) {
                *ran = done + (T - done) % n;
                w->cut = 1;
                return run_periods(w, (T - done) % n, NULL);
            }
        }
    }
    return WG_OK;
}

/* Period with the strict tolerance, extending the transient while none is
 * found; an extension is a transient of its own (with o->settle, it too
 * ends once its window has settled, at the full extension's phase). A
 * record after a transient that ended early must also not show its
 * period's residual growing, or it is extended too: just past a period
 * doubling a seed near the period-1 orbit, now unstable, sees its lag-1
 * residual fall while a slower flip mode decays, and the window settles;
 * the growing flip mode shows only later (lib.test_settle).
 * Returns the period (0: none) or a negative status. */
static int find_period(work *w, const wg_params *p, wg_point *pt, char *why, size_t whylen)
{
    for (int attempt = 0;; attempt++) {
        int rc = record(w);
        if (rc)
            return rc;
        if (attempt == 0) {
            if ((rc = period_error(w, p, &pt->err, why, whylen)))
                return rc;
            pt->tol = fmax(w->o->tol_floor, w->o->tol_factor * pt->err);
        }
        int n = wg_period_detect(w->rec, w->nrec, w->nstate, WG_PERIOD_MAX, pt->tol, &pt->resid);
        if (n && w->cut && attempt < w->o->extend && record_leaving(w, n))
            n = 0; /* stopped early on an orbit the record shows being left */
        if (n || attempt >= w->o->extend || (w->stop && *w->stop))
            return n;
        int ran;
        if ((rc = transient(w, p, &ran, why, whylen)))
            return rc;
    }
}

void wg_record_classify(const wg_sweep_opts *o, const wg_record *r, wg_point *pt)
{
    int n = wg_period_detect(r->y, r->n, r->nstate, WG_PERIOD_MAX, pt->tol, &pt->resid);
    pt->converged = n > 0;
    if (!n && pt->lle <= o->lle_tol)
        n = wg_period_detect(r->y, r->n, r->nstate, WG_PERIOD_MAX, fmax(pt->tol, LOOSE_TOL),
                             &pt->resid);
    pt->period = n;
    if (n || pt->lle < -o->lle_tol)
        pt->regime = WG_REGIME_PERIODIC;
    else
        pt->regime = pt->lle > o->lle_tol ? WG_REGIME_CHAOTIC : WG_REGIME_QUASIPERIODIC;
}

/* Classify an orbit with no strict period: LLE, then a fresh record. */
static int classify_aperiodic(work *w, const wg_params *p, wg_point *pt, char *why,
                              size_t whylen)
{
    int rc = point_lle(w, p, &pt->lle, why, whylen);
    if (!rc)
        rc = record(w);
    if (rc)
        return rc;
    wg_record r = record_of(w);
    wg_record_classify(w->o, &r, pt);
    return WG_OK;
}

/* Floquet multipliers of the period-n orbit through the current state:
 * the variational monodromy of P^n there (wg_shoot.h; rk4-event only). */
static int point_floquet(work *w, wg_point *pt)
{
    wg_orbit *o = malloc(sizeof *o);
    double x[WG_NSTATE_MAX];
    if (!o)
        return WG_ENOMEM;
    memcpy(x, w->sim.y, sizeof x);
    int rc = wg_orbit_map(&w->sim, pt->period, WG_MONODROMY_MAP, x, o);
    if (rc == WG_OK)
        rc = wg_orbit_floquet(o, pt->floq_re, pt->floq_im);
    if (rc == WG_OK)
        pt->nfloq = o->dim;
    free(o);
    return rc;
}

/* The analysis of one point from state y (updated to the final state). */
int sweep_point_analyse(work *w, const wg_params *p, double *y, wg_point *pt, char *why,
                         size_t whylen)
{
    memset(pt, 0, sizeof *pt);
    pt->lle = NAN;
    pt->steps = steps_for(w, p);
    int rc = ensure_sim(w, &w->sim, &w->n_sim, pt->steps, p, why, whylen);
    if (rc)
        return rc;
    wg_sim_set_state(&w->sim, y, 0, 0.0);
    rc = transient(w, p, &pt->transient, why, whylen);
    int n = rc ? rc : find_period(w, p, pt, why, whylen);
    if (n > 0) {
        pt->regime = WG_REGIME_PERIODIC;
        pt->period = n;
        pt->converged = 1;
    } else if (n == 0) {
        n = classify_aperiodic(w, p, pt, why, whylen);
    }
    if (n < 0) {
        pt->regime = n == WG_ENONFINITE ? WG_REGIME_DIVERGED : WG_REGIME_NONE;
        snprintf(why, whylen, "%s", wg_status_str(n));
        return n;
    }
    wg_record r = record_of(w);
    wg_record_stats(&r, pt); /* over the last recording's periods */
    point_sections(w, p, pt);
    memcpy(y, w->sim.y, sizeof(double) * (size_t)w->nstate);
    memcpy(pt->y_end, y, sizeof(double) * (size_t)w->nstate);
    if (w->o->floquet && pt->regime == WG_REGIME_PERIODIC && pt->period > 0)
        point_floquet(w, pt); /* a failure leaves nfloq = 0 */
    return WG_OK;
}

int wg_point_measured(const wg_point *pt)
{
    return pt->nsec > 0 || (pt->regime != WG_REGIME_NONE && pt->regime != WG_REGIME_DIVERGED);
}

int wg_point_run(const wg_params *p, const wg_sweep_opts *o, double *y, wg_point *pt,
                 char *why, size_t whylen)
{
    work w;
    const char *field = "";
    char msg[160];
    int rc = wg_sweep_opts_check(o, &field, msg, sizeof msg);
    if (rc) {
        snprintf(why, whylen, "option %s: %s", field, msg);
        return rc;
    }
    rc = sweep_work_init(&w, o, NULL, NULL);
    if (rc) {
        snprintf(why, whylen, "out of memory for the record buffer");
        return rc;
    }
    rc = sweep_point_analyse(&w, p, y, pt, why, whylen);
    sweep_work_fini(&w);
    return rc;
}

/* Step-halving check: analyse the attractor reached (state y) again with
 * 2N steps per period and store that classification in pt. */
void sweep_verify_point(work *v, const wg_params *p, const double *y, wg_point *pt)
{
    double yv[WG_NSTATE_MAX];
    char why[160];
    wg_point *q = malloc(sizeof *q);
    if (!q)
        return;
    memcpy(yv, y, sizeof yv);
    if (sweep_point_analyse(v, p, yv, q, why, sizeof why) == WG_OK) {
        pt->checked = 1;
        pt->check_regime = q->regime;
        pt->check_period = q->period;
        pt->check_motion = q->motion;
    }
    free(q);
}


/* wg_regime.c - period detection, the live tracker, the wg_sim Poincare map
 * adapter and the largest Lyapunov exponent by twin trajectories. */
#include "wormgear/wg_regime.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <string.h>

static const char *const regime_names[] = {"none", "periodic", "quasiperiodic", "chaotic",
                                           "diverged"};

const char *wg_regime_name(int kind)
{
    return kind >= 0 && kind <= WG_REGIME_DIVERGED ? regime_names[kind] : "?";
}

/* ---- period detection -------------------------------------------------- */

static double dist_inf(const double *a, const double *b, int dim)
{
    double d = 0.0;
    for (int j = 0; j < dim; j++) {
        double e = fabs(a[j] - b[j]);
        if (!(e <= d)) /* also catches NaN */
            d = e;
    }
    return d;
}

/* Largest distance between points n apart, stopping early above stop. */
static double lag_resid(const double *pts, int npts, int dim, int n, double stop)
{
    double r = 0.0;
    for (int i = npts - 1; i >= n; i--) {
        double d = dist_inf(pts + (size_t)i * dim, pts + (size_t)(i - n) * dim, dim);
        if (!(d <= r))
            r = d;
        if (!(r <= stop))
            break;
    }
    return r;
}

int wg_period_detect(const double *pts, int npts, int dim, int nmax, double tol,
                     double *resid)
{
    double best = INFINITY;
    for (int n = 1; n <= nmax; n++) {
        int pairs = npts - n;
        if (pairs < n || pairs < 8)
            break;
        double r = lag_resid(pts, npts, dim, n, fmax(tol, best));
        if (r <= tol) {
            if (resid)
                *resid = r;
            return n;
        }
        if (r < best)
            best = r;
    }
    if (resid)
        *resid = best;
    return 0;
}

/* ---- streaming tracker -------------------------------------------------- */

void wg_tracker_init(wg_tracker *t, int dim, double tol)
{
    memset(t, 0, sizeof *t);
    t->dim = dim < 1 ? 1 : dim > WG_NSTATE_MAX ? WG_NSTATE_MAX : dim;
    t->tol = tol;
}

/* Row of the i-th oldest stored section (the rows are a ring from head). */
static int tracker_row(const wg_tracker *t, int i)
{
    int k = t->head + i;
    return k >= WG_TRACK_LEN ? k - WG_TRACK_LEN : k;
}

void wg_tracker_push(wg_tracker *t, const wg_section *sec)
{
    int k;
    if (t->n == WG_TRACK_LEN) { /* overwrite the oldest */
        k = t->head;
        t->head = tracker_row(t, 1);
        t->impacts -= t->imp[k];
    } else {
        k = tracker_row(t, t->n++);
    }
    memcpy(t->pts[k], sec->y, sizeof(double) * (size_t)t->dim);
    t->imp[k] = sec->stats.impacts;
    t->mot[k] = sec->stats.motion;
    t->impacts += t->imp[k];
    t->motion = 0;
    for (int i = 0; i < t->n; i++) /* stored rows, in any order */
        if (t->mot[i] > t->motion)
            t->motion = t->mot[i];
}

int wg_tracker_period(const wg_tracker *t, double *resid)
{
    if (t->n < 16) {
        if (resid)
            *resid = INFINITY;
        return 0;
    }
    double flat[WG_TRACK_LEN * WG_NSTATE_MAX]; /* the ring in order, rows dim apart */
    const size_t row = sizeof(double) * (size_t)t->dim;
    for (int i = 0; i < t->n; i++)
        memcpy(flat + (size_t)i * t->dim, t->pts[tracker_row(t, i)], row);
    return wg_period_detect(flat, t->n, t->dim, WG_PERIOD_MAX, t->tol, resid);
}

/* ---- wg_sim as a Poincare map -------------------------------------------- */

/* Put sim s at x and psi = 0; a sim already there continues without a
 * reset. */
static void simmap_enter(wg_sim *s, const double *x)
{
    if (s->k != 0 || memcmp(s->y, x, sizeof(double) * (size_t)s->nstate) != 0)
        wg_sim_set_state(s, x, 0, s->tau);
}

int wg_simmap_step(void *ctx, double *x)
{
    wg_simmap *sm = ctx;
    wg_sim *s = sm->sim;
    simmap_enter(s, x);
    uint64_t n = (uint64_t)sm->periods * (uint64_t)s->cfg.steps_per_period;
    int rc = sm->run ? sm->run(sm->run_ctx, s, n) : wg_sim_run(s, n, NULL, NULL);
    memcpy(x, s->y, sizeof(double) * (size_t)s->nstate);
    return rc;
}

wg_map wg_simmap_map(wg_simmap *sm)
{
    return (wg_map){wg_simmap_step, sm, sm->sim->nstate};
}

/* ---- largest Lyapunov exponent -------------------------------------------- */

static double dist2(const double *a, const double *b, int dim)
{
    double s = 0.0;
    for (int j = 0; j < dim; j++)
        s += (a[j] - b[j]) * (a[j] - b[j]);
    return sqrt(s);
}

/* Twin separation band: renormalise only when d leaves [d0/BAND, d0*BAND].
 * Between renormalisations the twin runs on untouched (a wg_simmap then
 * needs no state reset), and the log growth telescopes exactly. */
#define BAND 1e3

static void twin_start(const double *x, double *xt, int dim, double d0)
{
    double nrm = 0.0;
    for (int j = 0; j < dim; j++)
        nrm += (1.0 + 0.1 * j) * (1.0 + 0.1 * j);
    for (int j = 0; j < dim; j++) /* a fixed direction touching every component */
        xt[j] = x[j] + d0 * (1.0 + 0.1 * j) / sqrt(nrm);
}

/* Benettin's loop (wg_lle_twin) over step, which advances x and the
 * twin's xt by one map step each. */
typedef int (*lle_step_fn)(void *ctx, double *x, double *xt);

static int lle_run(lle_step_fn step, void *ctx, int dim, double *x, int steps, double d0,
                   double *lle)
{
    double xt[64];
    if (dim > 64 || steps < 1 || !(d0 > 0.0))
        return WG_EINVAL;
    twin_start(x, xt, dim, d0);
    double sum = 0.0, d = d0;
    for (int k = 0; k < steps; k++) {
        int rc = step(ctx, x, xt);
        if (rc)
            return rc;
        d = dist2(x, xt, dim);
        if (!(d > 0.0) || !isfinite(d)) { /* collapsed onto the orbit: re-seed */
            sum += log(d0 * 1e-12 / d0);
            twin_start(x, xt, dim, d0);
            d = d0;
            continue;
        }
        if (d > d0 * BAND || d < d0 / BAND || k == steps - 1) {
            sum += log(d / d0);
            for (int j = 0; j < dim; j++)
                xt[j] = x[j] + (xt[j] - x[j]) * (d0 / d);
        }
    }
    *lle = sum / steps;
    return WG_OK;
}

typedef struct twin_maps {
    const wg_map *base, *twin;
} twin_maps;

/* The base's step, then the twin's. */
static int twin_maps_step(void *ctx, double *x, double *xt)
{
    const twin_maps *m = ctx;
    int rc = m->base->fn(m->base->ctx, x);
    return rc ? rc : m->twin->fn(m->twin->ctx, xt);
}

int wg_lle_twin(const wg_map *base, const wg_map *twin, double *x, int steps, double d0,
                double *lle)
{
    if (twin->dim != base->dim)
        return WG_EINVAL;
    twin_maps m = {base, twin};
    return lle_run(twin_maps_step, &m, base->dim, x, steps, d0, lle);
}

typedef struct twin_sims {
    wg_sim *s[2];
    wg_run2_fn run2;
    void *run_ctx;
} twin_sims;

/* One mesh period of both sims, from x and xt, at once. */
static int twin_sims_step(void *ctx, double *x, double *xt)
{
    twin_sims *m = ctx;
    wg_sim *a = m->s[0], *b = m->s[1];
    simmap_enter(a, x);
    simmap_enter(b, xt);
    const uint64_t n = (uint64_t)a->cfg.steps_per_period;
    int rc[2];
    if (m->run2) {
        rc[0] = m->run2(m->run_ctx, a, b, n);
        rc[1] = WG_OK;
    } else {
        uint64_t left[2] = {n, n}, done[2];
        const wg_sink *const sk[2] = {NULL, NULL};
        wg_sim_run_pair(m->s, left, sk, done, rc);
        for (int j = 0; j < 2 && rc[0] == WG_OK; j++) /* the other's rest, alone */
            if (rc[j] == WG_OK && done[j] < n)
                rc[j] = wg_sim_run(m->s[j], n - done[j], NULL, NULL);
    }
    memcpy(x, a->y, sizeof(double) * (size_t)a->nstate);
    memcpy(xt, b->y, sizeof(double) * (size_t)b->nstate);
    return rc[0] ? rc[0] : rc[1];
}

int wg_lle_sims(wg_sim *sim, wg_sim *twin, double *x, int periods, double d0, wg_run2_fn run2,
                void *run_ctx, double *lle)
{
    if (sim == twin || sim->nstate != twin->nstate ||
        sim->cfg.steps_per_period != twin->cfg.steps_per_period)
        return WG_EINVAL;
    twin_sims m = {{sim, twin}, run2, run_ctx};
    return lle_run(twin_sims_step, &m, sim->nstate, x, periods, d0, lle);
}

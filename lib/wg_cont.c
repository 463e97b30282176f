/* wg_cont.c - pseudo-arclength continuation of periodic orbits (wg_cont.h):
 * the corrector, the tangent, the adaptive step along a branch, branch
 * switching at period doublings, and the run. Test functions and the
 * location of bifurcations are in wg_cont_bif.c. */
#include "cont.h"
#include "internal.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define MAXIT 30        /* Newton iterations per corrector */
#define COS_MAX 0.98    /* consecutive tangents at most ~11 degrees apart */
#define FD_REL 1e-6     /* dP/dparam: central difference step, relative */
#define SWITCH_EPS 1e-3 /* first step onto a period-2n branch */

static const char *const bif_names[WG_NBIF] = {"fold", "period_doubling", "torus", "grazing",
                                               "branch_point"};

const char *wg_bif_name(int kind) { return kind >= 0 && kind < WG_NBIF ? bif_names[kind] : "?"; }

void wg_cont_opts_default(wg_cont_opts *o)
{
    *o = (wg_cont_opts){.model = WG_MODEL_CONSISTENT, .param = WG_P_OMEGA, .from = 0.1,
                        .to = 2.5, .start = 0.1, .period = 1, .steps = WG_STEPS_DEFAULT * 2,
                        .transient = 500, .ds0 = 1e-3, .ds_min = 1e-7, .ds_max = 0.01,
                        .tol = 1e-10, .loc_tol = 1e-9, .max_points = 5000, .depth = 1};
}

int wg_cont_steps(const wg_params *p, const wg_cont_opts *o)
{
    double vals[3] = {o->from, o->to, o->start};
    int need = 0;
    for (int i = 0; i < 3; i++) {
        wg_params q = *p;
        q.v[o->param] = vals[i];
        int k = wg_min_steps(wg_rk4_hmax(o->model, &q), q.v[WG_P_OMEGA]);
        need = k > need ? k : need;
    }
    int n = o->steps, lim = (int)ceil(1.25 * need);
    if (n < lim)
        n = (lim + 7) / 8 * 8;
    return n > WG_STEPS_MAX ? WG_STEPS_MAX : n;
}

void cont_note(const cont *c, int code, int branch, double value, const char *fmt, ...)
{
    if (!c->sink || !c->sink->on_note)
        return;
    char msg[256];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    c->sink->on_note(c->sink->ctx, code, branch, value, msg);
}

double cont_wdot(const cont *c, const double *a, const double *b)
{
    double s = 0.0;
    for (int i = 0; i < c->d; i++)
        s += a[i] * b[i];
    return c->th * s + a[c->d] * b[c->d];
}

/* ---- evaluating the map ------------------------------------------------------ */

static int set_param(cont *c, double v)
{
    if (c->p.v[c->o->param] == v)
        return WG_OK;
    c->p.v[c->o->param] = v;
    return wg_sim_set_params(&c->sim, &c->p, c->why, c->whylen);
}

static void full_state(const cont *c, const double *u, double *y)
{
    memcpy(y, c->base, sizeof(double) * WG_NSTATE_MAX);
    for (int i = 0; i < c->d; i++)
        y[c->idx[i]] = u[i];
}

/* P^n at (u's state, parameter v), active coordinates into px. */
static int map_state(cont *c, const double *u, double v, int n, double *px)
{
    double y[WG_NSTATE_MAX];
    int rc = set_param(c, v);
    if (rc)
        return rc;
    full_state(c, u, y);
    wg_sim_set_state(&c->sim, y, 0, 0.0);
    rc = wg_sim_run(&c->sim, (uint64_t)n * (uint64_t)c->sim.cfg.steps_per_period, NULL, NULL);
    for (int i = 0; i < c->d; i++)
        px[i] = c->sim.y[c->idx[i]];
    return rc;
}

/* dP^n/dparam at u by central differences (one-sided at the table's ends). */
static int dp_dparam(cont *c, const double *u, int n, double *pl)
{
    const wg_param_info *r = wg_param_info_get(c->o->param);
    double v = u[c->d], dv = FD_REL * fmax(1.0, fabs(v));
    double a = fmax(r->min, v - dv), b = fmin(r->max, v + dv);
    double pa[WG_NSTATE_MAX], pb[WG_NSTATE_MAX];
    int rc = map_state(c, u, a, n, pa);
    if (!rc)
        rc = map_state(c, u, b, n, pb);
    for (int i = 0; i < c->d && !rc; i++)
        pl[i] = (pb[i] - pa[i]) / (b - a);
    return rc;
}

static int map_at(cont *c, const double *u, int n, wg_orbit *o)
{
    double y[WG_NSTATE_MAX];
    int rc = set_param(c, u[c->d]);
    if (rc)
        return rc;
    full_state(c, u, y);
    return wg_orbit_map(&c->sim, n, c->o->monodromy, y, o);
}

/* The bordered Jacobian [[M - I, pl], [a]] of the corrector, row-major. */
static void bordered(const cont *c, const sol *s, const double *a, double *J)
{
    int d = c->d, m = d + 1;
    for (int i = 0; i < d; i++) {
        for (int j = 0; j < d; j++)
            J[i * m + j] = s->orb.M[i * d + j] - (i == j);
        J[i * m + d] = s->pl[i];
    }
    for (int j = 0; j < m; j++)
        J[d * m + j] = a[j];
}

int cont_correct(cont *c, int n, const double *up, const double *a, sol *s)
{
    int d = c->d, m = d + 1;
    memcpy(s->u, up, sizeof s->u);
    s->n = n;
    for (int it = 0;; it++) {
        int rc = map_at(c, s->u, n, &s->orb);
        if (!rc)
            rc = dp_dparam(c, s->u, n, s->pl);
        if (rc)
            return rc;
        double r[UMAX], J[UMAX * UMAX], res = 0.0, cr = 0.0;
        for (int i = 0; i < d; i++) {
            r[i] = s->u[i] - s->orb.y[c->idx[i]]; /* -(P(x) - x) */
            res = fmax(res, fabs(r[i]));
        }
        for (int j = 0; j < m; j++)
            cr -= a[j] * (s->u[j] - up[j]);
        r[d] = cr;
        s->its = it;
        s->resid = res;
        if (res <= c->o->tol && fabs(cr) <= c->o->tol)
            return WG_OK;
        if (it == MAXIT || !(res < 1.0))
            return WG_ERANGE;
        bordered(c, s, a, J);
        if ((rc = la_solve(m, J, r)))
            return rc;
        for (int j = 0; j < m; j++)
            s->u[j] += r[j];
    }
}

int cont_finish(cont *c, sol *s, const double *tprev)
{
    int d = c->d, m = d + 1;
    double J[UMAX * UMAX], a[UMAX];
    for (int j = 0; j < m; j++)
        a[j] = (j < d ? c->th : 1.0) * tprev[j];
    bordered(c, s, a, J);
    memset(s->t, 0, sizeof s->t);
    s->t[d] = 1.0;
    int rc = la_solve(m, J, s->t);
    if (rc)
        return rc;
    double nrm = sqrt(cont_wdot(c, s->t, s->t)), sg = cont_wdot(c, s->t, tprev) < 0 ? -1 : 1;
    for (int j = 0; j < m; j++)
        s->t[j] *= sg / nrm;
    return wg_orbit_floquet(&s->orb, s->wr, s->wi);
}

/* ---- branches ------------------------------------------------------------------ */

static void emit_point(const cont *c, const sol *s, int id, int index, double ds)
{
    if (!c->sink || !c->sink->on_point)
        return;
    wg_cont_point pt;
    memset(&pt, 0, sizeof pt);
    pt.branch = id;
    pt.index = index;
    pt.period = s->n;
    pt.value = s->u[c->d];
    full_state(c, s->u, pt.y);
    memcpy(pt.xnsec, s->orb.xnsec, sizeof pt.xnsec);
    memcpy(pt.qmin, s->orb.qmin, sizeof pt.qmin);
    memcpy(pt.qmax, s->orb.qmax, sizeof pt.qmax);
    memcpy(pt.ncross, s->orb.ncross, sizeof pt.ncross);
    pt.nmult = c->d;
    memcpy(pt.mre, s->wr, sizeof pt.mre);
    memcpy(pt.mim, s->wi, sizeof pt.mim);
    pt.stable = hypot(s->wr[0], s->wi[0]) < 1.0;
    pt.dvalue = s->t[c->d];
    pt.ds = ds;
    pt.newton_its = s->its;
    pt.resid = s->resid;
    c->sink->on_point(c->sink->ctx, &pt);
}

/* The predictor of the next point: A + ds t, or, when that leaves the
 * range, the point of the tangent line at the range's end with the
 * parameter fixed there (a = e_param). Returns 1 in the second case. */
static int predict(const cont *c, const sol *A, double ds, double *up, double *a)
{
    int d = c->d;
    double v = A->u[d] + ds * A->t[d], bound = v > c->hi ? c->hi : c->lo;
    int last = (v > c->hi || v < c->lo) && fabs(A->t[d]) > 1e-3;
    double step = last ? (bound - A->u[d]) / A->t[d] : ds;
    for (int j = 0; j <= d; j++) {
        up[j] = A->u[j] + step * A->t[j];
        a[j] = last ? (j == d) : (j < d ? c->th : 1.0) * A->t[j];
    }
    if (last)
        up[d] = bound;
    return last;
}

/* Halve the step after a failed point; 0 when it fell below ds_min. */
static int halve(const cont *c, double *ds, int id, double v, int code, const char *what)
{
    *ds *= 0.5;
    if (*ds >= c->o->ds_min) {
        cont_note(c, code, id, v, "%s: step halved to %.3g", what, *ds);
        return 1;
    }
    cont_note(c, WG_NOTE_END, id, v, "%s and the step is below %.3g: branch ends", what,
              c->o->ds_min);
    return 0;
}

static double next_ds(const cont *c, double ds, int its)
{
    if (its <= 2)
        ds *= 1.5;
    else if (its >= 5)
        ds *= 0.6;
    return fmin(ds, c->o->ds_max);
}

double cont_half_gap(const cont *c, const sol *s, double *gap)
{
    double m = 0.0;
    for (int i = 0; i < c->d; i++) {
        gap[i] = s->n % 2 ? 0.0 : s->orb.ysec[s->n / 2][c->idx[i]] - s->u[i];
        m = fmax(m, fabs(gap[i]));
    }
    return m;
}

/* The reference direction of an even-period branch (see cont.h). */
static void set_ref(cont *c, const sol *s)
{
    double m = cont_half_gap(c, s, c->ref);
    c->has_ref = m > 1e-8;
    for (int i = 0; i < c->d && c->has_ref; i++)
        c->ref[i] /= m;
}

/* Follow branch id from start (already reported as point index0). */
static int branch(cont *c, const sol *start, int id, int depth, int index0)
{
    sol *buf = malloc(3 * sizeof *buf);
    if (!buf)
        return WG_ENOMEM;
    sol *A = &buf[0], *B = &buf[1], *first = &buf[2];
    *A = *first = *start;
    double ds = c->o->ds0, up[UMAX], a[UMAX];
    int n = A->n, npts = index0 + 1;
    set_ref(c, start);
    while (!(c->stop && *c->stop)) {
        if (npts >= c->o->max_points) {
            cont_note(c, WG_NOTE_END, id, A->u[c->d], "%d points: branch ends", npts);
            break;
        }
        int last = predict(c, A, ds, up, a), rc = cont_correct(c, n, up, a, B);
        if (!rc)
            rc = cont_finish(c, B, A->t);
        if (rc) {
            char what[96];
            snprintf(what, sizeof what, "Newton failed near %s = %.8g (%s, residual %.2e)",
                     wg_param_info_get(c->o->param)->name, up[c->d], wg_status_name(rc),
                     B->resid);
            if (halve(c, &ds, id, up[c->d], WG_NOTE_NEWTON, what))
                continue;
            break;
        }
        if (!last && cont_wdot(c, A->t, B->t) < COS_MAX) {
            if (halve(c, &ds, id, B->u[c->d], WG_NOTE_ANGLE, "the tangent turned too far"))
                continue;
            break;
        }
        double du[UMAX];
        for (int j = 0; j <= c->d; j++)
            du[j] = B->u[j] - A->u[j];
        int bp = cont_detect(c, A, B, cont_wdot(c, A->t, du), id, depth);
        if (bp && index0 > 0) /* a switched branch meets its parent again */
            break;
        emit_point(c, B, id, npts++, ds);
        sol *t = A;
        A = B;
        B = t;
        if (last) {
            cont_note(c, WG_NOTE_END, id, A->u[c->d], "reached the end of the range");
            break;
        }
        for (int j = 0; j <= c->d; j++)
            du[j] = A->u[j] - first->u[j];
        if (npts > 10 && sqrt(cont_wdot(c, du, du)) < 0.5 * ds) {
            cont_note(c, WG_NOTE_END, id, A->u[c->d], "the branch closed on itself");
            break;
        }
        ds = next_ds(c, ds, A->its);
    }
    free(buf);
    return WG_OK;
}

/* Period-2n branch from a queued period doubling: its first point at
 * distance eps along the -1 eigenvector; a fixed point of P^2n that is not
 * one of P^n. */
static int switch_branch(cont *c, pdq *q, sol *S)
{
    int d = c->d, n2 = 2 * q->n;
    double up[UMAX], a[UMAX], t[UMAX];
    for (int j = 0; j < d; j++)
        t[j] = q->v[j];
    t[d] = 0.0;
    for (double eps = SWITCH_EPS; eps < 0.1; eps *= 4.0) {
        for (int j = 0; j <= d; j++) {
            up[j] = q->u[j] + eps * t[j];
            a[j] = (j < d ? c->th : 1.0) * t[j];
        }
        if (cont_correct(c, n2, up, a, S) || cont_finish(c, S, t))
            continue;
        double sep = 0.0;
        for (int i = 0; i < d; i++)
            sep = fmax(sep, fabs(S->orb.ysec[q->n][c->idx[i]] - S->u[i]));
        if (sep > 0.1 * eps)
            return WG_OK;
    }
    return WG_ERANGE;
}

static int run_switches(cont *c)
{
    sol *S = malloc(sizeof *S), *P = malloc(sizeof *P);
    int rc = S && P ? WG_OK : WG_ENOMEM;
    for (int i = 0; i < c->nq && !rc && !(c->stop && *c->stop); i++) {
        pdq *q = &c->q[i];
        if (q->done)
            continue;
        q->done = 1;
        double v = q->u[c->d];
        if (2 * q->n > WG_SHOOT_NMAX || switch_branch(c, q, S)) {
            cont_note(c, WG_NOTE_SWITCH, c->nbranch, v, "no period-%d branch found at the "
                      "period doubling", 2 * q->n);
            continue;
        }
        int id = c->nbranch++; /* the doubling point itself, as a period-2n orbit */
        P->n = 2 * q->n;
        memcpy(P->u, q->u, sizeof P->u);
        if (map_at(c, P->u, P->n, &P->orb) == WG_OK && cont_finish(c, P, S->t) == WG_OK) {
            P->its = 0;
            P->resid = 0.0;
            emit_point(c, P, id, 0, 0.0);
        }
        emit_point(c, S, id, 1, SWITCH_EPS);
        rc = branch(c, S, id, q->depth, 1);
    }
    free(S);
    free(P);
    return rc;
}

/* ---- the run -------------------------------------------------------------------- */

/* A refusal of o's field (its name in *field): code, with why. */
static int refuse(const char **field, const char *name, int code, char *why, size_t whylen,
                  const char *fmt, ...) __attribute__((format(printf, 6, 7)));
static int refuse(const char **field, const char *name, int code, char *why, size_t whylen,
                  const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(why, whylen, fmt, ap);
    va_end(ap);
    if (field)
        *field = name;
    return code;
}

int wg_cont_check(const wg_cont_opts *o, const char **field, char *why, size_t whylen)
{
    const wg_param_info *r = wg_param_info_get(o->param);
    if (o->model != WG_MODEL_CONSISTENT)
        return refuse(field, "model", WG_EUNSUPPORTED, why, whylen, "continuation needs the "
                      "consistent model (the printed form runs rk4 only)");
    if (!r)
        return refuse(field, "param", WG_EUNKNOWN, why, whylen,
                      "parameter id %d does not exist", o->param);
    static const char *const names[3] = {"from", "to", "start"};
    double vals[3] = {o->from, o->to, o->start};
    for (int i = 0; i < 3; i++)
        if (wg_param_check(o->param, vals[i], why, whylen)) {
            if (field)
                *field = names[i];
            return WG_ERANGE;
        }
    double lo = fmin(o->from, o->to), hi = fmax(o->from, o->to);
    if (o->from == o->to)
        return refuse(field, "range", WG_ERANGE, why, whylen, "need a range, got %s = %.15g twice",
                      r->name, o->from);
    if (!(o->start >= lo && o->start <= hi))
        return refuse(field, "start", WG_ERANGE, why, whylen,
                      "need a value in [%.15g, %.15g] (the range), got %.15g", lo, hi, o->start);
    if (o->period < 1 || o->period > WG_SHOOT_NMAX)
        return refuse(field, "period", WG_EINVAL, why, whylen, "need 1 to %d, got %d",
                      WG_SHOOT_NMAX, o->period);
    if (!(o->ds_min > 0))
        return refuse(field, "ds_min", WG_EINVAL, why, whylen, "need > 0, got %g", o->ds_min);
    if (!(o->ds_max >= o->ds_min))
        return refuse(field, "ds_max", WG_EINVAL, why, whylen, "need at least %g (the smallest "
                      "step the continuation halves to), got %g", o->ds_min, o->ds_max);
    if (!(o->ds0 >= o->ds_min && o->ds0 <= o->ds_max))
        return refuse(field, "ds0", WG_EINVAL, why, whylen, "need a first step in [%g, %g] "
                      "(ds_min, ds_max), got %g", o->ds_min, o->ds_max, o->ds0);
    if (!(o->tol >= WG_TOL_MIN && o->tol <= WG_CONT_TOL_MAX))
        return refuse(field, "tol", WG_ERANGE, why, whylen, "need a residual (states in b_c) "
                      "in [%g, %g], got %g", WG_TOL_MIN, WG_CONT_TOL_MAX, o->tol);
    if (!(o->loc_tol >= WG_TOL_MIN && o->loc_tol <= WG_CONT_LOC_TOL_MAX))
        return refuse(field, "loc_tol", WG_ERANGE, why, whylen, "need a bracket (parameter "
                      "units) in [%g, %g], got %g", WG_TOL_MIN, WG_CONT_LOC_TOL_MAX, o->loc_tol);
    if (o->max_points < 2)
        return refuse(field, "max_points", WG_EINVAL, why, whylen, "need at least 2, got %d",
                      o->max_points);
    if (o->depth < 0 || o->transient < 0)
        return refuse(field, o->depth < 0 ? "depth" : "transient", WG_EINVAL, why, whylen,
                      "need >= 0, got %d", o->depth < 0 ? o->depth : o->transient);
    return WG_OK;
}

/* Least period of the orbit of s: the smallest m dividing n whose
 * section comes back to the start (to 1e-8 relative). */
static int least_period(const cont *c, const sol *s)
{
    for (int m = 1; m < s->n; m++) {
        if (s->n % m)
            continue;
        double gap = 0.0, mag = 1.0;
        for (int i = 0; i < c->d; i++) {
            gap = fmax(gap, fabs(s->orb.ysec[m][c->idx[i]] - s->u[i]));
            mag = fmax(mag, fabs(s->u[i]));
        }
        if (gap <= 1e-8 * mag)
            return m;
    }
    return s->n;
}

/* The transient before the first point, TRANSIENT_CHUNK periods at a
 * time so that a stop asked for ends it (a --transient of 1e7 periods
 * ran 80 s past Ctrl-C). 1 when stopped, else wg_sim_run's status. */
enum { TRANSIENT_CHUNK = 64 };
static int run_transient(cont *c)
{
    uint64_t spp = (uint64_t)c->sim.cfg.steps_per_period;
    for (int left = c->o->transient; left > 0;) {
        if (c->stop && *c->stop)
            return 1;
        int n = left < TRANSIENT_CHUNK ? left : TRANSIENT_CHUNK;
        int rc = wg_sim_run(&c->sim, (uint64_t)n * spp, NULL, NULL);
        if (rc)
            return rc;
        left -= n;
    }
    return WG_OK;
}

/* The first point: the orbit reached from y0 after the transient, refined
 * at fixed parameter. 1: stopped in the transient, nothing found. */
static int first_point(cont *c, const double *y0, sol *S)
{
    const wg_cont_opts *o = c->o;
    wg_sim_set_state(&c->sim, y0, 0, 0.0);
    int rc = run_transient(c);
    if (rc == 1)
        return 1;
    double up[UMAX], a[UMAX] = {0}, t[UMAX] = {0};
    memcpy(c->base, c->sim.y, sizeof c->base);
    for (int i = 0; i < c->d; i++)
        up[i] = c->sim.y[c->idx[i]];
    up[c->d] = o->start;
    a[c->d] = 1.0;
    t[c->d] = o->to > o->start ? 1.0 : -1.0;
    if (!rc && !(rc = cont_correct(c, o->period, up, a, S)))
        rc = cont_finish(c, S, t);
    if (rc) {
        snprintf(c->why, c->whylen, "no period-%d orbit found at %s = %g from the state "
                 "reached after %d periods (%s, residual %.2e): try --period or --start",
                 o->period, wg_param_info_get(o->param)->name, o->start, o->transient,
                 wg_status_name(rc), S->resid);
        return rc;
    }
    int m = least_period(c, S);
    if (m < o->period) {
        snprintf(c->why, c->whylen, "the orbit found at %s = %g has period %d, not %d: use "
                 "--period %d, or --start where a period-%d orbit is the attractor",
                 wg_param_info_get(o->param)->name, o->start, m, o->period, m, o->period);
        return WG_ERANGE;
    }
    return WG_OK;
}

static int run(cont *c, const double *y0)
{
    sol *S = malloc(sizeof *S);
    if (!S)
        return WG_ENOMEM;
    int rc = first_point(c, y0, S);
    if (rc == 1) { /* stopped before the first point */
        free(S);
        return WG_OK;
    }
    if (!rc) {
        sol *S2 = malloc(sizeof *S2);
        if (S2)
            *S2 = *S;
        c->nbranch = 1;
        emit_point(c, S, 0, 0, 0.0);
        rc = branch(c, S, 0, c->o->depth, 0);
        if (!rc && S2 && c->o->start != c->o->from && !(c->stop && *c->stop)) {
            for (int j = 0; j <= c->d; j++)
                S2->t[j] = -S2->t[j];
            c->nbranch = 2;
            emit_point(c, S2, 1, 0, 0.0);
            rc = branch(c, S2, 1, c->o->depth, 0);
        }
        free(S2);
        if (!rc)
            rc = run_switches(c);
    }
    free(S);
    return rc;
}

int wg_cont_run(const wg_params *p, const double *y0, const wg_cont_opts *o,
                const wg_cont_sink *sink, volatile sig_atomic_t *stop, char *why,
                size_t whylen)
{
    const char *field = "";
    char msg[200];
    int rc = wg_cont_check(o, &field, msg, sizeof msg);
    if (rc) {
        snprintf(why, whylen, "option %s: %s", field, msg);
        return rc;
    }
    cont *c = calloc(1, sizeof *c);
    if (!c) {
        snprintf(why, whylen, "out of memory");
        return WG_ENOMEM;
    }
    *c = (cont){.p = *p, .o = o, .sink = sink, .stop = stop, .lo = fmin(o->from, o->to),
                .hi = fmax(o->from, o->to), .why = why, .whylen = whylen};
    c->p.v[o->param] = o->start;
    wg_sim_config cfg = {o->model, WG_STEPPER_RK4_EVENT, wg_cont_steps(p, o)};
    if ((rc = wg_sim_init(&c->sim, &c->p, &cfg, why, whylen))) {
        free(c);
        return rc;
    }
    c->d = wg_orbit_dim(&c->sim, c->idx);
    c->th = 1.0 / c->d;
    rc = run(c, y0);
    if (rc == WG_ENOMEM)
        snprintf(why, whylen, "out of memory");
    wg_sim_fini(&c->sim);
    free(c);
    return rc;
}

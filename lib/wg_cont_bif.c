/* wg_cont_bif.c - test functions along a branch and the location of the
 * bifurcations they reveal (wg_cont.h).
 *
 * Detection compares two consecutive points: the tangent's parameter
 * component (fold), the number of real multipliers beyond +1 and -1 and of
 * complex ones outside the unit circle (counted with multiplicity: the
 * table3 scene has exact double multipliers, from the two bearing
 * directions of each body normal to the line of action), and the contact
 * extremes against their thresholds (grazing). Location runs a secant
 * (Illinois, with a bisection every fourth step) on a continuous test
 * value along the arclength from the earlier point, each trial corrected
 * onto the branch. A multiplier test must end near zero: a count that
 * changed because a complex pair met on the real axis outside the circle
 * is not a crossing and is dropped. */
#include "cont.h"
#include "internal.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define REAL_TOL 1e-5 /* |Im mu| below this (relative): a real multiplier (a double
                         real pair may come out of the QR as a pair this close) */
#define CROSS_TOL 1e-4 /* a located multiplier test must end this close to 0 */
#define MAX_EV 64

/* Test values at one point. */
typedef struct tvals {
    double tl;                    /* tangent's parameter component */
    int npos, nneg, ncx;          /* real mu > 1, real mu < -1, complex |mu| > 1 */
    double fpos, fneg, fcx;       /* 1 - mu, mu + 1 and 1 - |mu| of the nearest of each */
    int ipos, ineg, icx;          /* their indices */
    double graz[WG_NCONTACT][4];  /* min - c, min + c, max - c, max + c (NAN: none) */
    double half;                  /* ref . (P^(n/2)(x) - x) (NAN: odd period) */
} tvals;

static int is_real(double re, double im) { return fabs(im) <= REAL_TOL * fmax(1.0, hypot(re, im)); }

/* Dead-zone half width of contact j at point s (the continued parameter
 * may be b or b_j itself). */
static double thr(const cont *c, const sol *s, int j)
{
    int id = j == WG_C_MESH ? WG_P_B : WG_P_B_J;
    return c->o->param == id ? s->u[c->d] : c->p.v[id];
}

static void multiplier_tests(const cont *c, const sol *s, tvals *t)
{
    t->npos = t->nneg = t->ncx = 0;
    t->fpos = t->fneg = t->fcx = INFINITY;
    t->ipos = t->ineg = t->icx = 0;
    for (int i = 0; i < c->d; i++) {
        double re = s->wr[i], im = s->wi[i], m = hypot(re, im);
        if (!is_real(re, im)) {
            t->ncx += m > 1.0;
            if (im > 0 && fabs(1.0 - m) < fabs(t->fcx))
                t->fcx = 1.0 - m, t->icx = i;
            continue;
        }
        t->npos += re > 1.0;
        t->nneg += re < -1.0;
        if (fabs(1.0 - re) < fabs(t->fpos))
            t->fpos = 1.0 - re, t->ipos = i;
        if (fabs(re + 1.0) < fabs(t->fneg))
            t->fneg = re + 1.0, t->ineg = i;
    }
}

static void tests_of(const cont *c, const sol *s, tvals *t)
{
    t->tl = s->t[c->d];
    multiplier_tests(c, s, t);
    double gap[WG_NSTATE_MAX];
    cont_half_gap(c, s, gap);
    t->half = c->has_ref ? 0.0 : NAN;
    for (int i = 0; i < c->d && c->has_ref; i++)
        t->half += c->ref[i] * gap[i];
    int nc = c->d == 2 ? 1 : WG_NCONTACT;
    for (int j = 0; j < WG_NCONTACT; j++) {
        double b = thr(c, s, j);
        for (int k = 0; k < 4; k++) {
            double q = k < 2 ? s->orb.qmin[j] : s->orb.qmax[j];
            t->graz[j][k] = j < nc && b > 0.0 ? q - ((k & 1) ? -b : b) : NAN;
        }
    }
}

static double fval(const cont *c, const sol *s, int kind, int j, int k)
{
    tvals t;
    tests_of(c, s, &t);
    switch (kind) {
    case WG_BIF_FOLD: return t.tl;
    case WG_BIF_BP: return t.fpos;
    case WG_BIF_PD: return t.fneg;
    case WG_BIF_TORUS: return t.fcx;
    default: return t.graz[j][k];
    }
}

static int differ(double a, double b) { return (a > 0) != (b > 0) && isfinite(a) && isfinite(b); }

/* One event found between A and B, before and after location. */
typedef struct event {
    int kind, j, k;
    double sigma, bracket;
    int evals;
    sol *X;
} event;

/* Corrected point at arclength sg along A's tangent. */
static int at_sigma(cont *c, const sol *A, double sg, sol *T)
{
    double up[UMAX], a[UMAX];
    for (int j = 0; j <= c->d; j++) {
        up[j] = A->u[j] + sg * A->t[j];
        a[j] = (j < c->d ? c->th : 1.0) * A->t[j];
    }
    int rc = cont_correct(c, A->n, up, a, T);
    return rc ? rc : cont_finish(c, T, A->t);
}

/* A period-2m branch passing through the period-m orbit within one step,
 * without its fold in the same step (a long step): the crossing is a
 * doubling of the period-m branch located earlier (queued) inside the
 * step; else the end of the step nearer to it stands, with the step as
 * bracket, if the half-period gap there is within a quarter of the step.
 * WG_ERANGE when the gap only turned. */
static int through_parent(cont *c, const sol *A, const sol *B, double sb, event *e)
{
    double ga[WG_NSTATE_MAX], step = 0.0, va = A->u[c->d], vb = B->u[c->d];
    double na = cont_half_gap(c, A, ga), nb = cont_half_gap(c, B, ga);
    for (int j = 0; j < c->d; j++)
        step = fmax(step, fabs(B->u[j] - A->u[j]));
    *e->X = na < nb ? *A : *B;
    e->sigma = na < nb ? 0.0 : sb;
    e->bracket = fabs(vb - va);
    for (int i = 0; i < c->nq; i++) {
        const pdq *q = &c->q[i];
        double v = q->u[c->d];
        if (2 * q->n == A->n && v >= fmin(va, vb) - 1e-6 && v <= fmax(va, vb) + 1e-6) {
            memcpy(e->X->u, q->u, sizeof q->u);
            e->bracket = q->bracket;
            return WG_OK;
        }
    }
    return fmin(na, nb) <= 0.25 * step ? WG_OK : WG_ERANGE;
}

/* Secant (Illinois) on the test value over the arclength [0, sb]; e->X
 * gets the trial with the smallest |value|. WG_OK or WG_ERANGE (a trial
 * failed twice: the bracket so far stands). */
static int locate(cont *c, const sol *A, const sol *B, double sb, event *e)
{
    if (e->j == -2)
        return through_parent(c, A, B, sb, e);
    double lo = 0.0, hi = sb, flo = fval(c, A, e->kind, e->j, e->k);
    double fhi = fval(c, B, e->kind, e->j, e->k), vlo = A->u[c->d], vhi = B->u[c->d];
    double best = fmin(fabs(flo), fabs(fhi));
    *e->X = fabs(flo) < fabs(fhi) ? *A : *B;
    sol *T = malloc(sizeof *T);
    int side = 0, rc = T ? WG_OK : WG_ENOMEM;
    for (int it = 0; !rc && it < 80 && hi - lo > c->o->loc_tol; it++) {
        double sg = (flo * hi - fhi * lo) / (flo - fhi);
        if (!(sg > lo && sg < hi) || it % 4 == 3)
            sg = 0.5 * (lo + hi);
        if (at_sigma(c, A, sg, T) && at_sigma(c, A, sg = 0.5 * (lo + hi), T)) {
            rc = WG_ERANGE;
            break;
        }
        e->evals++;
        double f = fval(c, T, e->kind, e->j, e->k);
        if (fabs(f) < best) {
            best = fabs(f);
            *e->X = *T;
        }
        if (f == 0.0) { /* an exact zero of the test */
            vlo = vhi = T->u[c->d];
            break;
        }
        if ((f > 0) == (fhi > 0)) {
            hi = sg, fhi = f, vhi = T->u[c->d];
            flo *= side == -1 ? 0.5 : 1.0;
            side = -1;
        } else {
            lo = sg, flo = f, vlo = T->u[c->d];
            fhi *= side == 1 ? 0.5 : 1.0;
            side = 1;
        }
    }
    e->sigma = 0.5 * (lo + hi);
    e->bracket = fabs(vhi - vlo);
    free(T);
    return rc;
}

/* Unit (weighted) eigenvector of M for the real multiplier mu, by inverse
 * iteration. */
static int eigvec(const cont *c, const sol *X, double mu, double *v)
{
    int d = c->d;
    double a[WG_NSTATE_MAX * WG_NSTATE_MAX], shift = mu + 1e-9 * (1.0 + fabs(mu));
    for (int i = 0; i < d; i++)
        v[i] = 1.0 + 0.1 * i;
    for (int it = 0; it < 4; it++) {
        memcpy(a, X->orb.M, sizeof(double) * (size_t)(d * d));
        for (int i = 0; i < d; i++)
            a[i * d + i] -= shift;
        int rc = la_solve(d, a, v);
        if (rc)
            return rc;
        double nrm = 0.0;
        for (int i = 0; i < d; i++)
            nrm += c->th * v[i] * v[i];
        for (int i = 0; i < d; i++)
            v[i] /= sqrt(nrm);
    }
    return WG_OK;
}

/* Queue a located period doubling for branch switching (once). */
static void queue_pd(cont *c, const sol *X, int idx, int depth, double bracket)
{
    double v = X->u[c->d];
    for (int i = 0; i < c->nq; i++)
        if (c->q[i].n == X->n && fabs(c->q[i].u[c->d] - v) <= 1e-6)
            return;
    if (c->nq == QMAX)
        return;
    pdq *q = &c->q[c->nq];
    if (eigvec(c, X, X->wr[idx], q->v))
        return;
    memcpy(q->u, X->u, sizeof q->u);
    q->n = X->n;
    q->bracket = bracket;
    q->depth = depth - 1;
    q->done = 0;
    c->nq++;
}

/* A branch point of a period-2m branch where a doubling of the period-m
 * branch was queued: the switched branch has come back to its parent. */
static void close_pd(cont *c, const sol *X)
{
    for (int i = 0; i < c->nq; i++)
        if (2 * c->q[i].n == X->n && fabs(c->q[i].u[c->d] - X->u[c->d]) <= 1e-6)
            c->q[i].done = 1;
}

static void fill(const cont *c, const event *e, int id, wg_bif *b)
{
    const sol *X = e->X;
    tvals t;
    tests_of(c, X, &t);
    int i = e->kind == WG_BIF_PD ? t.ineg : e->kind == WG_BIF_TORUS ? t.icx
          : e->kind == WG_BIF_GRAZING ? 0 : t.ipos;
    memset(b, 0, sizeof *b);
    *b = (wg_bif){e->kind, id, X->n, X->u[c->d], {0}, X->wr[i], X->wi[i], X->orb.xnsec[0],
                  X->orb.qmin[WG_C_MESH], X->orb.qmax[WG_C_MESH], -1, 0, 0, e->bracket, e->evals};
    memcpy(b->y, c->base, sizeof b->y);
    for (int k = 0; k < c->d; k++)
        b->y[c->idx[k]] = X->u[k];
    if (e->kind == WG_BIF_GRAZING) {
        b->contact = e->j;
        b->side = (e->k & 1) ? -1 : 1;
        b->extreme = e->k < 2 ? -1 : 1;
    }
}

/* Candidate events between A and B from their test values. */
static int candidates(const cont *c, const sol *A, const sol *B, event *ev)
{
    tvals ta, tb;
    tests_of(c, A, &ta);
    tests_of(c, B, &tb);
    int n = 0, fold = differ(ta.tl, tb.tl), half = differ(ta.half, tb.half);
    /* A period-2m branch passes through the period-m orbit at a doubling of
     * that orbit, and its parameter turns there: the fold is the branch
     * point (j = -1; without the fold in the same step, j = -2: not
     * located, the corrector would fall onto the period-m orbit). */
    if (fold)
        ev[n++] = (event){WG_BIF_FOLD, half ? -1 : 0, 0, 0, 0, 0, NULL};
    if (half && !fold)
        ev[n++] = (event){WG_BIF_BP, -2, 0, 0, 0, 0, NULL};
    if (!fold && !half && ta.npos != tb.npos && differ(ta.fpos, tb.fpos))
        ev[n++] = (event){WG_BIF_BP, 0, 0, 0, 0, 0, NULL};
    if (ta.nneg != tb.nneg && differ(ta.fneg, tb.fneg))
        ev[n++] = (event){WG_BIF_PD, 0, 0, 0, 0, 0, NULL};
    if (ta.ncx != tb.ncx && differ(ta.fcx, tb.fcx))
        ev[n++] = (event){WG_BIF_TORUS, 0, 0, 0, 0, 0, NULL};
    for (int j = 0; j < WG_NCONTACT; j++)
        for (int k = 0; k < 4 && n < MAX_EV; k++)
            if (differ(ta.graz[j][k], tb.graz[j][k]))
                ev[n++] = (event){WG_BIF_GRAZING, j, k, 0, 0, 0, NULL};
    return n;
}

static int by_sigma(const void *a, const void *b)
{
    double x = ((const event *)a)->sigma, y = ((const event *)b)->sigma;
    return (x > y) - (x < y);
}

int cont_detect(cont *c, const sol *A, const sol *B, double sb, int id, int depth)
{
    event ev[MAX_EV];
    int n = candidates(c, A, B, ev), m = 0, bp = 0;
    for (int i = 0; i < n; i++) {
        event e = ev[i];
        if (!(e.X = malloc(sizeof *e.X)))
            break;
        int rc = locate(c, A, B, sb, &e);
        if (rc && e.j == -2) {
            free(e.X);
            continue;
        }
        double f = fval(c, e.X, e.kind, e.j, e.k);
        if (rc)
            cont_note(c, WG_NOTE_LOCATE, id, e.X->u[c->d], "%s: location stopped (%s), "
                      "parameter bracket %.2e", wg_bif_name(e.kind), wg_status_name(rc),
                      e.bracket);
        if (e.kind != WG_BIF_FOLD && e.kind != WG_BIF_GRAZING && e.j == 0 &&
            !(fabs(f) <= CROSS_TOL)) {
            free(e.X); /* multipliers met off the unit circle: no crossing */
            continue;
        }
        if (e.kind == WG_BIF_FOLD && e.j == -1)
            e.kind = WG_BIF_BP;
        ev[m++] = e;
    }
    qsort(ev, (size_t)m, sizeof ev[0], by_sigma);
    for (int i = 0; i < m; i++) {
        wg_bif b;
        fill(c, &ev[i], id, &b);
        if (c->sink && c->sink->on_bif)
            c->sink->on_bif(c->sink->ctx, &b);
        if (ev[i].kind == WG_BIF_PD && depth > 0) {
            tvals t;
            tests_of(c, ev[i].X, &t);
            queue_pd(c, ev[i].X, t.ineg, depth, ev[i].bracket);
        }
        if (ev[i].kind == WG_BIF_BP) {
            bp = 1;
            close_pd(c, ev[i].X);
        }
        free(ev[i].X);
    }
    return bp;
}

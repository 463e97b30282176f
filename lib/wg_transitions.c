/* wg_transitions.c - the transitions table of a sweep (MODEL.md s5): grazing,
 * back-side impacts, jumps with their up/down hysteresis, period doublings,
 * chaotic and quasi-periodic intervals, returns to period-1. Computed from
 * the points alone; every location is a bracket between two grid values. */
#include "wormgear/wg_sweep.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

#define JUMP_TOL 0.02 /* x b: up/down orbit envelopes differing by more: a jump */
#define JUMP_TOL_APERIODIC 0.1 /* x b: looser for two aperiodic sets (sampling) */
#define CHAOS_GAP 3   /* periodic windows of at most this many points stay inside a band */

static const char *const trans_names[WG_NTRANS] = {
    "grazing", "back-side impacts", "jump", "period doubling", "period halving",
    "period change", "chaos", "quasi-periodic", "return to period-1"};

const char *wg_trans_name(int kind)
{
    return kind >= 0 && kind < WG_NTRANS ? trans_names[kind] : "?";
}

typedef struct tlist {
    wg_transition *v;
    int n, max;
} tlist;

static void add(tlist *t, wg_transition tr)
{
    if (t->n < t->max)
        t->v[t->n++] = tr;
}

/* Period label: n for a periodic point, 0 for anything else. */
static int label(const wg_point *p)
{
    return p->regime == WG_REGIME_PERIODIC ? p->period : 0;
}

static int valid(const wg_point *p)
{
    return p->regime != WG_REGIME_NONE && p->regime != WG_REGIME_DIVERGED;
}

/* A pair of neighbours in increasing-parameter order: lo then hi. */
static wg_transition bracket(int kind, int dir, const wg_point *lo, const wg_point *hi, int from,
                             int to)
{
    wg_transition t = {kind, dir, lo->value, hi->value, 0.5 * (lo->value + hi->value), from, to,
                       NAN, NAN};
    return t;
}

/* The backlash at point p: b, or where b is the swept parameter (NAN) the
 * point's own value. */
static double b_at(const wg_point *p, double b)
{
    return isnan(b) ? p->value : b;
}

/* Contact changes between neighbours lo < hi (in parameter value). */
static void contact_events(tlist *t, int dir, const wg_point *lo, const wg_point *hi, double b)
{
    double glo = lo->min_xn - b_at(lo, b), ghi = hi->min_xn - b_at(hi, b);
    if ((glo > 0) != (ghi > 0)) {
        wg_transition tr = bracket(WG_TR_GRAZING, dir, lo, hi, lo->motion, hi->motion);
        tr.at = lo->value + (hi->value - lo->value) * glo / (glo - ghi);
        add(t, tr);
    }
    if ((lo->motion == WG_MOTION_DOUBLE) != (hi->motion == WG_MOTION_DOUBLE))
        add(t, bracket(WG_TR_BACKSIDE, dir, lo, hi, lo->motion, hi->motion));
}

/* Period changes between neighbours lo < hi. */
static void period_events(tlist *t, int dir, const wg_point *lo, const wg_point *hi)
{
    int a = label(lo), c = label(hi);
    if (a == c)
        return;
    if (c == 1)
        add(t, bracket(WG_TR_RETURN_P1, dir, lo, hi, a, c));
    else if (a && c == 2 * a)
        add(t, bracket(WG_TR_DOUBLING, dir, lo, hi, a, c));
    else if (a && c && a == 2 * c)
        add(t, bracket(WG_TR_HALVING, dir, lo, hi, a, c));
    else if (a && c)
        add(t, bracket(WG_TR_PERIOD, dir, lo, hi, a, c));
}

/* Intervals of points with regime `regime` (ascending order), merging gaps
 * of at most CHAOS_GAP points; from = points in the regime, to = others. */
static void intervals(tlist *t, int kind, int dir, const wg_point *const *asc, int n,
                      int regime)
{
    for (int i = 0; i < n;) {
        if (asc[i]->regime != regime) {
            i++;
            continue;
        }
        int j = i, last = i, in = 0, out = 0;
        while (j < n && j - last <= CHAOS_GAP + 1) {
            if (asc[j]->regime == regime) {
                in++;
                out += j - last > 1 ? j - last - 1 : 0;
                last = j;
            }
            j++;
        }
        wg_transition tr = {kind, dir, asc[i]->value, asc[last]->value, asc[i]->value, in, out,
                            NAN, NAN};
        add(t, tr);
        i = last + 1;
    }
}

/* Events of one sweep, points given in ascending parameter order. */
static void sweep_events(tlist *t, int dir, const wg_point *const *asc, int n, double b)
{
    for (int i = 0; i + 1 < n; i++) {
        if (!valid(asc[i]) || !valid(asc[i + 1]))
            continue;
        contact_events(t, dir, asc[i], asc[i + 1], b);
        period_events(t, dir, asc[i], asc[i + 1]);
    }
    intervals(t, WG_TR_CHAOS, dir, asc, n, WG_REGIME_CHAOTIC);
    intervals(t, WG_TR_QUASI, dir, asc, n, WG_REGIME_QUASIPERIODIC);
}

/* Two attractors at the same parameter value differ by an amplitude jump:
 * their envelopes (min and max x_n) are apart by more than JUMP_TOL b. A
 * different period alone is not a jump: near a period doubling the two
 * sweeps cross it one grid point apart (slow convergence), with the same
 * envelope. */
static int differ(const wg_point *u, const wg_point *d, double b)
{
    if (!valid(u) || !valid(d))
        return 0;
    double bu = b_at(u, b);
    double tol = (!label(u) && !label(d) ? JUMP_TOL_APERIODIC : JUMP_TOL) * (bu > 0 ? bu : 1.0);
    return fabs(u->max_xn - d->max_xn) > tol || fabs(u->min_xn - d->min_xn) > tol;
}

/* Hysteresis intervals: runs of grid values where up and down differ. The
 * up sweep leaves its branch just above the run, the down sweep just
 * below it. */
static void jumps(tlist *t, const wg_point *const *u, const wg_point *const *d, int n, double b)
{
    for (int i = 0; i < n;) {
        if (!differ(u[i], d[i], b)) {
            i++;
            continue;
        }
        int j = i;
        while (j + 1 < n && differ(u[j + 1], d[j + 1], b))
            j++;
        const wg_point *uhi = j + 1 < n ? u[j + 1] : u[j], *dlo = i > 0 ? d[i - 1] : d[i];
        wg_transition tr = {WG_TR_JUMP, 0, u[j]->value, uhi->value,
                            0.5 * (u[j]->value + uhi->value), label(u[j]), label(uhi),
                            dlo->value, d[i]->value};
        add(t, tr);
        i = j + 1;
    }
}

static int cmp_at(const void *a, const void *b)
{
    const wg_transition *x = a, *y = b;
    double ax = x->kind == WG_TR_JUMP ? x->lo2 : x->at, ay = y->kind == WG_TR_JUMP ? y->lo2 : y->at;
    if (ax != ay)
        return (ax > ay) - (ax < ay);
    if (x->dir != y->dir)
        return y->dir - x->dir; /* up first */
    return x->kind - y->kind;
}

/* Pointers to points in ascending parameter order. */
static void ascending(const wg_point *pts, int n, const wg_point **asc)
{
    int rising = n < 2 || pts[n - 1].value >= pts[0].value;
    for (int i = 0; i < n; i++)
        asc[i] = rising ? &pts[i] : &pts[n - 1 - i];
}

int wg_transitions(const wg_point *up, int nup, const wg_point *down, int ndown, double b,
                   wg_transition *out, int max)
{
    tlist t = {out, 0, max};
    const wg_point **au = malloc(sizeof *au * (size_t)(nup + 1));
    const wg_point **ad = malloc(sizeof *ad * (size_t)(ndown + 1));
    if (!au || !ad) {
        free(au);
        free(ad);
        return 0;
    }
    ascending(up, nup, au);
    ascending(down, ndown, ad);
    if (nup)
        sweep_events(&t, +1, au, nup, b);
    if (ndown)
        sweep_events(&t, -1, ad, ndown, b);
    if (nup && nup == ndown)
        jumps(&t, au, ad, nup, b);
    qsort(out, (size_t)t.n, sizeof *out, cmp_at);
    free(au);
    free(ad);
    return t.n;
}

/* sweep_exact.c - matching a sweep's transitions with wgcont's located
 * bifurcations (see sweep_exact.h). */
#include "sweep_exact.h"

#include <math.h>
#include <stdio.h>

/* Parameter interval a transition row covers (both sweeps' brackets). */
static void span(const wg_transition *t, double *lo, double *hi)
{
    if (!t)
        return;
    double a = t->kind == WG_TR_JUMP ? t->lo2 : t->lo, b = t->hi;
    *lo = fmin(*lo, fmin(a, b));
    *hi = fmax(*hi, fmax(a, b));
}

/* Is row r of wgcont the transition t (kind and periods; value unchecked)? */
static int same_kind(const cont_row *r, const wg_transition *t)
{
    int n = t->from && t->to ? (t->from < t->to ? t->from : t->to) : 0;
    switch (t->kind) {
    case WG_TR_GRAZING:
        return r->kind == WG_BIF_GRAZING && r->contact == WG_C_MESH && r->side > 0 &&
               r->extreme < 0;
    case WG_TR_BACKSIDE:
        return r->kind == WG_BIF_GRAZING && r->contact == WG_C_MESH && r->side < 0 &&
               r->extreme < 0;
    case WG_TR_DOUBLING:
    case WG_TR_HALVING:
    case WG_TR_RETURN_P1: return r->kind == WG_BIF_PD && n && r->period == n;
    case WG_TR_JUMP: return r->kind == WG_BIF_FOLD;
    case WG_TR_QUASI: return r->kind == WG_BIF_TORUS;
    default: return 0;
    }
}

/* The matches within win of the row's interval [lo, hi] into buf. */
static void matches(const cont_bifs *x, const wg_transition *t, double lo, double hi, double win,
                    char *buf, size_t len)
{
    double last = NAN;
    size_t n = 0;
    int shown = 0;
    buf[0] = 0;
    for (int i = 0; x && t && i < x->n && n + 40 < len; i++) {
        const cont_row *r = &x->row[i];
        if (!same_kind(r, t) || r->value < lo - win || r->value > hi + win ||
            fabs(r->value - last) < 1e-6)
            continue;
        if (shown++ == 4) {
            n += (size_t)snprintf(buf + n, len - n, "; ...");
            break;
        }
        n += (size_t)snprintf(buf + n, len - n, "%s%.7f (%s P%d)", n ? "; " : "", r->value,
                              wg_bif_name(r->kind), r->period);
        last = r->value;
    }
}

void exact_cell(const cont_bifs *x, const wg_transition *up, const wg_transition *dn,
                double tight, double win, char *buf, size_t len)
{
    const wg_transition *t = up ? up : dn;
    double lo = INFINITY, hi = -INFINITY;
    span(up, &lo, &hi);
    span(dn, &lo, &hi);
    matches(x, t, lo, hi, tight, buf, len);
    if (!buf[0])
        matches(x, t, lo, hi, win, buf, len);
    if (!buf[0])
        snprintf(buf, len, "-");
}

/* wg_herm.c - the cubic Hermite interpolant of a coordinate over one step
 * (its values and rates at both ends): its value, rate, crossings and
 * extrema, and the extremum of x_n inside a step that the period's
 * statistics take. A leaf: the kernels' runs of plain steps, the step
 * driver and the contacts use it. */
#include "internal.h"

#include <math.h>

static double herm_val(const herm *H, double t)
{
    double t2 = t * t, t3 = t2 * t;
    return (2 * t3 - 3 * t2 + 1) * H->q0 + (t3 - 2 * t2 + t) * H->d0 + (-2 * t3 + 3 * t2) * H->q1 +
           (t3 - t2) * H->d1;
}

double herm_der(const herm *H, double t)
{
    double t2 = t * t;
    return (6 * t2 - 6 * t) * H->q0 + (3 * t2 - 4 * t + 1) * H->d0 + (-6 * t2 + 6 * t) * H->q1 +
           (3 * t2 - 2 * t) * H->d1;
}

/* Newton's method on the cubic H(t) - c = ((p3 t + p2) t + p1) t + p0,
 * from the chord's root, inside a bracket that each iterate narrows (a step
 * that would leave it bisects). It stops once the next correction,
 * predicted from this one as |H'' / 2 H'| dt^2, is under 1e-17, or the
 * bracket is 1e-15 wide: two or three evaluations for a crossing, where
 * false position took six. A crossing exactly at the end (H(1) = c) is 1. */
double herm_root(const herm *H, double c)
{
    const double p0 = H->q0 - c, p1 = H->d0;
    const double p2 = 3 * (H->q1 - H->q0) - 2 * H->d0 - H->d1;
    const double p3 = 2 * (H->q0 - H->q1) + H->d0 + H->d1;
    double a = 0.0, b = 1.0, fb = H->q1 - c;
    if (fb == 0.0)
        return 1.0;
    double t = p0 / (p0 - fb);
    if (!(t > a && t < b))
        t = 0.5;
    for (int it = 0; it < 80; it++) {
        double f = ((p3 * t + p2) * t + p1) * t + p0;
        if (f == 0.0)
            return t;
        if ((f > 0) == (fb > 0))
            b = t, fb = f;
        else
            a = t;
        double d = (3 * p3 * t + 2 * p2) * t + p1, dd = 6 * p3 * t + 2 * p2;
        double tn = t - f / d;
        if (!(tn > a && tn < b)) { /* out of the bracket, or d == 0 */
            t = 0.5 * (a + b);
            if (b - a <= 1e-15)
                return t;
            continue;
        }
        double dt = tn - t;
        t = tn;
        if (fabs(dd) * dt * dt <= 2e-17 * fabs(d) || b - a <= 1e-15)
            return t;
    }
    return t;
}

/* Minimum of H on (0,1) when the rate goes from negative to positive. */
double herm_min(const herm *H)
{
    /* H'(t) = A t^2 + B t + C */
    double A = 6 * H->q0 + 3 * H->d0 - 6 * H->q1 + 3 * H->d1;
    double B = -6 * H->q0 - 4 * H->d0 + 6 * H->q1 - 2 * H->d1;
    double C = H->d0;
    double t;
    if (fabs(A) < 1e-300) {
        t = -C / B;
    } else {
        double disc = B * B - 4 * A * C;
        if (disc < 0)
            return dmin(H->q0, H->q1);
        double sq = sqrt(disc);
        double qq = -0.5 * (B + (B >= 0 ? sq : -sq));
        double r1 = qq / A, r2 = qq != 0 ? C / qq : r1;
        /* the minimum is where H'' = 2 A t + B > 0 */
        t = (2 * A * r1 + B > 0) ? r1 : r2;
    }
    double v = (t > 0 && t < 1) ? herm_val(H, t) : INFINITY;
    return dmin(v, dmin(H->q0, H->q1));
}

double herm_max(const herm *H)
{
    herm N = {-H->q0, -H->q1, -H->d0, -H->d1};
    return -herm_min(&N);
}

void herm_turn(double q0, double q1, double v0, double v1, double h, double *mn, double *mx)
{
    if ((v0 < 0) == (v1 < 0))
        return;
    herm H = {q0, q1, v0 * h, v1 * h};
    if (v0 < 0)
        *mn = dmin(*mn, herm_min(&H));
    else
        *mx = dmax(*mx, herm_max(&H));
}

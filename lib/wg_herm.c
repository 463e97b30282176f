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

/* Illinois false position. */
double herm_root(const herm *H, double c)
{
    double a = 0.0, b = 1.0, fa = H->q0 - c, fb = H->q1 - c;
    int side = 0;
    if (fb == 0.0) /* the loop would take 0 for fb's sign and leave the root */
        return 1.0;
    for (int it = 0; it < 60 && b - a > 1e-15; it++) {
        double t = (fa * b - fb * a) / (fa - fb);
        if (!(t > a && t < b))
            t = 0.5 * (a + b);
        double ft = herm_val(H, t) - c;
        if (ft == 0.0)
            return t;
        if ((ft > 0) == (fb > 0)) {
            b = t;
            fb = ft;
            if (side == -1)
                fa *= 0.5;
            side = -1;
        } else {
            a = t;
            fa = ft;
            if (side == 1)
                fb *= 0.5;
            side = 1;
        }
    }
    return 0.5 * (a + b);
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

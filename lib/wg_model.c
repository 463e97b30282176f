/* wg_model.c - reference equations of motion, outputs, equilibrium and the
 * RK4 stability limit. The fast kernels live in wg_kernel.c and are tested
 * against wg_rhs() here. */
#include "wormgear/wg_model.h"
#include "internal.h"
#include "wormgear/wg_regime.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <string.h>

static const char *const model_names[] = {"consistent", "printed"};
static const char *const contact_names[WG_NCONTACT] = {"mesh", "x1", "y1", "z1",
                                                       "x2", "y2", "z2"};
static const char *const event_names[WG_NEVKIND] = {"separation", "drive_impact",
                                                    "back_impact", "back_release"};
static const char *const motion_names[] = {"no_impact", "single_sided", "double_sided"};

const char *wg_model_name(int m) { return (m == 0 || m == 1) ? model_names[m] : "?"; }

int wg_model_lookup(const char *name)
{
    for (int m = 0; m < 2; m++)
        if (strcmp(name, model_names[m]) == 0)
            return m;
    return -1;
}
const char *wg_contact_name(int c) { return (c >= 0 && c < WG_NCONTACT) ? contact_names[c] : "?"; }
const char *wg_event_name(int k) { return (k >= 0 && k < WG_NEVKIND) ? event_names[k] : "?"; }
const char *wg_motion_name(int m) { return (m >= 0 && m <= 2) ? motion_names[m] : "?"; }

int wg_model_nstate(int model) { return model == WG_MODEL_PRINTED ? 16 : 14; }

double wg_deadzone(double x, double c)
{
    if (x > c)
        return x - c;
    if (x < -c)
        return x + c;
    return 0.0;
}

int wg_params_torsional(const wg_params *p)
{
    return p->v[WG_P_MU1] == 0.0 && p->v[WG_P_MU2] == 0.0;
}

void model_exc_trig(const wg_params *p, double psi, double t[4])
{
    const double *v = p->v;
    t[0] = cos(psi + v[WG_P_PHI1]);
    t[1] = cos(psi + v[WG_P_PHI2]);
    t[2] = sin(psi + v[WG_P_PHI2]);
    t[3] = cos(psi + v[WG_P_PHI]);
}

void model_exc_of_trig(const wg_params *p, const double t[4], double omega, wg_exc *e)
{
    const double *v = p->v;
    e->kp = 1.0 + v[WG_P_K_A] * t[0];
    e->te = v[WG_P_E_M] * t[1];
    e->dte = v[WG_P_E_M] * omega * t[2];
    e->fx = v[WG_P_F_M] + v[WG_P_F_E] * t[3];
}

void wg_exc_eval(const wg_params *p, double psi, double omega, wg_exc *e)
{
    double t[4];
    model_exc_trig(p, psi, t);
    model_exc_of_trig(p, t, omega, e);
}

void model_mesh_vectors(int model, const wg_params *p, double c[7], double m[7])
{
    const double *v = p->v;
    double a1 = v[WG_P_A1], a2 = v[WG_P_A2], a3 = v[WG_P_A3];
    const double cc[7] = {a1, a2, -a3, -a1, -a2, a3, 1.0};
    double mu1 = v[WG_P_MU1], mu2 = v[WG_P_MU2];
    if (model == WG_MODEL_PRINTED) /* bare a_i: every body has the mass m_e */
        mu1 = mu2 = 1.0;
    for (int i = 0; i < 7; i++) {
        c[i] = cc[i];
        m[i] = (i < 3 ? mu1 : i < 6 ? mu2 : 1.0) * cc[i];
    }
}

/* Bearing stiffness and damping in the x1 y1 z1 x2 y2 z2 order. */
static void bearings(const wg_params *p, double k[6], double xi[6])
{
    for (int i = 0; i < 6; i++) {
        k[i] = p->v[WG_P_K1X + i];
        xi[i] = p->v[WG_P_XI1X + i];
    }
}

static void mesh(int model, const wg_params *p, const wg_exc *e, const double *y,
                 double *xn, double *dxn, double *F)
{
    double c[7], m[7];
    model_mesh_vectors(model, p, c, m);
    int nd = model == WG_MODEL_PRINTED ? 8 : 7;
    double x = -e->te, dx = e->dte;
    for (int i = 0; i < 6; i++) {
        x += c[i] * y[i];
        dx += c[i] * y[nd + i];
    }
    if (model == WG_MODEL_PRINTED) { /* theta1 + theta2 (lever arms absorbed) */
        x += y[6] + y[7];
        dx += y[14] + y[15];
    } else {
        x += y[6];
        dx += y[13];
    }
    *xn = x;
    *dxn = dx;
    *F = 2.0 * p->v[WG_P_XI_P] * dx + e->kp * wg_deadzone(x, p->v[WG_P_B]);
}

void wg_rhs(int model, const wg_params *p, const wg_exc *e, const double *y, double *dy)
{
    double c[7], m[7], k[6], xi[6], xn, dxn, F;
    model_mesh_vectors(model, p, c, m);
    bearings(p, k, xi);
    mesh(model, p, e, y, &xn, &dxn, &F);
    int nd = model == WG_MODEL_PRINTED ? 8 : 7;
    for (int i = 0; i < nd; i++)
        dy[i] = y[nd + i];
    for (int i = 0; i < 6; i++)
        dy[nd + i] = -2.0 * xi[i] * y[nd + i] - k[i] * wg_deadzone(y[i], p->v[WG_P_B_J]) - m[i] * F;
    double dg = 2.0 * p->v[WG_P_XI_G];
    if (model == WG_MODEL_PRINTED) {
        /* As printed: theta1'' - a1 F = f (anti-restoring), theta2'' + a3 F = 0,
         * no lever arms, no load torque. */
        dy[14] = -dg * y[14] + p->v[WG_P_A1] * F + e->fx;
        dy[15] = -dg * y[15] - p->v[WG_P_A3] * F;
    } else {
        dy[13] = -dg * y[13] - F + e->fx;
    }
}

void wg_outputs_eval(int model, const wg_params *p, const wg_exc *e, const double *y,
                     wg_outputs *o)
{
    double k[6], xi[6];
    mesh(model, p, e, y, &o->xn, &o->dxn, &o->F);
    bearings(p, k, xi);
    int nd = model == WG_MODEL_PRINTED ? 8 : 7;
    double mu[2] = {p->v[WG_P_MU1], p->v[WG_P_MU2]};
    if (model == WG_MODEL_PRINTED)
        mu[0] = mu[1] = 1.0;
    for (int i = 0; i < 6; i++) {
        double f = k[i] * wg_deadzone(y[i], p->v[WG_P_B_J]) + 2.0 * xi[i] * y[nd + i];
        double u = mu[i / 3];
        o->fb[i] = u > 0.0 ? f / u : 0.0;
    }
}

/* x in [0, 2 pi). */
static double wrap_angle(double x)
{
    x -= TWO_PI * floor(x / TWO_PI);
    return x >= TWO_PI ? 0.0 : x;
}

void wg_angles(int model, const wg_params *p, uint64_t period, double psi, const double *y,
               double th[2])
{
    double z1 = p->v[WG_P_Z1], z2 = p->v[WG_P_Z2];
    double e1, e2;
    if (model == WG_MODEL_PRINTED) {
        e1 = y[6] / p->v[WG_P_RHO1];
        e2 = -y[7] / p->v[WG_P_RHO2];
    } else {
        double a1 = p->v[WG_P_A1], a3 = p->v[WG_P_A3];
        double w1 = a1 / p->v[WG_P_J1], w3 = a3 / p->v[WG_P_J2];
        double D = a1 * w1 + a3 * w3;
        double s = D > 0.0 ? y[6] / D : 0.0;
        e1 = s * w1 / p->v[WG_P_RHO1];
        e2 = -s * w3 / p->v[WG_P_RHO2];
    }
    /* period mod z: whole turns of the mesh phase within one revolution (a
     * table row is a whole number >= 1; anything else counts as 1 tooth) */
    uint64_t n1 = z1 >= 1 && z1 <= 1e6 ? (uint64_t)z1 : 1;
    uint64_t n2 = z2 >= 1 && z2 <= 1e6 ? (uint64_t)z2 : 1;
    double k1 = (double)(period % n1), k2 = (double)(period % n2);
    th[0] = wrap_angle((TWO_PI * k1 + psi) / (double)n1 + e1);
    th[1] = wrap_angle((TWO_PI * k2 + psi) / (double)n2 + e2);
}

/* Inverse of the dead zone on its outer branches: g(x; c) = v. */
static double deadzone_inv(double v, double c)
{
    return v > 0.0 ? v + c : v < 0.0 ? v - c : 0.0;
}

void wg_equilibrium(int model, const wg_params *p, double *y)
{
    double c[7], m[7], k[6], xi[6];
    model_mesh_vectors(model, p, c, m);
    bearings(p, k, xi);
    int n = wg_model_nstate(model);
    memset(y, 0, (size_t)n * sizeof *y);
    double f0 = p->v[WG_P_F_M];
    double xn = deadzone_inv(f0, p->v[WG_P_B]);
    int rigid = model == WG_MODEL_CONSISTENT && wg_params_torsional(p);
    double rest = xn + p->v[WG_P_E_M] * cos(p->v[WG_P_PHI2]);
    for (int i = 0; i < 6 && !rigid; i++) {
        y[i] = deadzone_inv(-m[i] * f0 / k[i], p->v[WG_P_B_J]);
        rest -= c[i] * y[i];
    }
    if (model == WG_MODEL_PRINTED)
        y[6] = y[7] = 0.5 * rest;
    else
        y[6] = rest;
}

/* ---- RK4 stability limit ------------------------------------------------ */

enum { SN = 14 };
#define RK4_TOL (1.0 + 1e-8) /* |R| up to this counts as stable (rounding of A) */

static void matmul(int n, const double *a, const double *b, double *out)
{
    for (int i = 0; i < n; i++)
        for (int j = 0; j < n; j++) {
            double s = 0.0;
            for (int l = 0; l < n; l++)
                s += a[i * n + l] * b[l * n + j];
            out[i * n + j] = s;
        }
}

/* First-order system matrix of the stiffest linear configuration. */
static int linear_matrix(const wg_params *p, double *A)
{
    double c[7], m[7], k[6], xi[6];
    model_mesh_vectors(WG_MODEL_CONSISTENT, p, c, m);
    bearings(p, k, xi);
    double kp = 1.0 + p->v[WG_P_K_A], dp = 2.0 * p->v[WG_P_XI_P];
    int lo = wg_params_torsional(p) ? 6 : 0; /* torsional: s only */
    int nd = 7 - lo, n = 2 * nd;
    memset(A, 0, sizeof(double) * (size_t)(n * n));
    for (int i = 0; i < nd; i++) {
        int I = lo + i;
        A[i * n + nd + i] = 1.0;
        double *row = &A[(nd + i) * n];
        for (int j = 0; j < nd; j++) {
            int J = lo + j;
            row[j] = -m[I] * kp * c[J];
            row[nd + j] = -m[I] * dp * c[J];
        }
        if (I < 6) {
            row[i] -= k[I];
            row[nd + i] -= 2.0 * xi[I];
        } else {
            row[nd + i] -= 2.0 * p->v[WG_P_XI_G];
        }
    }
    return n;
}

/* Spectral radius of the RK4 step matrix R(hA) from ||P^(2^30)||^(2^-30),
 * or the first upper bound found at or below `stable`. */
static double rk4_radius(int n, const double *A, double h, double stable)
{
    double P[SN * SN], T[SN * SN], U[SN * SN];
    /* P = I + hA (I + hA/2 (I + hA/3 (I + hA/4))) by Horner. */
    for (int i = 0; i < n * n; i++)
        P[i] = (i % (n + 1) == 0) ? 1.0 : 0.0;
    for (int d = 4; d >= 1; d--) {
        matmul(n, A, P, T);
        for (int i = 0; i < n * n; i++)
            P[i] = (i % (n + 1) == 0 ? 1.0 : 0.0) + h / d * T[i];
    }
    /* ||P^n||^(1/n) >= rho for every n: once it is below the tolerance the
     * step is stable, and most stable candidates stop after a few squarings. */
    double logc = 0.0;
    for (int it = 0; it < 30; it++) {
        matmul(n, P, P, U);
        double nrm = 0.0;
        for (int i = 0; i < n; i++) {
            double s = 0.0;
            for (int j = 0; j < n; j++)
                s += fabs(U[i * n + j]);
            nrm = s > nrm ? s : nrm;
        }
        if (!(nrm > 0.0) || !isfinite(nrm))
            return nrm > 0.0 ? INFINITY : 0.0;
        for (int i = 0; i < n * n; i++)
            P[i] = U[i] / nrm;
        logc = 2.0 * logc + log(nrm);
        double est = exp(ldexp(logc, -(it + 1))); /* ||P^(2^(it+1))||^(2^-(it+1)) */
        if (est <= stable)
            return est;
    }
    return exp(ldexp(logc, -30));
}

double model_rk4_hmax_bisect(const wg_params *p)
{
    double A[SN * SN];
    int n = linear_matrix(p, A);
    double lo = 0.0, hi = 1.0;
    while (rk4_radius(n, A, hi, RK4_TOL) <= RK4_TOL) {
        lo = hi;
        hi *= 2.0;
        if (hi > 1e6)
            return hi;
    }
    for (int it = 0; it < 32; it++) { /* relative precision 2^-32 of hi */
        double mid = 0.5 * (lo + hi);
        if (rk4_radius(n, A, mid, RK4_TOL) <= RK4_TOL)
            lo = mid;
        else
            hi = mid;
    }
    return lo;
}

/* |R(h lam)|^2 for the RK4 polynomial R(z) = 1 + z + z^2/2 + z^3/6 + z^4/24
 * and lam = re + i im (Horner, as rk4_radius forms R(hA)). */
static double rk4_gain2(double re, double im, double h)
{
    /* The loop d = 4, 3, 2, 1 unrolled: a division by 4, 2 or 1 is the
     * multiplication by its exact inverse (the same bits), only the 3s stay
     * divisions. The first stage starts from 1 + 0i. */
    double zr = h * re, zi = h * im;
    double pr = 1.0 + zr * 0.25, pi = zi * 0.25;
    double tr = (zr * pr - zi * pi) / 3, ti = (zr * pi + zi * pr) / 3;
    pr = 1.0 + tr, pi = ti;
    tr = (zr * pr - zi * pi) * 0.5, ti = (zr * pi + zi * pr) * 0.5;
    pr = 1.0 + tr, pi = ti;
    tr = zr * pr - zi * pi, ti = zr * pi + zi * pr;
    pr = 1.0 + tr, pi = ti;
    return pr * pr + pi * pi;
}

/* Largest h with |R(h' lam)| <= RK4_TOL for every h' in [0, h]. Along a ray
 * into the left half-plane RK4's stability region is left once, at
 * |h lam| <= 2.97 (checked on a 0.05-degree grid of rays): a scan brackets
 * that exit and bisection pins it to the last bit. No ray into the closed
 * left half-plane leaves before |h lam| = 2.6155 (at 122.7 degrees; 0.01-
 * degree grid), so there the scan starts at grid point SCAN_LEFT
 * (|h lam| = 2.5): every point below it is inside, as the full scan finds,
 * and the bracket is the same. */
static double ray_hmax(double re, double im)
{
    enum { SCAN = 64, SCAN_LEFT = 50 };
    double mod = hypot(re, im), t2 = RK4_TOL * RK4_TOL, lo = 0.0, hi = 0.0;
    if (!(mod > 0.0))
        return INFINITY;
    for (int i = re <= 0.0 ? SCAN_LEFT : 1; i <= SCAN && lo == hi; i++) {
        hi = 3.2 / mod * i / SCAN;
        if (rk4_gain2(re, im, hi) <= t2)
            lo = hi;
    }
    if (lo == hi) /* no exit up to |z| = 3.2: cannot happen for RK4 */
        return hi;
    for (double mid = 0.5 * (lo + hi); mid > lo && mid < hi; mid = 0.5 * (lo + hi))
        *(rk4_gain2(re, im, mid) <= t2 ? &lo : &hi) = mid;
    return lo;
}

double wg_rk4_hmax(int model, const wg_params *p)
{
    if (model != WG_MODEL_CONSISTENT)
        return 0.0;
    double A[SN * SN], wr[SN], wi[SN], h = INFINITY;
    int n = linear_matrix(p, A);
    if (wg_eig(n, A, wr, wi) != WG_OK) /* QR did not converge: the slow way */
        return model_rk4_hmax_bisect(p);
    for (int i = 0; i < n; i++)
        if (wi[i] >= 0.0) /* a conjugate has the same |R| */
            h = dmin(h, ray_hmax(wr[i], wi[i]));
    return h > 1e6 ? 1048576.0 : h;
}

int wg_params_same_linear(const wg_params *a, const wg_params *b)
{
    static const int ids[] = {WG_P_XI_P, WG_P_XI_G, WG_P_K_A, WG_P_A1, WG_P_A2, WG_P_A3,
                              WG_P_MU1, WG_P_MU2};
    for (unsigned i = 0; i < sizeof ids / sizeof ids[0]; i++)
        if (a->v[ids[i]] != b->v[ids[i]])
            return 0;
    for (int i = WG_P_K1X; i <= WG_P_XI2Z; i++)
        if (a->v[i] != b->v[i])
            return 0;
    return 1;
}

int wg_min_steps(double hmax, double omega)
{
    if (!(hmax > 0.0))
        return 1;
    double n = 6.283185307179586 / (omega * hmax);
    return (int)ceil(n * (1.0 - 1e-12));
}

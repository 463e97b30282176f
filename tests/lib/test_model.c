/* Model equations: dead zone, hand-computed RHS terms, every specialised
 * kernel against the reference RHS, symmetric stiffness (consistent) vs the
 * printed form's asymmetry and drift, equilibrium, RK4 stability limit,
 * the split step's excitation by rotation, the contacts' zone bounds. */
#include "kern_fix.h"

#include <math.h>
#include <time.h>

static void test_deadzone(void)
{
    ASSERT_NEAR(wg_deadzone(1.5, 1.0), 0.5, 0);
    ASSERT_NEAR(wg_deadzone(-1.5, 1.0), -0.5, 0);
    ASSERT_NEAR(wg_deadzone(0.3, 1.0), 0.0, 0);
    ASSERT_NEAR(wg_deadzone(-1.0, 1.0), 0.0, 0);
    ASSERT_NEAR(wg_deadzone(2.0, 0.0), 2.0, 0);
    ASSERT_NEAR(wg_deadzone(-2.0, 0.0), -2.0, 0);
}

/* Model names and back: the one table (scenes, wgsim --model, PARAMS). */
static void test_model_names(void)
{
    ASSERT_EQ_INT(wg_model_lookup("consistent"), WG_MODEL_CONSISTENT);
    ASSERT_EQ_INT(wg_model_lookup("printed"), WG_MODEL_PRINTED);
    for (int m = 0; m < 2; m++)
        ASSERT_EQ_INT(wg_model_lookup(wg_model_name(m)), m);
    ASSERT_EQ_INT(wg_model_lookup("Consistent"), -1);
    ASSERT_EQ_INT(wg_model_lookup(""), -1);
    ASSERT_EQ_INT(wg_model_lookup("?"), -1);
}

static void test_rhs_hand_computed(void)
{
    wg_params p;
    wg_params_default(&p);
    const double *v = p.v;
    double y[14], dy[14];
    some_state(y);
    double psi = 0.7, om = 1.3;
    wg_exc e;
    wg_exc_eval(&p, psi, om, &e);
    ASSERT_NEAR(e.kp, 1 + v[WG_P_K_A] * cos(psi + v[WG_P_PHI1]), 1e-15);
    ASSERT_NEAR(e.te, v[WG_P_E_M] * cos(psi + v[WG_P_PHI2]), 1e-15);
    ASSERT_NEAR(e.dte, v[WG_P_E_M] * om * sin(psi + v[WG_P_PHI2]), 1e-15);
    ASSERT_NEAR(e.fx, v[WG_P_F_M] + v[WG_P_F_E] * cos(psi + v[WG_P_PHI]), 1e-15);
    wg_rhs(WG_MODEL_CONSISTENT, &p, &e, y, dy);
    /* MODEL.md s2 written out term by term */
    double a1 = v[WG_P_A1], a2 = v[WG_P_A2], a3 = v[WG_P_A3], mu1 = v[WG_P_MU1], mu2 = v[WG_P_MU2];
    double xn = a1 * (y[0] - y[3]) + a2 * (y[1] - y[4]) - a3 * (y[2] - y[5]) + y[6] - e.te;
    double dxn = a1 * (y[7] - y[10]) + a2 * (y[8] - y[11]) - a3 * (y[9] - y[12]) + y[13] + e.dte;
    double gx = xn > 1 ? xn - 1 : xn < -1 ? xn + 1 : 0; /* b = 1 */
    double F = 2 * v[WG_P_XI_P] * dxn + e.kp * gx;
    double bj = 1.0;
#define G(x) ((x) > bj ? (x) - bj : (x) < -bj ? (x) + bj : 0.0)
    double ex[14];
    for (int i = 0; i < 7; i++)
        ex[i] = y[7 + i];
    ex[7] = -2 * v[WG_P_XI1X] * y[7] - v[WG_P_K1X] * G(y[0]) - mu1 * a1 * F;
    ex[8] = -2 * v[WG_P_XI1Y] * y[8] - v[WG_P_K1Y] * G(y[1]) - mu1 * a2 * F;
    ex[9] = -2 * v[WG_P_XI1Z] * y[9] - v[WG_P_K1Z] * G(y[2]) + mu1 * a3 * F;
    ex[10] = -2 * v[WG_P_XI2X] * y[10] - v[WG_P_K2X] * G(y[3]) + mu2 * a1 * F;
    ex[11] = -2 * v[WG_P_XI2Y] * y[11] - v[WG_P_K2Y] * G(y[4]) + mu2 * a2 * F;
    ex[12] = -2 * v[WG_P_XI2Z] * y[12] - v[WG_P_K2Z] * G(y[5]) - mu2 * a3 * F;
    ex[13] = -2 * v[WG_P_XI_G] * y[13] - F + e.fx;
#undef G
    for (int i = 0; i < 14; i++)
        ASSERT_NEAR(dy[i], ex[i], 1e-13);
    wg_outputs o;
    wg_outputs_eval(WG_MODEL_CONSISTENT, &p, &e, y, &o);
    ASSERT_NEAR(o.xn, xn, 1e-14);
    ASSERT_NEAR(o.dxn, dxn, 1e-14);
    ASSERT_NEAR(o.F, F, 1e-14);
    /* worm bearing x force in mesh-force units: (k g + 2 xi v) / mu1 */
    ASSERT_NEAR(o.fb[0], (v[WG_P_K1X] * 0.3 + 2 * v[WG_P_XI1X] * y[7]) / mu1, 1e-13);
}

/* One RK4 step with the reference RHS (excitation at the three stages). */
static void ref_step(int model, const wg_params *p, const wg_exc *e, const double *y0, double *y1,
                     double h, int n)
{
    double k[4][16], yt[16];
    wg_rhs(model, p, &e[0], y0, k[0]);
    for (int i = 0; i < n; i++)
        yt[i] = y0[i] + 0.5 * h * k[0][i];
    wg_rhs(model, p, &e[1], yt, k[1]);
    for (int i = 0; i < n; i++)
        yt[i] = y0[i] + 0.5 * h * k[1][i];
    wg_rhs(model, p, &e[1], yt, k[2]);
    for (int i = 0; i < n; i++)
        yt[i] = y0[i] + h * k[2][i];
    wg_rhs(model, p, &e[2], yt, k[3]);
    for (int i = 0; i < n; i++)
        y1[i] = y0[i] + h / 6 * (k[0][i] + 2 * k[1][i] + 2 * k[2][i] + k[3][i]);
}

/* Every specialisation, through wg_sim's own selection, equals the reference
 * step on parameters where its dropped terms are really zero. */
static void test_kernels_match_reference(void)
{
    for (unsigned f = 0; f < 64; f++) {
        if (kfix_skip(f))
            continue;
        wg_params p;
        wg_sim s;
        double y0[16], y1[16], yr[16];
        kfix_setup(f, &p, &s, y0);
        memcpy(y1, y0, sizeof y1);
        wg_exc e[3];
        double h = 0.01;
        for (int j = 0; j < 3; j++)
            wg_exc_eval(&p, 0.4 + 0.005 * j, 1.0, &e[j]);
        /* zone-locked kernels need zones matching the state */
        if (f & KF_LOCK) {
            double q[7];
            q[0] = y0[6] - e[0].te;
            for (int i = 0; i < 6; i++)
                q[0] += s.core->kc.c[i] * y0[i];
            for (int i = 0; i < 6; i++)
                q[i + 1] = y0[i];
            for (int j = 0; j < 7; j++) {
                double c = j ? p.v[WG_P_B_J] : p.v[WG_P_B];
                int z = q[j] > c ? 1 : q[j] < -c ? -1 : 0;
                s.core->kc.w[j] = z ? 1 : 0;
                s.core->kc.zc[j] = z * c;
            }
        }
        s.core->kernel(y0, y1, &s.core->kc, e, h);
        ref_step(WG_MODEL_CONSISTENT, &p, e, y0, yr, h, 14);
        double err = maxdiff(y1, yr, 14);
        if (err > 1e-13)
            fprintf(stderr, "kernel flags %u: max diff %.3g\n", f, err);
        ASSERT_TRUE(err <= 1e-13);
        wg_sim_fini(&s);
    }
}

/* Stiffness Jacobian d(acc)/d(q) by central differences, linear case. */
static void jacobian(int model, const wg_params *p, double J[8][8])
{
    int n = wg_model_nstate(model), nd = n / 2;
    wg_exc e = {1.0 + p->v[WG_P_K_A], 0, 0, 0};
    for (int j = 0; j < nd; j++) {
        double yp[16] = {0}, ym[16] = {0}, dp[16], dm[16];
        yp[j] = 1e-3;
        ym[j] = -1e-3;
        wg_rhs(model, p, &e, yp, dp);
        wg_rhs(model, p, &e, ym, dm);
        for (int i = 0; i < nd; i++)
            J[i][j] = (dp[nd + i] - dm[nd + i]) / 2e-3;
    }
}

static void test_stiffness_symmetry(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_B] = p.v[WG_P_B_J] = 0;
    double J[8][8];
    /* consistent: diag(1/mu) J is symmetric (J = -M^-1 K, K symmetric) */
    jacobian(WG_MODEL_CONSISTENT, &p, J);
    double w[7];
    for (int i = 0; i < 7; i++)
        w[i] = i < 3 ? 1 / p.v[WG_P_MU1] : i < 6 ? 1 / p.v[WG_P_MU2] : 1.0;
    double asym = 0;
    for (int i = 0; i < 7; i++)
        for (int j = 0; j < 7; j++)
            asym = fmax(asym, fabs(w[i] * J[i][j] - w[j] * J[j][i]));
    ASSERT_TRUE(asym < 1e-9);
    /* printed: no positive diagonal scaling can symmetrise it: the
     * theta1-theta2 coupling has opposite signs both ways, and theta1's own
     * stiffness is negative (anti-restoring). */
    jacobian(WG_MODEL_PRINTED, &p, J);
    ASSERT_TRUE(J[6][7] * J[7][6] < 0);
    ASSERT_TRUE(J[6][6] > 0); /* d(th1'')/d(th1) > 0: anti-restoring */
    int sign_asym = 0;
    for (int i = 0; i < 8; i++)
        for (int j = 0; j < 8; j++)
            sign_asym += J[i][j] * J[j][i] < -1e-12;
    ASSERT_TRUE(sign_asym > 0);
}

/* Under constant torque the printed form's rotations drift without bound;
 * the consistent form settles. */
static void test_printed_drifts_consistent_settles(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_K_A] = p.v[WG_P_E_M] = p.v[WG_P_F_E] = 0;
    p.v[WG_P_XI_G] = 0.05;
    char why[300];
    double y1[2][16], y2[2][16];
    for (int m = 0; m < 2; m++) {
        wg_sim_config cfg = {m, WG_STEPPER_RK4, 128};
        wg_sim s;
        ASSERT_EQ_INT(wg_sim_init(&s, &p, &cfg, why, sizeof why), WG_OK);
        double y[16] = {0};
        wg_sim_set_state(&s, y, 0, 0); /* start at rest, undeflected */
        ASSERT_EQ_INT(wg_sim_run(&s, 128 * 200, NULL, NULL), WG_OK);
        memcpy(y1[m], s.y, sizeof s.y);
        ASSERT_EQ_INT(wg_sim_run(&s, 128 * 200, NULL, NULL), WG_OK);
        memcpy(y2[m], s.y, sizeof s.y);
        wg_sim_fini(&s);
    }
    /* consistent: state at 200 and 400 periods agree (settled, bounded) */
    for (int i = 0; i < 14; i++)
        ASSERT_NEAR(y2[0][i], y1[0][i], 1e-6);
    /* printed: theta1 grows linearly (damped rigid-body mode under torque) */
    double th1a = y1[1][6], th1b = y2[1][6];
    ASSERT_TRUE(fabs(th1b) > 1.8 * fabs(th1a) && fabs(th1a) > 10);
    ASSERT_TRUE(fabs(y2[1][14]) > 0.01); /* its rate does not decay to zero */
}

static void test_equilibrium_is_static(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_K_A] = p.v[WG_P_E_M] = p.v[WG_P_F_E] = 0;
    double y[14], dy[14];
    wg_equilibrium(WG_MODEL_CONSISTENT, &p, y);
    wg_exc e;
    wg_exc_eval(&p, 0, 1, &e);
    wg_rhs(WG_MODEL_CONSISTENT, &p, &e, y, dy);
    for (int i = 0; i < 14; i++)
        ASSERT_NEAR(dy[i], 0, 1e-14);
    wg_outputs o;
    wg_outputs_eval(WG_MODEL_CONSISTENT, &p, &e, y, &o);
    ASSERT_NEAR(o.xn, p.v[WG_P_B] + p.v[WG_P_F_M], 1e-14);
    ASSERT_NEAR(o.F, p.v[WG_P_F_M], 1e-14);
    /* bearings beyond their clearance, pushed by the mesh force */
    ASSERT_TRUE(fabs(y[0]) > p.v[WG_P_B_J] && y[0] < 0);
    /* with TE the mesh coordinate still starts at b + f_m */
    wg_params_default(&p);
    wg_equilibrium(WG_MODEL_CONSISTENT, &p, y);
    wg_exc_eval(&p, 0, 1, &e);
    wg_outputs_eval(WG_MODEL_CONSISTENT, &p, &e, y, &o);
    ASSERT_NEAR(o.xn, p.v[WG_P_B] + p.v[WG_P_F_M], 1e-14);
}

/* Linear, unforced, undamped-by-contact run: below the limit it blows up,
 * just above it stays bounded; wg_sim refuses N below the limit. */
static void test_stability_limit(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_B] = p.v[WG_P_B_J] = 0;
    p.v[WG_P_E_M] = p.v[WG_P_F_M] = p.v[WG_P_F_E] = 0;
    double hmax = wg_rk4_hmax(WG_MODEL_CONSISTENT, &p);
    ASSERT_TRUE(hmax > 0.05 && hmax < 2);
    /* k_a = 0 so the linear system is exactly the one analysed */
    p.v[WG_P_K_A] = 0;
    hmax = wg_rk4_hmax(WG_MODEL_CONSISTENT, &p);
    double om = 0.1;
    int nmin = wg_min_steps(hmax, om);
    char why[300];
    wg_sim s;
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4, nmin - 1};
    p.v[WG_P_OMEGA] = om;
    ASSERT_EQ_INT(wg_sim_init(&s, &p, &cfg, why, sizeof why), WG_ESTABILITY);
    char need[64];
    snprintf(need, sizeof need, "need N >= %d", nmin);
    ASSERT_CONTAINS(why, need);
    /* run the step matrix directly at h just above and below the limit */
    for (int side = 0; side < 2; side++) {
        double h = hmax * (side ? 1.02 : 0.98);
        wg_sim_config c2 = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4, 1024};
        p.v[WG_P_OMEGA] = 1.0;
        ASSERT_EQ_INT(wg_sim_init(&s, &p, &c2, why, sizeof why), WG_OK);
        double y[16] = {0}, y1[16] = {0};
        some_state(y);
        wg_exc e[3] = {{1, 0, 0, 0}, {1, 0, 0, 0}, {1, 0, 0, 0}};
        double n0 = 0, n1 = 0;
        for (int i = 0; i < 14; i++)
            n0 += y[i] * y[i];
        for (int it = 0; it < 20000; it++) {
            s.core->kernel(y, y1, &s.core->kc, e, h);
            memcpy(y, y1, sizeof y);
        }
        for (int i = 0; i < 14; i++)
            n1 += y[i] * y[i];
        if (side == 0)
            ASSERT_TRUE(n1 < n0);
        else
            ASSERT_TRUE(!(n1 <= 1e6 * n0)); /* grew, or overflowed to inf/NaN */
        wg_sim_fini(&s);
    }
}

/* Random linear parts over the table's ranges: stiffness and damping
 * log-uniform, some undamped, some rigid (torsional), geometry normalised. */
static void random_linear(wg_params *p, unsigned *seed)
{
    wg_params_default(p);
#define U01() ((double)rand_r(seed) / RAND_MAX)
    for (int i = WG_P_K1X; i <= WG_P_K2Z; i++)
        p->v[i] = pow(10.0, -3.0 + 7.0 * U01());
    for (int i = WG_P_XI1X; i <= WG_P_XI2Z; i++)
        p->v[i] = U01() < 0.1 ? 0.0 : pow(10.0, -3.0 + 4.0 * U01());
    p->v[WG_P_XI_P] = U01() < 0.1 ? 0.0 : 2.0 * U01();
    p->v[WG_P_XI_G] = U01() < 0.5 ? 0.0 : U01();
    p->v[WG_P_K_A] = 0.95 * U01();
    int rigid = U01() < 0.1;
    p->v[WG_P_MU1] = rigid ? 0.0 : pow(10.0, -2.0 + 4.0 * U01());
    p->v[WG_P_MU2] = rigid ? 0.0 : pow(10.0, -2.0 + 4.0 * U01());
    double al = 0.5 * U01(), be = 1.5 * U01();
    p->v[WG_P_A1] = cos(al) * sin(be);
    p->v[WG_P_A2] = sin(al);
    p->v[WG_P_A3] = cos(al) * cos(be);
#undef U01
}

/* The eigenvalue limit against the slow spectral-radius bisection it
 * replaced: the scenes, the table's corners and random linear parts. */
static void test_stability_limit_methods(void)
{
    unsigned seed = test_seed("random linear parts:");
    double worst = 0.0, tfast = 0.0, tslow = 0.0;
    for (int i = 0; i < 120; i++) {
        wg_params p;
        if (i < 4) {
            static const char *const mu[4][2] = {{"1", "1"}, {"0", "0"}, {"100", "0.01"}, {"0.01", "100"}};
            wg_params_default(&p);
            p.v[WG_P_MU1] = atof(mu[i][0]);
            p.v[WG_P_MU2] = atof(mu[i][1]);
            p.v[WG_P_XI_P] = i == 1 ? 0.0 : 2.0;
        } else {
            random_linear(&p, &seed);
        }
        char why[200];
        if (wg_params_check(&p, why, sizeof why) != WG_OK)
            continue;
        struct timespec a, b, c;
        clock_gettime(CLOCK_MONOTONIC, &a);
        double hf = wg_rk4_hmax(WG_MODEL_CONSISTENT, &p);
        clock_gettime(CLOCK_MONOTONIC, &b);
        double hs = model_rk4_hmax_bisect(&p);
        clock_gettime(CLOCK_MONOTONIC, &c);
        tfast += (b.tv_sec - a.tv_sec) + 1e-9 * (b.tv_nsec - a.tv_nsec);
        tslow += (c.tv_sec - b.tv_sec) + 1e-9 * (c.tv_nsec - b.tv_nsec);
        double rel = fabs(hf - hs) / hs;
        if (!(rel <= 1e-7))
            printf("case %d: eigenvalues %.17g, bisection %.17g (rel %.2e)\n", i, hf, hs, rel);
        ASSERT_TRUE(rel <= 1e-7);
        worst = rel > worst ? rel : worst;
    }
    printf("stability limit, eigenvalues vs bisection: max relative difference %.2e; "
           "%.1f us vs %.1f us per call\n", worst, 1e6 * tfast / 120, 1e6 * tslow / 120);
}

/* The split step's excitation by rotation from psi0 (ct_exc_rot) is
 * ct_exc_at's within their roundings (libm's psi0 + d is rounded to 9e-16):
 * at every step start psi0 = 2 pi k / N and at sub-step times across the
 * step, for N on each of its three branches (short and long polynomial,
 * libm below N = 26), and along an omega ramp's quadratic phase and past
 * its end. */
static void test_split_excitation_by_rotation(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = 8.0; /* h = 2 pi / (omega N) within the RK4 limit at N = 8 */
    p.v[WG_P_F_E] = 0.3;
    const int Ns[] = {8, 25, 26, 64, 125, 126, 128, 256, 4096};
    const double frac[] = {0.0, 1e-9, 0.25, 0.5, 0.61803, 1.0};
    double worst = 0.0;
    for (size_t a = 0; a < sizeof Ns / sizeof Ns[0]; a++) {
        wg_sim s;
        char why[256];
        wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, Ns[a]};
        ASSERT_EQ_INT(wg_sim_init(&s, &p, &cfg, why, sizeof why), WG_OK);
        const double om = p.v[WG_P_OMEGA], h = wg_sim_step_tau(&s);
        for (int k = 0; k < Ns[a]; k++) {
            double psi0 = 2 * M_PI * k / Ns[a];
            phase plain = {psi0, om, 0.0, INFINITY, om};
            phase ramp = {psi0, om, 0.02, 0.4 * h, om + 0.02 * 0.4 * h};
            const phase *ph[2] = {&plain, &ramp};
            for (int r = 0; r < 2; r++)
                for (size_t f = 0; f < sizeof frac / sizeof frac[0]; f++) {
                    wg_exc x, y = ct_exc_rot(&s, ph[r], cos(psi0), sin(psi0), frac[f] * h);
                    ct_exc_at(&s, ph[r], frac[f] * h, &x);
                    const double xs[4] = {x.kp, x.te, x.dte, x.fx};
                    const double ys[4] = {y.kp, y.te, y.dte, y.fx};
                    for (int j = 0; j < 4; j++) /* libm's own: psi rounded to 9e-16 */
                        worst = fmax(worst, fabs(xs[j] - ys[j]) / (1 + fabs(xs[j])));
                }
        }
        wg_sim_fini(&s);
    }
    /* a Taylor term wrong or missing is >= 1e-13 off; the two round apart */
    printf("  largest difference from the libm evaluation: %.2e x (1 + |value|)\n", worst);
    ASSERT_TRUE(worst > 0.0 && worst < 2e-15);
}

/* The split step finds the contacts that left their zones from the bounds
 * ct_set_lock keeps (ct_left): a contact's bit must be set exactly where
 * ct_zone puts its coordinate in another zone, or the coordinate is NaN,
 * for every zone and threshold (0 too: a smooth contact), at the bounds,
 * the doubles beside them, signed zeros, denormals and infinities. */
static void test_zone_bounds_mask(void)
{
    wg_params p;
    wg_params_default(&p);
    wg_sim s;
    char why[256];
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, 128};
    ASSERT_EQ_INT(wg_sim_init(&s, &p, &cfg, why, sizeof why), WG_OK);
    const double cs[] = {0.0, 4.9e-324, 1e-300, 0.05, 1.0, 3.5};
    unsigned seed = 12345;
    long checked = 0, set = 0;
    for (size_t a = 0; a < sizeof cs / sizeof cs[0]; a++)
        for (size_t bj = 0; bj < sizeof cs / sizeof cs[0]; bj++)
            for (int pat = 0; pat < 3; pat++) {
                s.p.v[WG_P_B] = cs[a];
                s.p.v[WG_P_B_J] = cs[bj];
                for (int j = 0; j < WG_NCONTACT; j++) { /* zones -1, 0, 1 in turn */
                    s.core->zone[j] = (j + pat) % 3 - 1;
                    ct_set_lock(&s, j, s.core->zone[j]);
                }
                for (int j = 0; j < WG_NCONTACT; j++) {
                    const double c = ct_threshold(&s, j);
                    double probe[24] = {0.0, -0.0, c, -c, nextafter(c, INFINITY),
                                        nextafter(c, -INFINITY), nextafter(-c, INFINITY),
                                        nextafter(-c, -INFINITY), 2 * c + 1, -2 * c - 1,
                                        INFINITY, -INFINITY, NAN, 4.9e-324, -4.9e-324};
                    for (int r = 15; r < 24; r++) /* around the bounds, c's scale */
                        probe[r] = (2.0 * rand_r(&seed) / RAND_MAX - 1.0) * (2 * c + 1e-300);
                    for (int r = 0; r < 24; r++) {
                        double q[WG_NCONTACT];
                        for (int i = 0; i < WG_NCONTACT; i++)
                            q[i] = i == j ? probe[r] : 0.5 * c; /* the others: bits not checked */
                        const unsigned m = ct_left(&s, q, WG_NCONTACT);
                        const int left = ct_zone(q[j], c) != s.core->zone[j] || isnan(q[j]);
                        ASSERT_EQ_INT((int)((m >> j) & 1u), left);
                        checked++;
                        set += left;
                    }
                }
            }
    printf("  %ld coordinates checked against ct_zone, %ld outside their zone\n", checked, set);
    ASSERT_TRUE(set > checked / 4 && set < checked);
    wg_sim_fini(&s);
}

TEST_MAIN(TEST(test_deadzone), TEST(test_model_names), TEST(test_rhs_hand_computed),
          TEST(test_kernels_match_reference),
          TEST(test_stiffness_symmetry), TEST(test_printed_drifts_consistent_settles),
          TEST(test_equilibrium_is_static), TEST(test_stability_limit),
          TEST(test_stability_limit_methods), TEST(test_split_excitation_by_rotation),
          TEST(test_zone_bounds_mask))

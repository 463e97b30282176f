/* The period-n map and its variational monodromy (wg_shoot.h):
 *   - linear case (b = b_j = 0, k_a = 0): the Newton orbit is the exact
 *     frequency response and the multipliers are exp(lambda_i T) of the
 *     system matrix, both to RK4's error, which falls ~16x per halving;
 *   - impacting orbits: the monodromy against central finite differences of
 *     the very map (to the differences' own error when the crossings are
 *     single; to the discretisation error when a body's three bearing axes
 *     cross together), the ODE's saltation is the identity, det M equals
 *     exp(trace(A) T) (Liouville: damping acts in every zone);
 *   - the refined orbit is a fixed point of wg_sim_run itself;
 *   - what is refused. */
#include "test_sim.h"
#include "wormgear/wg_regime.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_shoot.h"
#include "test_linear.h"

enum { NS = 14 };

static wg_params scene(const char *name)
{
    wg_scene sc;
    char why[256];
    int rc = wg_scene_open(&sc, name, why, sizeof why);
    if (rc)
        fprintf(stderr, "%s\n", why);
    ASSERT_EQ_INT(rc, WG_OK);
    return sc.p;
}

/* A sim at omega settled on its attractor after `periods` periods. */
static wg_sim settled(const wg_params *p0, double omega, int N, int periods)
{
    wg_params p = *p0;
    p.v[WG_P_OMEGA] = omega;
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, N);
    wg_sim_run(&s, (uint64_t)periods * (uint64_t)N, NULL, NULL);
    return s;
}

/* Refine the period-n orbit through the sim's state; x gets it. */
static void refine(wg_sim *s, int n, double *x, wg_orbit *o)
{
    double res;
    memcpy(x, s->y, sizeof(double) * NS);
    ASSERT_EQ_INT(wg_orbit_refine(s, n, x, 1e-12, 12, &res, o), WG_OK);
    ASSERT_TRUE(res <= 1e-12);
}

/* Largest distance from an exact multiplier exp(lambda T) to the nearest
 * computed one, relative to max(|mu|, 1e-3). */
static double multiplier_error(const wg_params *p, const double *wr, const double *wi)
{
    double A[NS * NS], b0[NS], lr[NS], li[NS], worst = 0.0;
    double complex B[NS];
    linear_system(p, A, b0, B);
    ASSERT_EQ_INT(wg_eig(NS, A, lr, li), WG_OK);
    double T = 2 * M_PI / p->v[WG_P_OMEGA];
    for (int i = 0; i < NS; i++) {
        double complex mu = cexp((lr[i] + I * li[i]) * T);
        double best = INFINITY;
        for (int j = 0; j < NS; j++)
            best = fmin(best, cabs(mu - (wr[j] + I * wi[j])));
        worst = fmax(worst, best / fmax(cabs(mu), 1e-3));
    }
    return worst;
}

static void test_linear_case_is_exact(void)
{
    wg_params p = scene("table3");
    p.v[WG_P_B] = p.v[WG_P_B_J] = p.v[WG_P_K_A] = 0.0;
    double err[2], merr[2], y[NS], x[NS], wr[NS], wi[NS];
    wg_orbit *o = malloc(sizeof *o);
    for (int k = 0; k < 2; k++) {
        int N = 256 << k;
        wg_sim s = settled(&p, 0.9, N, 50);
        refine(&s, 1, x, o);
        ASSERT_EQ_INT(o->crossings, 0);
        p.v[WG_P_OMEGA] = 0.9;
        exact_response(&p, y);
        err[k] = 0.0;
        for (int i = 0; i < NS; i++)
            err[k] = fmax(err[k], fabs(x[i] - y[i]));
        ASSERT_EQ_INT(wg_orbit_floquet(o, wr, wi), WG_OK);
        merr[k] = multiplier_error(&p, wr, wi);
        printf("  linear, N = %d: |orbit - exact| %.2e, multipliers vs exp(lambda T) %.2e\n", N,
               err[k], merr[k]);
        wg_sim_fini(&s);
    }
    ASSERT_TRUE(err[0] < 1e-6 && merr[0] < 2e-4);
    ASSERT_TRUE(err[1] < err[0] / 10 && merr[1] < merr[0] / 10); /* RK4: ~16x */
    free(o);
}

/* ---- impacting orbits ----------------------------------------------------------- */

/* Central finite differences of P^n at x (eps scaled by max(1, |x_j|)). */
static void fd_monodromy(wg_sim *s, int n, const double *x, double eps, double *J)
{
    wg_simmap sm = {s, n, NULL, NULL};
    double xp[NS], xm[NS];
    for (int j = 0; j < NS; j++) {
        double hj = eps * fmax(1.0, fabs(x[j]));
        memcpy(xp, x, sizeof xp);
        memcpy(xm, x, sizeof xm);
        xp[j] += hj;
        xm[j] -= hj;
        wg_simmap_step(&sm, xp);
        wg_simmap_step(&sm, xm);
        for (int i = 0; i < NS; i++)
            J[i * NS + j] = (xp[i] - xm[i]) / (2 * hj);
    }
}

static double maxdiff(const double *a, const double *b, int n)
{
    double d = 0.0;
    for (int i = 0; i < n; i++)
        d = fmax(d, fabs(a[i] - b[i]));
    return d;
}

/* |M_map - M_fd| at one orbit (and, into *flow, |M_flow - M_map|). */
static double fd_gap(const wg_params *p, double omega, int N, wg_orbit *o, double *flow)
{
    wg_sim s = settled(p, omega, N, 400);
    double x[NS], J[NS * NS], Mmap[NS * NS];
    refine(&s, 1, x, o);
    memcpy(Mmap, o->M, sizeof Mmap);
    ASSERT_TRUE(o->crossings >= 2);
    ASSERT_TRUE(o->salt_ode < 1e-9); /* the ODE's saltation: the identity */
    fd_monodromy(&s, 1, x, 1e-6, J);
    double d = maxdiff(Mmap, J, NS * NS);
    ASSERT_EQ_INT(wg_orbit_map(&s, 1, WG_MONODROMY_FLOW, x, o), WG_OK);
    *flow = maxdiff(Mmap, o->M, NS * NS);
    wg_sim_fini(&s);
    return d;
}

static void test_monodromy_against_finite_differences(void)
{
    wg_orbit *o = malloc(sizeof *o);
    double flow;
    /* mesh impacts only (b_j = 0): every crossing single */
    wg_params p = scene("table3");
    p.v[WG_P_B_J] = 0.0;
    double d = fd_gap(&p, 0.85, 256, o, &flow);
    printf("  mesh impacts, N = 256: |M - M_fd| %.2e (%ld crossings), |M_flow - M| %.2e\n", d,
           o->crossings, flow);
    ASSERT_TRUE(d < 2e-8);
    ASSERT_TRUE(flow > 10 * d); /* the map's saltation matters at this level */
    /* table3: the bearings' three axes of a body cross at one instant */
    p = scene("table3");
    double dd[2], ff[2];
    for (int k = 0; k < 2; k++) {
        dd[k] = fd_gap(&p, 0.85, 256 << k, o, &ff[k]);
        printf("  table3, N = %d: |M - M_fd| %.2e (%ld crossings), |M_flow - M| %.2e\n",
               256 << k, dd[k], o->crossings, ff[k]);
    }
    /* Both gaps fall from N = 256 to 512, then sit at 6e-7 .. 1.4e-6 at N =
     * 1024 and 2048 (measured, with false position's crossings and with
     * Newton's): a floor, not truncation error. |M - M_fd| fell 23x from 256
     * to 512 with false position and 2.7x with Newton (3.6e-7 at 256, 15x
     * below false position's), so it has a bound at each N, not a ratio. */
    ASSERT_TRUE(dd[0] < 2e-5 && dd[1] < 1e-6);
    ASSERT_TRUE(ff[1] < ff[0] / 8);
    free(o);
}

/* Liouville: damping acts in every zone, so trace(A) is the same constant
 * everywhere and det M = exp(trace(A) n T) on any orbit, impacts or not. */
static void test_determinant_is_liouville(void)
{
    wg_params p = scene("table3");
    wg_orbit *o = malloc(sizeof *o);
    double rel[2];
    double tr = -2 * p.v[WG_P_XI_G];
    for (int i = 0; i < 6; i++)
        tr -= 2 * p.v[WG_P_XI1X + i];
    double cc = p.v[WG_P_A1] * p.v[WG_P_A1] + p.v[WG_P_A2] * p.v[WG_P_A2] +
                p.v[WG_P_A3] * p.v[WG_P_A3];
    tr -= 2 * p.v[WG_P_XI_P] * (1 + (p.v[WG_P_MU1] + p.v[WG_P_MU2]) * cc);
    for (int k = 0; k < 2; k++) {
        int N = 256 << k;
        wg_sim s = settled(&p, 1.21, N, 600);
        double x[NS], wr[NS], wi[NS];
        refine(&s, 2, x, o); /* the period-2 orbit of the cascade */
        ASSERT_EQ_INT(wg_orbit_floquet(o, wr, wi), WG_OK);
        double complex det = 1.0;
        for (int i = 0; i < NS; i++)
            det *= wr[i] + I * wi[i];
        rel[k] = fabs(creal(det) / exp(tr * 2 * 2 * M_PI / 1.21) - 1.0);
        printf("  period 2 at 1.21, N = %d: det M / exp(tr A T) - 1 = %.2e (%ld crossings)\n", N,
               rel[k], o->crossings);
        ASSERT_TRUE(o->crossings > 10);
        wg_sim_fini(&s);
    }
    ASSERT_TRUE(rel[0] < 1e-3 && rel[1] < rel[0] / 10);
    free(o);
}

static void test_orbit_is_a_fixed_point_of_the_sim(void)
{
    wg_params p = scene("table3");
    wg_orbit *o = malloc(sizeof *o);
    wg_sim s = settled(&p, 0.85, 256, 400);
    double x[NS];
    refine(&s, 1, x, o);
    wg_sim_set_state(&s, x, 0, 0.0);
    ASSERT_EQ_INT(wg_sim_run(&s, 256, NULL, NULL), WG_OK);
    ASSERT_TRUE(maxdiff(s.y, o->y, NS) == 0.0); /* the very map */
    ASSERT_TRUE(maxdiff(s.y, x, NS) <= 1e-12);
    ASSERT_TRUE(o->qmin[WG_C_MESH] < p.v[WG_P_B]); /* it impacts */
    ASSERT_NEAR(o->xnsec[0], x[6] + p.v[WG_P_A1] * (x[0] - x[3]) + p.v[WG_P_A2] * (x[1] - x[4]) -
                                 p.v[WG_P_A3] * (x[2] - x[5]) - p.v[WG_P_E_M] * cos(p.v[WG_P_PHI2]),
                1e-12);
    wg_sim_fini(&s);
    free(o);
}

static void test_torsional_is_two_dimensional(void)
{
    wg_params p = scene("torsional");
    wg_orbit *o = malloc(sizeof *o);
    wg_sim s = settled(&p, 0.8, 256, 300);
    double x[NS], wr[2], wi[2];
    refine(&s, 1, x, o);
    ASSERT_EQ_INT(o->dim, 2);
    ASSERT_TRUE(o->idx[0] == 6 && o->idx[1] == 13);
    ASSERT_EQ_INT(wg_orbit_floquet(o, wr, wi), WG_OK);
    double det = wr[0] * wr[1] - wi[0] * wi[1]; /* a conjugate pair or two reals */
    ASSERT_NEAR(det, exp(-2 * p.v[WG_P_XI_P] * 2 * M_PI / 0.8), 1e-6);
    wg_sim_fini(&s);
    free(o);
}

static void test_refused(void)
{
    wg_params p = scene("table3");
    wg_orbit *o = malloc(sizeof *o);
    double x[WG_NSTATE_MAX] = {0};
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4, 64);
    ASSERT_EQ_INT(wg_orbit_map(&s, 1, WG_MONODROMY_MAP, s.y, o), WG_EUNSUPPORTED);
    wg_sim_fini(&s);
    s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, 64);
    ASSERT_EQ_INT(wg_orbit_map(&s, 0, WG_MONODROMY_MAP, s.y, o), WG_EINVAL);
    ASSERT_EQ_INT(wg_orbit_map(&s, WG_SHOOT_NMAX + 1, WG_MONODROMY_MAP, s.y, o), WG_EINVAL);
    ASSERT_EQ_INT(wg_orbit_map(&s, 1, 7, s.y, o), WG_EINVAL);
    x[6] = 1e12; /* blows up */
    ASSERT_EQ_INT(wg_orbit_map(&s, 1, WG_MONODROMY_MAP, x, o), WG_ENONFINITE);
    wg_sim_fini(&s);
    wg_sim_config cfg = {WG_MODEL_PRINTED, WG_STEPPER_RK4, 128};
    char why[256];
    ASSERT_EQ_INT(wg_sim_init(&s, &p, &cfg, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_orbit_map(&s, 1, WG_MONODROMY_MAP, s.y, o), WG_EUNSUPPORTED);
    wg_sim_fini(&s);
    free(o);
}

TEST_MAIN(TEST(test_linear_case_is_exact), TEST(test_monodromy_against_finite_differences),
          TEST(test_determinant_is_liouville), TEST(test_orbit_is_a_fixed_point_of_the_sim),
          TEST(test_torsional_is_two_dimensional), TEST(test_refused))

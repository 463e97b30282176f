/* test_ramp.c - ramps through the command path: omega on the ramp line,
 * a section every N steps, no x_n jump; refused ramps change nothing. */
#include "fixture.h"

static double max_jump(int from, int to)
{
    double m = 0;
    for (int i = from + 1; i < to; i++)
        m = fmax(m, fabs(F.xn[i] - F.xn[i - 1]));
    return m;
}

/* omega follows the ramp line, phase stays continuous (a section every N
 * steps), x_n has no jump beyond what omega itself explains. */
static void test_ramp_continuity(void)
{
    wgd *d = setup(128);
    run(d, 128 * 200);
    int a = F.nsamples;
    double tau0 = d->sim.tau, dur = 1500;
    ASSERT_EQ_INT(ramp(d, "omega", 0, 0, 2.0, dur, "tau"), WG_OK);
    ASSERT_STR(F.params_reason, "ramp");
    int npc0 = F.npc;
    run(d, 128 * 700);
    int b = F.nsamples;
    int end = a;
    double worst = 0;
    for (int i = a; i < b; i++) {
        double el = F.tau[i] - tau0;
        if (el <= dur) {
            worst = fmax(worst, fabs(F.omega[i] - (1.0 + el / dur)));
            end = i;
        } else {
            ASSERT_NEAR(F.omega[i], 2.0, 0);
        }
    }
    ASSERT_NEAR(worst, 0.0, 1e-9);
    ASSERT_TRUE(end > a + 1000 && end < b - 1000);
    ASSERT_EQ_INT(F.pc_gaps, 0);
    ASSERT_EQ_INT(F.npc - npc0, 700); /* one section per N steps, also while ramping */
    ASSERT_EQ_INT(d->sim.k, 0);
    double before = max_jump(a - 2000, a), during = max_jump(a, end), after = max_jump(end, b);
    ASSERT_TRUE(during <= 1.5 * fmax(before, after));
    ASSERT_STR(F.params_reason, "ramp-end");
    ASSERT_EQ_INT(d->sim.ramp.active, 0);
    teardown(d);
}

/* A ramp whose jump or end is refused leaves parameters and the active
 * ramp exactly as they were. */
static void test_ramp_refused_atomic(void)
{
    wgd *d = setup(16);
    ASSERT_EQ_INT(ramp(d, "omega", 0, 0, 1.5, 10000, "tau"), WG_OK);
    run(d, 2000);
    wg_params p0 = d->sim.p;
    wg_ramp r0 = d->sim.ramp;
    ASSERT_EQ_INT(ramp(d, "omega", 1, 1.2, 0.05, 100, "tau"), WG_ESTABILITY); /* end unstable */
    ASSERT_TRUE(memcmp(&p0, &d->sim.p, sizeof p0) == 0);
    ASSERT_TRUE(memcmp(&r0, &d->sim.ramp, sizeof r0) == 0);
    ASSERT_EQ_INT(ramp(d, "omega", 1, 0.05, 1.0, 100, "tau"), WG_ESTABILITY); /* jump unstable */
    ASSERT_TRUE(memcmp(&p0, &d->sim.p, sizeof p0) == 0);
    ASSERT_EQ_INT(ramp(d, "omega", 0, 0, 1.0, -5, "tau"), WG_ERANGE);
    ASSERT_EQ_INT(ramp(d, "omega", 0, 0, 1.0, 5, "hours"), WG_EINVAL);
    ASSERT_EQ_INT(ramp(d, "a1", 0, 0, 0.3, 5, "s"), WG_EINVAL);
    ASSERT_EQ_INT(ramp(d, "omega", 0, 0, NAN, 5, "s"), WG_ERANGE);
    ASSERT_TRUE(memcmp(&r0, &d->sim.ramp, sizeof r0) == 0);
    /* seconds are simulated physical seconds: tau = s * omega_n */
    ASSERT_EQ_INT(ramp(d, "xi_p", 0, 0, 0.12, 0.01, "s"), WG_OK);
    ASSERT_NEAR(d->sim.ramp.dur, 0.01 * d->scene.scale.omega_n_rad_s, 1e-9);
    teardown(d);
}

/* Issue 10, defect 1: a ramp naming two or more parameters once wrote
 * every id into a single int on the stack (ASan: stack-buffer-overflow).
 * It is refused, names what is allowed, and changes nothing. */
static void test_ramp_many_names(void)
{
    wgd *d = setup(128);
    static char *names[WG_NPARAM + 2];
    static double values[WG_NPARAM + 2];
    for (int i = 0; i < WG_NPARAM + 2; i++) {
        names[i] = (char *)wg_param_info_get(i % WG_NPARAM)->name;
        values[i] = wg_param_info_get(i % WG_NPARAM)->def;
    }
    wg_params p0 = d->sim.p;
    int counts[] = {2, 3, WG_NPARAM, WG_NPARAM + 1, 0};
    for (unsigned k = 0; k < sizeof counts / sizeof counts[0]; k++) {
        wormgear_cmd_t c = {.op = "ramp", .nparams = counts[k], .names = names,
                            .values = values, .duration = 5, .unit = "tau"};
        ASSERT_EQ_INT(send(d, &c), WG_EINVAL);
        ASSERT_CONTAINS(F.message, "ramp takes exactly one parameter");
        ASSERT_TRUE(memcmp(&p0, &d->sim.p, sizeof p0) == 0);
        ASSERT_EQ_INT(d->sim.ramp.active, 0);
    }
    teardown(d);
}

/* A ramp that replaces a running one says so, and what became of it. */
static void test_ramp_replaces(void)
{
    wgd *d = setup(64);
    ASSERT_EQ_INT(ramp(d, "omega", 0, 0, 1.5, 1000, "tau"), WG_OK);
    ASSERT_TRUE(strstr(F.message, "replaces") == NULL);
    run(d, 64 * 10);
    ASSERT_EQ_INT(ramp(d, "omega", 0, 0, 0.8, 500, "tau"), WG_OK);
    ASSERT_CONTAINS(F.message, "it replaces the running ramp of omega to 1.5");
    ASSERT_CONTAINS(F.message, "from where that ramp had taken it");
    run(d, 64 * 10);
    double phi = d->sim.p.v[WG_P_PHI];
    ASSERT_EQ_INT(ramp(d, "phi", 0, 0, phi + 0.1, 500, "tau"), WG_OK);
    ASSERT_CONTAINS(F.message, "it replaces the running ramp of omega to 0.8");
    ASSERT_CONTAINS(F.message, "omega stays at");
    double w = d->sim.p.v[WG_P_OMEGA];
    run(d, 64 * 10);
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], w, 0); /* the replaced ramp really stopped */
    teardown(d);
}

TEST_MAIN(TEST(test_ramp_continuity), TEST(test_ramp_refused_atomic), TEST(test_ramp_many_names),
          TEST(test_ramp_replaces))

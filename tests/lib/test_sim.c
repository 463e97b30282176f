/* The integration driver: sections and periods, kernel choice (skip what a
 * scene does not need), torsional path = full path with vanishing mass
 * ratios, blow-up handling, atomic parameter changes, determinism, motion
 * classes. */
#include "test.h"
#include "test_sim.h"
#include "wormgear/wg_sim.h"
#include "wormgear/wg_status.h"

typedef struct rec {
    int nsec, nev;
    double tau[64], xn[64];
    int motion[64], impacts[64];
    uint64_t period[64];
} rec;

static void on_sec(void *ctx, const wg_section *s)
{
    rec *r = ctx;
    if (r->nsec < 64) {
        r->tau[r->nsec] = s->tau;
        r->xn[r->nsec] = s->out.xn;
        r->motion[r->nsec] = s->stats.motion;
        r->impacts[r->nsec] = s->stats.impacts;
        r->period[r->nsec] = s->stats.period;
    }
    r->nsec++;
}

static void on_ev(void *ctx, const wg_event *e)
{
    (void)e;
    ((rec *)ctx)->nev++;
}

static void test_sections_fall_on_periods(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = 1.3;
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4, 100);
    rec r = {0};
    wg_sink sink = {&r, NULL, on_sec, NULL};
    ASSERT_EQ_INT(wg_sim_run(&s, 100 * 10 + 37, &sink, NULL), WG_OK);
    ASSERT_EQ_INT(r.nsec, 10);
    ASSERT_EQ_INT(s.k, 37);
    ASSERT_EQ_INT(s.period, 10);
    for (int i = 0; i < 10; i++) {
        ASSERT_NEAR(r.tau[i], (i + 1) * 2 * M_PI / 1.3, 1e-11);
        ASSERT_EQ_INT(r.period[i], i);
    }
    ASSERT_NEAR(wg_sim_psi(&s), 2 * M_PI * 37 / 100, 1e-15);
    wg_sim_fini(&s);
}

static void test_kernel_choice_skips_terms(void)
{
    wg_params p;
    wg_params_default(&p);
    char name[64];
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, 128);
    ASSERT_STR(wg_sim_kernel_name(&s, name, sizeof name), "full+bj+b+ka+em+locked");
    wg_sim_fini(&s);
    p.v[WG_P_K_A] = p.v[WG_P_E_M] = p.v[WG_P_B_J] = 0;
    s = test_sim_make(&p, WG_STEPPER_RK4, 128);
    ASSERT_STR(wg_sim_kernel_name(&s, name, sizeof name), "full+b");
    /* changing a parameter re-selects the kernel, outside the step loop */
    wg_params q = p;
    q.v[WG_P_K_A] = 0.2;
    char why[300];
    ASSERT_EQ_INT(wg_sim_set_params(&s, &q, why, sizeof why), WG_OK);
    ASSERT_STR(wg_sim_kernel_name(&s, name, sizeof name), "full+b+ka");
    wg_sim_fini(&s);
    p.v[WG_P_MU1] = p.v[WG_P_MU2] = 0;
    p.v[WG_P_B_J] = 1;
    s = test_sim_make(&p, WG_STEPPER_RK4, 128);
    ASSERT_STR(wg_sim_kernel_name(&s, name, sizeof name), "torsional+b");
    wg_sim_fini(&s);
}

/* The 1-DOF torsional kernel is the limit of the full one as mu -> 0. */
static void test_torsional_is_full_limit(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = 0.8;
    rec r[2] = {{0}, {0}};
    for (int k = 0; k < 2; k++) {
        p.v[WG_P_MU1] = p.v[WG_P_MU2] = k ? 0.0 : 1e-9;
        wg_sim s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, 256);
        char name[64];
        ASSERT_TRUE(strncmp(wg_sim_kernel_name(&s, name, sizeof name), k ? "torsional" : "full",
                            k ? 9 : 4) == 0);
        wg_sink sink = {&r[k], NULL, on_sec, NULL};
        ASSERT_EQ_INT(wg_sim_run(&s, 256 * 40, &sink, NULL), WG_OK);
        wg_sim_fini(&s);
    }
    double worst = 0;
    for (int i = 0; i < 40; i++)
        worst = fmax(worst, fabs(r[0].xn[i] - r[1].xn[i]));
    ASSERT_TRUE(worst < 1e-6);
}

static void test_blowup_is_caught_state_kept(void)
{
    wg_params p;
    wg_params_default(&p);
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, 128);
    ASSERT_EQ_INT(wg_sim_run(&s, 300, NULL, NULL), WG_OK);
    double y[16];
    memcpy(y, s.y, sizeof y);
    y[3] = NAN;
    wg_sim_set_state(&s, y, s.k, s.tau);
    uint64_t steps = s.steps, done = 99;
    double tau = s.tau;
    ASSERT_EQ_INT(wg_sim_run(&s, 10, NULL, &done), WG_ENONFINITE);
    ASSERT_EQ_INT(done, 0);
    ASSERT_EQ_INT(s.steps, steps);
    ASSERT_NEAR(s.tau, tau, 0);
    ASSERT_TRUE(isnan(s.y[3]) && s.y[0] == y[0]); /* the failed step was not applied */
    /* absurd but finite values are caught the same way */
    y[3] = 1e12;
    wg_sim_set_state(&s, y, s.k, s.tau);
    ASSERT_EQ_INT(wg_sim_run(&s, 10, NULL, &done), WG_ENONFINITE);
    ASSERT_NEAR(s.y[3], 1e12, 0);
    /* a good state runs again */
    y[3] = 0;
    wg_sim_set_state(&s, y, s.k, s.tau);
    ASSERT_EQ_INT(wg_sim_run(&s, 10, NULL, &done), WG_OK);
    wg_sim_fini(&s);
}

static void test_set_params_is_atomic(void)
{
    wg_params p;
    wg_params_default(&p);
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4, 128);
    wg_sim_run(&s, 200, NULL, NULL);
    wg_sim before = s;
    wg_params q = s.p;
    q.v[WG_P_XI_P] = 0.1;
    q.v[WG_P_K_A] = 3.0; /* out of range: nothing applies */
    char why[300];
    ASSERT_EQ_INT(wg_sim_set_params(&s, &q, why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "k_a = 3 out of range [0, 0.95]");
    ASSERT_TRUE(memcmp(&before.p, &s.p, sizeof s.p) == 0);
    ASSERT_TRUE(memcmp(before.y, s.y, sizeof s.y) == 0);
    q = s.p;
    q.v[WG_P_OMEGA] = 0.05; /* needs more than 128 steps per period */
    ASSERT_EQ_INT(wg_sim_set_params(&s, &q, why, sizeof why), WG_ESTABILITY);
    ASSERT_CONTAINS(why, "need N >= ");
    ASSERT_NEAR(s.p.v[WG_P_OMEGA], 1.0, 0);
    /* ramps: geometry refused, bad duration refused, target range checked */
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_A1, NULL, 0.3, 10, why, sizeof why), WG_EINVAL);
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_OMEGA, NULL, 1.5, 0, why, sizeof why), WG_ERANGE);
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_OMEGA, NULL, 12, 10, why, sizeof why), WG_ERANGE);
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_OMEGA, NULL, 0.05, 10, why, sizeof why), WG_ESTABILITY);
    ASSERT_TRUE(!s.ramp.active);
    /* a ramp of a non-frequency parameter ends exactly on target */
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_XI_P, NULL, 0.12, 50, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(&s, 128 * 20, NULL, NULL), WG_OK);
    ASSERT_TRUE(!s.ramp.active);
    ASSERT_NEAR(s.p.v[WG_P_XI_P], 0.12, 0);
    wg_sim_fini(&s);
}

/* A split step keeps only the cosine and sine of each step's start phase
 * from earlier periods (ct_psi0) and takes the excitation's terms from the
 * parameters. After a change of any excitation input, or of a damping (no
 * new table), the next split steps use the new values: the run continues
 * exactly as a new sim set up with them at the same state. */
static void test_excitation_change_seen(void)
{
    static const struct { int id; double v; } change[] = {
        {WG_P_F_E, 0.1}, {WG_P_PHI, 1.0}, {WG_P_K_A, 0.2}, {WG_P_E_M, 0.25},
        {WG_P_OMEGA, 0.72}, {WG_P_XI_P, 0.09}, {WG_P_PHI1, 0.5}, {WG_P_PHI2, 2.0},
        {WG_P_F_M, 0.3}};
    char why[300];
    for (unsigned c = 0; c < sizeof change / sizeof change[0]; c++) {
        wg_params p;
        wg_params_default(&p);
        p.v[WG_P_OMEGA] = 0.7; /* an impact every period */
        wg_sim a = test_sim_make(&p, WG_STEPPER_RK4_EVENT, 128);
        ASSERT_EQ_INT(wg_sim_run(&a, 128 * 20, NULL, NULL), WG_OK);
        ASSERT_TRUE(a.nsplit >= 20);
        wg_params q = a.p;
        q.v[change[c].id] = change[c].v;
        ASSERT_EQ_INT(wg_sim_set_params(&a, &q, why, sizeof why), WG_OK);
        wg_sim b = test_sim_make(&q, WG_STEPPER_RK4_EVENT, 128);
        wg_sim_set_state(&b, a.y, a.k, a.tau);
        uint64_t na = a.nsplit;
        ASSERT_EQ_INT(wg_sim_run(&a, 128 * 20, NULL, NULL), WG_OK);
        ASSERT_EQ_INT(wg_sim_run(&b, 128 * 20, NULL, NULL), WG_OK);
        ASSERT_TRUE(a.nsplit - na == b.nsplit && b.nsplit >= 20);
        if (memcmp(a.y, b.y, sizeof a.y) != 0)
            fprintf(stderr, "after %s = %g: the runs differ\n", wg_param_info_get(change[c].id)->name,
                    change[c].v);
        ASSERT_TRUE(memcmp(a.y, b.y, sizeof a.y) == 0);
        wg_sim_fini(&a);
        wg_sim_fini(&b);
    }
}

/* wg_sim_outputs takes the excitation from the table when no ramp runs:
 * at every phase index, in and after a ramp of omega, and after the table
 * is built again (its sines and cosines kept for an omega or an amplitude,
 * computed again for a phase), it gives exactly what wg_exc_eval at
 * wg_sim_psi and wg_outputs_eval give. */
static void test_outputs_from_table_exact(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = 0.7;
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, 128);
    char why[300];
    int ramped = 0;
    static const struct { int at, id; double v; } set[] = {
        {3 * 128, WG_P_PHI2, 1.0}, {4 * 128, WG_P_E_M, 0.3}, {5 * 128, WG_P_OMEGA, 0.8},
        {6 * 128, WG_P_PHI1, 0.4}, {7 * 128, WG_P_K_A, 0.25}, {8 * 128, WG_P_PHI, 2.0},
        {9 * 128, WG_P_OMEGA, 0.7}};
    for (int i = 0; i < 10 * 128 + 5; i++) {
        if (i == 128)
            ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_OMEGA, NULL, 0.75, 20.0, why, sizeof why), WG_OK);
        for (unsigned c = 0; c < sizeof set / sizeof set[0]; c++)
            if (i == set[c].at) {
                wg_params q = s.p;
                q.v[set[c].id] = set[c].v;
                ASSERT_EQ_INT(wg_sim_set_params(&s, &q, why, sizeof why), WG_OK);
            }
        ramped |= s.ramp.active;
        wg_outputs a, b;
        wg_exc e;
        wg_sim_outputs(&s, &a);
        wg_exc_eval(&s.p, wg_sim_psi(&s), s.p.v[WG_P_OMEGA], &e);
        wg_outputs_eval(WG_MODEL_CONSISTENT, &s.p, &e, s.y, &b);
        ASSERT_TRUE(memcmp(&a, &b, sizeof a) == 0);
        ASSERT_EQ_INT(wg_sim_run(&s, 1 + (uint64_t)(i % 3), NULL, NULL), WG_OK);
    }
    ASSERT_TRUE(ramped && !s.ramp.active); /* both paths were taken */
    wg_sim_fini(&s);
}

/* A ramp is accepted only if its duration is in the documented range and
 * every value along it is finite and in range: a denormal duration must
 * never make a parameter NaN (issue 10, defect 2). Messages name the
 * limits, the end that is wrong, and print bounds that read back exactly. */
static void test_ramp_never_stores_nonfinite(void)
{
    wg_params p;
    wg_params_default(&p);
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, 128);
    char why[300];
    static const double bad[] = {4.94e-324, 1e-310, 1e-300, 0, -1, 1e300, INFINITY, NAN, 2e15};
    for (unsigned i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        for (int id = 0; id < WG_NPARAM; id++) {
            if (!(wg_param_info_get(id)->flags & WG_PF_RAMP))
                continue;
            double to = wg_param_info_get(id)->max;
            ASSERT_EQ_INT(wg_sim_ramp(&s, id, NULL, to, bad[i], why, sizeof why), WG_ERANGE);
            ASSERT_CONTAINS(why, "[1e-06, 1e+15] tau");
        }
    }
    ASSERT_TRUE(!s.ramp.active);
    /* at the shortest allowed duration the parameters stay finite and in range */
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_XI_P, NULL, 2.0, 1e-6, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(&s, 128, NULL, NULL), WG_OK);
    ASSERT_TRUE(wg_params_check(&s.p, why, sizeof why) == WG_OK);
    ASSERT_NEAR(s.p.v[WG_P_XI_P], 2.0, 0);
    double from = 99;
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_OMEGA, &from, 1.2, 10, why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "from");
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_OMEGA, NULL, 99, 10, why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "target");
    /* a bound printed so that a value one ulp outside reads as outside */
    ASSERT_EQ_INT(wg_param_check(WG_P_PHI1, 6.2831853071795871, why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "phi1 = 6.283185307179587 out of range [-6.283185307179586, "
                         "6.283185307179586]");
    ASSERT_EQ_INT(wg_param_check(WG_P_OMEGA, 12, why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "omega = 12 out of range [0.01, 10]");
    wg_sim_fini(&s);
}

static void test_deterministic(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = 1.45;
    double y[2][16];
    rec r[2] = {{0}, {0}};
    for (int k = 0; k < 2; k++) {
        wg_sim s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, 128);
        wg_sink sink = {&r[k], NULL, on_sec, on_ev};
        ASSERT_EQ_INT(wg_sim_run(&s, 128 * 60, &sink, NULL), WG_OK);
        memcpy(y[k], s.y, sizeof y[k]);
        wg_sim_fini(&s);
    }
    ASSERT_TRUE(memcmp(y[0], y[1], sizeof y[0]) == 0);
    ASSERT_TRUE(memcmp(r[0].xn, r[1].xn, sizeof r[0].xn) == 0);
    ASSERT_EQ_INT(r[0].nev, r[1].nev);
}

static int run_class(double om, double em)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = om;
    p.v[WG_P_E_M] = em;
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, 256);
    rec r = {0};
    wg_sink sink = {&r, NULL, on_sec, NULL};
    ASSERT_EQ_INT(wg_sim_run(&s, 256 * 64, &sink, NULL), WG_OK);
    wg_sim_fini(&s);
    int worst = 0;
    for (int i = 32; i < 64; i++)
        worst = r.motion[i] > worst ? r.motion[i] : worst;
    return worst;
}

static void test_motion_classes(void)
{
    ASSERT_EQ_INT(run_class(0.3, 0.2), WG_MOTION_NO_IMPACT);
    ASSERT_EQ_INT(run_class(0.7, 0.2), WG_MOTION_SINGLE);
    ASSERT_EQ_INT(run_class(1.0, 3.0), WG_MOTION_DOUBLE); /* 15x the TE: rattle */
}

/* Zero backlash: the mesh RHS is smooth, so no step is split, and each pass
 * through x_n = 0 reports both of its boundary events at the same time. */
static void test_zero_backlash_events(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_B] = 0;
    p.v[WG_P_F_M] = 0.0;
    p.v[WG_P_B_J] = 0;
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, 128);
    rec r = {0};
    wg_sink sink = {&r, NULL, NULL, on_ev};
    ASSERT_EQ_INT(wg_sim_run(&s, 128 * 30, &sink, NULL), WG_OK);
    ASSERT_EQ_INT(s.nsplit, 0);
    ASSERT_TRUE(r.nev > 0);
    ASSERT_EQ_INT(s.nevents[WG_C_MESH][WG_EV_SEPARATION], s.nevents[WG_C_MESH][WG_EV_BACK_IMPACT]);
    wg_sim_fini(&s);
}

/* The period statistics count each bearing's impacts (either side) and its
 * largest impact speed: exactly the events the sink sees in that period. */
typedef struct bstat {
    long cur[WG_NBEARING], periods, impacts, mismatches;
    double vcur[WG_NBEARING];
} bstat;

static void on_bev(void *ctx, const wg_event *ev)
{
    bstat *b = ctx;
    int j = ev->contact - WG_C_X1;
    if (j >= 0 && (ev->kind == WG_EV_DRIVE_IMPACT || ev->kind == WG_EV_BACK_IMPACT)) {
        b->cur[j]++;
        b->vcur[j] = fmax(b->vcur[j], fabs(ev->velocity));
    }
}

static void on_bsec(void *ctx, const wg_section *sec)
{
    bstat *b = ctx;
    for (int j = 0; j < WG_NBEARING; j++) {
        b->mismatches += sec->stats.bimpacts[j] != b->cur[j] || sec->stats.bvmax[j] != b->vcur[j];
        b->impacts += b->cur[j];
        b->cur[j] = 0, b->vcur[j] = 0;
    }
    b->periods++;
}

static void test_period_bearing_stats(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = 1.2; /* xi_p 0.08: every bearing rattles */
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, 128);
    ASSERT_EQ_INT(wg_sim_run(&s, 128 * 300, NULL, NULL), WG_OK); /* whole periods */
    bstat b = {{0}, 0, 0, 0, {0}};
    wg_sink sink = {&b, NULL, on_bsec, on_bev};
    ASSERT_EQ_INT(wg_sim_run(&s, 128 * 100, &sink, NULL), WG_OK);
    ASSERT_EQ_INT(b.periods, 100);
    ASSERT_EQ_INT(b.mismatches, 0);
    ASSERT_TRUE(b.impacts >= 600); /* each of the six at least once a period */
    printf("  100 periods: %ld bearing impacts, each period's statistics equal to its events\n",
           b.impacts);
    wg_sim_fini(&s);
}

TEST_MAIN(TEST(test_sections_fall_on_periods), TEST(test_kernel_choice_skips_terms),
          TEST(test_torsional_is_full_limit), TEST(test_blowup_is_caught_state_kept),
          TEST(test_set_params_is_atomic), TEST(test_excitation_change_seen),
          TEST(test_outputs_from_table_exact),
          TEST(test_ramp_never_stores_nonfinite),
          TEST(test_deterministic), TEST(test_motion_classes),
          TEST(test_zero_backlash_events), TEST(test_period_bearing_stats))

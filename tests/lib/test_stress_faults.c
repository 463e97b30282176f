/* Injected faults. A NaN, an infinity or an absurd value forced into any
 * state component is caught at the next step: WG_ENONFINITE, no step
 * applied (counters, time, phase, contact zones and kernel coefficients as
 * before), nothing reaches the sinks; putting the previous good state back
 * continues bit-identically to a run that never faulted. Non-finite
 * parameters are refused before they reach the state. */
#include "stress.h"
#include "internal.h" /* white box: the private part of a wg_sim */

typedef struct cnt {
    int steps, secs, evs;
} cnt;

static void c_step(void *ctx, const wg_sim *s) { (void)s; ((cnt *)ctx)->steps++; }
static void c_sec(void *ctx, const wg_section *s) { (void)s; ((cnt *)ctx)->secs++; }
static void c_ev(void *ctx, const wg_event *e) { (void)e; ((cnt *)ctx)->evs++; }

enum { N = 128 };

/* table3 at omega 0.7 (impacts, bearings rattling: rk4-event splits steps),
 * advanced to step `at` from equilibrium. */
static void start(wg_sim *s, int stepper, uint64_t at)
{
    wg_params p = stress_scene("table3");
    p.v[WG_P_OMEGA] = 0.7;
    ASSERT_EQ_INT(test_sim_init(s, &p, stepper, N), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(s, at, NULL, NULL), WG_OK);
}

static void test_bad_values_caught_next_step(void)
{
    static const double bad[] = {NAN, INFINITY, -INFINITY, 1e300, -1e10};
    const uint64_t at = N * 40 + 77, more = N * 20;
    int injected = 0, identical = 0, split_drift = 0;
    for (int st = 0; st < 2; st++) {
        wg_sim ref; /* never faulted */
        start(&ref, st, at + more);
        for (int i = 0; i < 14; i++)
            for (unsigned v = 0; v < sizeof bad / sizeof bad[0]; v++) {
                wg_sim s;
                start(&s, st, at);
                double good[16];
                uint32_t k = s.k;
                double tau = s.tau;
                memcpy(good, s.y, sizeof good);
                double y[16];
                memcpy(y, good, sizeof y);
                y[i] = bad[v];
                wg_sim_set_state(&s, y, k, tau);
                wg_sim before = s;
                wg_sim_core core0 = *s.core; /* the private part, by value */
                cnt c = {0, 0, 0};
                wg_sink sink = {&c, c_step, c_sec, c_ev};
                uint64_t done = 99;
                ASSERT_EQ_INT(wg_sim_run(&s, more, &sink, &done), WG_ENONFINITE);
                ASSERT_EQ_INT(done, 0);
                ASSERT_TRUE(c.steps == 0 && c.secs == 0 && c.evs == 0);
                ASSERT_TRUE(s.steps == before.steps && s.period == before.period &&
                            s.k == before.k && s.tau == before.tau);
                ASSERT_TRUE(memcmp(s.core->zone, core0.zone, sizeof core0.zone) == 0);
                ASSERT_TRUE(memcmp(&s.core->kc, &core0.kc, sizeof core0.kc) == 0);
                ASSERT_TRUE(memcmp(s.y, y, sizeof(double) * 14) == 0); /* kept as given */
                /* the failed step's located crossings are not counted */
                split_drift += s.nsplit != before.nsplit;
                /* the caller puts the previous good state back and goes on */
                wg_sim_set_state(&s, good, k, tau);
                ASSERT_EQ_INT(wg_sim_run(&s, more, &sink, &done), WG_OK);
                ASSERT_EQ_INT(done, more);
                identical += memcmp(s.y, ref.y, sizeof(double) * 14) == 0;
                ASSERT_TRUE(stress_maxabs(s.y, 14) < 10);
                ASSERT_NEAR(stress_maxabs(s.y, 14), stress_maxabs(ref.y, 14), 1e-12);
                injected++;
                wg_sim_fini(&s);
            }
        wg_sim_fini(&ref);
    }
    printf("  %d injections (14 states x NaN, +-Inf, 1e300, -1e10 x 2 steppers): all caught at "
           "the next step; %d/%d continued bit-identically after restoring\n", injected,
           identical, injected);
    ASSERT_EQ_INT(split_drift, 0);
    ASSERT_EQ_INT(identical, injected);
}

/* At the last step of a period no section is emitted for a faulted step;
 * rigid bearings: a NaN in a bearing coordinate (which the torsional kernel
 * never reads) is zeroed by set_state, and one in s is caught. */
static void test_fault_at_section_and_torsional(void)
{
    wg_sim s;
    start(&s, WG_STEPPER_RK4_EVENT, N * 10 - 1);
    ASSERT_EQ_INT(s.k, N - 1);
    double y[16];
    memcpy(y, s.y, sizeof y);
    y[13] = NAN;
    wg_sim_set_state(&s, y, s.k, s.tau);
    cnt c = {0, 0, 0};
    wg_sink sink = {&c, c_step, c_sec, c_ev};
    ASSERT_EQ_INT(wg_sim_run(&s, 1, &sink, NULL), WG_ENONFINITE);
    ASSERT_EQ_INT(c.secs, 0);
    ASSERT_EQ_INT(s.period, 9);
    wg_sim_fini(&s);

    wg_params p = stress_scene("torsional");
    ASSERT_EQ_INT(test_sim_init(&s, &p, WG_STEPPER_RK4, N), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(&s, 1000, NULL, NULL), WG_OK);
    memcpy(y, s.y, sizeof y);
    y[0] = NAN;
    wg_sim_set_state(&s, y, s.k, s.tau);
    ASSERT_TRUE(s.y[0] == 0.0);
    ASSERT_EQ_INT(wg_sim_run(&s, 10, NULL, NULL), WG_OK);
    memcpy(y, s.y, sizeof y);
    y[6] = NAN;
    wg_sim_set_state(&s, y, s.k, s.tau);
    uint64_t done = 9;
    ASSERT_EQ_INT(wg_sim_run(&s, 10, NULL, &done), WG_ENONFINITE);
    ASSERT_EQ_INT(done, 0);
    wg_sim_fini(&s);
}

/* Mid-ramp, through the snapshot API: a NaN in a restored snapshot is
 * caught at the next step with the ramp untouched; restoring the snapshot
 * taken before continues bit-exactly like a run that never faulted (state,
 * time, counters, the ramped omega). */
static void test_fault_mid_ramp_snapshot(void)
{
    wg_params p = stress_scene("table3");
    p.v[WG_P_OMEGA] = 0.7;
    wg_sim a, b;
    char why[300];
    ASSERT_EQ_INT(test_sim_init(&a, &p, WG_STEPPER_RK4_EVENT, N), WG_OK);
    ASSERT_EQ_INT(test_sim_init(&b, &p, WG_STEPPER_RK4_EVENT, N), WG_OK);
    for (int r = 0; r < 2; r++) {
        wg_sim *s = r ? &b : &a;
        ASSERT_EQ_INT(wg_sim_run(s, N * 20, NULL, NULL), WG_OK);
        ASSERT_EQ_INT(wg_sim_ramp(s, WG_P_OMEGA, NULL, 0.9, 200.0, why, sizeof why), WG_OK);
        ASSERT_EQ_INT(wg_sim_run(s, N * 5 + 33, NULL, NULL), WG_OK);
        ASSERT_TRUE(s->ramp.active);
    }
    wg_snapshot good, bad;
    wg_sim_snapshot(&b, &good);
    bad = good;
    bad.y[9] = NAN;
    /* refused at the door, the running state untouched */
    ASSERT_EQ_INT(wg_sim_restore(&b, &bad, why, sizeof why), WG_EINVAL);
    ASSERT_CONTAINS(why, "not finite");
    ASSERT_TRUE(b.ramp.active && b.steps == good.steps && b.tau == good.tau);
    ASSERT_TRUE(memcmp(b.y, good.y, sizeof b.y) == 0);
    ASSERT_EQ_INT(wg_sim_restore(&b, &good, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(&a, N * 40, NULL, NULL), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(&b, N * 40, NULL, NULL), WG_OK);
    ASSERT_TRUE(memcmp(a.y, b.y, sizeof a.y) == 0);
    ASSERT_TRUE(a.tau == b.tau && a.steps == b.steps && a.period == b.period);
    ASSERT_TRUE(a.p.v[WG_P_OMEGA] == b.p.v[WG_P_OMEGA] && a.ramp.active == b.ramp.active);
    wg_sim_fini(&a);
    wg_sim_fini(&b);
}

/* Non-finite parameters never reach the integrator. */
static void test_nonfinite_params_refused(void)
{
    wg_sim s;
    start(&s, WG_STEPPER_RK4_EVENT, 500);
    char why[300];
    static const double bad[] = {NAN, INFINITY, -INFINITY};
    int refused = 0;
    for (int id = 0; id < WG_NPARAM; id++)
        for (int v = 0; v < 3; v++) {
            wg_sim before = s;
            wg_params q = s.p;
            q.v[id] = bad[v];
            int rc = wg_sim_set_params(&s, &q, why, sizeof why);
            ASSERT_EQ_INT(rc, WG_ERANGE);
            ASSERT_TRUE(memcmp(&s.p, &before.p, sizeof s.p) == 0);
            ASSERT_TRUE(memcmp(s.y, before.y, sizeof s.y) == 0);
            const wg_param_info *r = wg_param_info_get(id);
            if (r->flags & WG_PF_RAMP) {
                ASSERT_EQ_INT(wg_sim_ramp(&s, id, NULL, bad[v], 10.0, why, sizeof why), WG_ERANGE);
                ASSERT_TRUE(!s.ramp.active);
            }
            refused += rc == WG_ERANGE;
        }
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_XI_P, NULL, 0.1, NAN, why, sizeof why), WG_ERANGE);
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_XI_P, NULL, 0.1, INFINITY, why, sizeof why), WG_ERANGE);
    printf("  %d non-finite parameter values refused (set and ramp), state untouched\n",
           refused);
    ASSERT_EQ_INT(wg_sim_run(&s, 1000, NULL, NULL), WG_OK);
    wg_sim_fini(&s);
}

TEST_MAIN(TEST(test_bad_values_caught_next_step), TEST(test_fault_at_section_and_torsional),
          TEST(test_fault_mid_ramp_snapshot), TEST(test_nonfinite_params_refused))

/* Snapshots: wg_sim_restore validates every field exactly as the live path
 * does (parameters through wg_sim_set_params's checks, k < N, a finite
 * state, tau and its compensation term, the counters, the ramp as
 * wg_sim_ramp would accept it, the period statistics) and leaves the sim
 * unchanged when it refuses. */
#include "test.h"
#include "test_sim.h"
#include "wormgear/wg_sim.h"
#include "wormgear/wg_status.h"

#include <stdint.h>

enum { N = 128 };

/* A sim in the middle of an omega ramp, on an impacting orbit. */
static wg_sim mid_ramp(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = 1.35;
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, N);
    char why[300];
    ASSERT_EQ_INT(wg_sim_run(&s, N * 20 + 37, NULL, NULL), WG_OK);
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_OMEGA, NULL, 1.6, 2000.0, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(&s, 1001, NULL, NULL), WG_OK);
    ASSERT_TRUE(s.ramp.active);
    return s;
}

/* ---- hostile values: one mutation of a valid snapshot each ---------------- */

typedef struct hostile {
    const char *what;
    void (*mutate)(wg_snapshot *w);
    int rc;           /* the code wg_sim_restore must return */
    const char *says; /* ... and a part of its message */
} hostile;

static void m_model(wg_snapshot *w) { w->model = WG_MODEL_PRINTED; }
static void m_stepper(wg_snapshot *w) { w->stepper = WG_STEPPER_RK4; }
static void m_n(wg_snapshot *w) { w->steps_per_period = 256; }
static void m_omega(wg_snapshot *w) { w->p.v[WG_P_OMEGA] = 12; }
static void m_cosines(wg_snapshot *w) { w->p.v[WG_P_A1] = 0.5; }
static void m_stiff(wg_snapshot *w) { w->p.v[WG_P_K1X] = 1e4; }
static void m_param_nan(wg_snapshot *w) { w->p.v[WG_P_XI_P] = NAN; }
static void m_y_nan(wg_snapshot *w) { w->y[3] = NAN; }
static void m_y_huge(wg_snapshot *w) { w->y[0] = 1e10; }
static void m_k_n(wg_snapshot *w) { w->k = N; }
static void m_k_max(wg_snapshot *w) { w->k = UINT32_MAX; }
static void m_tau_huge(wg_snapshot *w) { w->tau = 1e308; }
static void m_tau_neg(wg_snapshot *w) { w->tau = -1; }
static void m_tau_nan(wg_snapshot *w) { w->tau = NAN; }
static void m_tau_c(wg_snapshot *w) { w->tau_c = 1.0; }
static void m_tau_c_nan(wg_snapshot *w) { w->tau_c = NAN; }
static void m_period(wg_snapshot *w) { w->period = w->steps + 1; }
static void m_active(wg_snapshot *w) { w->ramp.active = 7; }
static void m_ramp_id(wg_snapshot *w) { w->ramp.id = 99; }
static void m_ramp_geom(wg_snapshot *w)
{
    w->ramp = (wg_ramp){1, WG_P_A1, w->p.v[WG_P_A1], 0.3, w->tau, 100.0};
}
static void m_ramp_to(wg_snapshot *w) { w->ramp.v1 = 1000; }
static void m_ramp_from(wg_snapshot *w) { w->ramp.v0 = NAN; }
static void m_ramp_dur0(wg_snapshot *w) { w->ramp.dur = 0; }
static void m_ramp_dur_huge(wg_snapshot *w) { w->ramp.dur = 1e16; }
static void m_ramp_tau0(wg_snapshot *w) { w->ramp.tau0 = w->tau + 1; }
static void m_ramp_tau0_nan(wg_snapshot *w) { w->ramp.tau0 = NAN; }
static void m_ramp_over(wg_snapshot *w) { w->ramp.tau0 = w->tau - w->ramp.dur - 1; }
static void m_ramp_value(wg_snapshot *w) { w->p.v[WG_P_OMEGA] = 1.5; }
static void m_ramp_unstable(wg_snapshot *w)
{
    w->ramp = (wg_ramp){1, WG_P_K1X, w->p.v[WG_P_K1X], 1e4, w->tau, 100.0};
}
static void m_motion(wg_snapshot *w) { w->cur.motion = 3; }
static void m_motion_last(wg_snapshot *w) { w->last.motion = -1; }
static void m_impacts(wg_snapshot *w) { w->cur.impacts = -1; }
static void m_minmax(wg_snapshot *w) { w->last.min_xn = w->last.max_xn + 1; }
static void m_min_nan(wg_snapshot *w) { w->cur.min_xn = NAN; }
static void m_cur_period(wg_snapshot *w) { w->cur.period = w->period + 1; }

static const hostile cases[] = {
    {"another model", m_model, WG_ESTATE, "model printed"},
    {"another stepper", m_stepper, WG_ESTATE, "stepper rk4"},
    {"another N", m_n, WG_ESTATE, "N = 256"},
    {"omega = 12", m_omega, WG_ERANGE, "omega = 12 out of range [0.01, 10]"},
    {"a1 breaks the cosines", m_cosines, WG_ERANGE, "a1^2 + a2^2 + a3^2"},
    {"k1x = 1e4 at N = 128", m_stiff, WG_ESTABILITY, "need N >="},
    {"xi_p = nan", m_param_nan, WG_ERANGE, "xi_p = nan out of range"},
    {"y[3] = nan", m_y_nan, WG_EINVAL, "not finite"},
    {"y[0] = 1e10", m_y_huge, WG_EINVAL, "not finite"},
    {"k = N", m_k_n, WG_EINVAL, "k = 128 out of range [0, 128)"},
    {"k = 2^32 - 1", m_k_max, WG_EINVAL, "k = 4294967295 out of range"},
    {"tau = 1e308", m_tau_huge, WG_EINVAL, "tau = 1e+308 out of range [0, 1e+15]"},
    {"tau = -1", m_tau_neg, WG_EINVAL, "tau = -1 out of range"},
    {"tau = nan", m_tau_nan, WG_EINVAL, "tau = nan out of range"},
    {"tau_c = 1", m_tau_c, WG_EINVAL, "tau_c = 1"},
    {"tau_c = nan", m_tau_c_nan, WG_EINVAL, "tau_c = nan"},
    {"period > steps", m_period, WG_EINVAL, "period"},
    {"ramp active = 7", m_active, WG_EINVAL, "ramp active = 7, must be 0 or 1"},
    {"ramp of parameter 99", m_ramp_id, WG_EUNKNOWN, "parameter id 99 does not exist"},
    {"ramp of a1", m_ramp_geom, WG_EINVAL, "a1 cannot be ramped"},
    {"ramp of omega to 1000", m_ramp_to, WG_ERANGE, "ramp target: omega = 1000 out of range"},
    {"ramp from nan", m_ramp_from, WG_ERANGE, "ramp from: omega = nan out of range"},
    {"ramp duration 0", m_ramp_dur0, WG_ERANGE, "ramp duration 0 tau out of range"},
    {"ramp duration 1e16", m_ramp_dur_huge, WG_ERANGE, "ramp duration 1e+16 tau"},
    {"ramp started after tau", m_ramp_tau0, WG_EINVAL, "ramp tau0"},
    {"ramp tau0 = nan", m_ramp_tau0_nan, WG_EINVAL, "ramp tau0"},
    {"ramp already over", m_ramp_over, WG_EINVAL, "ramp tau0"},
    {"ramped value off the ramp", m_ramp_value, WG_EINVAL, "omega = 1.5 is not on the ramp"},
    {"ramp of k1x to 1e4", m_ramp_unstable, WG_ESTABILITY, "need N >="},
    {"cur.motion = 3", m_motion, WG_EINVAL, "cur.motion = 3"},
    {"last.motion = -1", m_motion_last, WG_EINVAL, "last.motion = -1"},
    {"cur.impacts = -1", m_impacts, WG_EINVAL, "cur.impacts = -1"},
    {"last.min_xn > last.max_xn", m_minmax, WG_EINVAL, "last.min_xn"},
    {"cur.min_xn = nan", m_min_nan, WG_EINVAL, "cur.min_xn"},
    {"cur.period != period", m_cur_period, WG_EINVAL, "cur.period"},
};

/* The run's whole visible state, for "unchanged" checks. */
static int same_run(const wg_sim *a, const wg_snapshot *before, double hmax, double h)
{
    wg_snapshot now;
    wg_sim_snapshot(a, &now);
    return memcmp(&now, before, sizeof now) == 0 && a->hmax == hmax && a->h == h;
}

static size_t ends_with_quotes(const char *s)
{
    size_t n = strlen(s);
    return n >= 2 && s[n - 1] == '\'' && s[n - 2] == '\'';
}

static void test_restore_refuses_hostile_values(void)
{
    wg_sim src = mid_ramp(), dst = mid_ramp();
    ASSERT_EQ_INT(wg_sim_run(&dst, 333, NULL, NULL), WG_OK); /* a different moment */
    wg_snapshot good, before;
    wg_sim_snapshot(&src, &good);
    wg_sim_snapshot(&dst, &before);
    double hmax = dst.hmax, h = dst.h;
    char why[400];
    int refused = 0, n = (int)(sizeof cases / sizeof cases[0]);
    for (int i = 0; i < n; i++) {
        wg_snapshot w = good;
        cases[i].mutate(&w);
        why[0] = 0;
        int rc = wg_sim_restore(&dst, &w, why, sizeof why);
        if (rc != cases[i].rc || !strstr(why, cases[i].says) || ends_with_quotes(why))
            TEST_FAIL_("%s: rc %d (want %d), why '%s' (want '%s')", cases[i].what, rc,
                       cases[i].rc, why, cases[i].says);
        if (!same_run(&dst, &before, hmax, h))
            TEST_FAIL_("%s: the sim changed", cases[i].what);
        refused += rc != WG_OK;
    }
    printf("  %d of %d hostile snapshots refused, the sim unchanged\n", refused, n);
    ASSERT_EQ_INT(wg_sim_restore(&dst, &good, why, sizeof why), WG_OK);
    wg_sim_fini(&src);
    wg_sim_fini(&dst);
}

/* A ramp of another parameter than omega restores too, mid-ramp and at its
 * first step, and continues bit-exactly. */
static void test_restore_accepts_live_ramps(void)
{
    wg_sim a = mid_ramp(), b = mid_ramp();
    char why[300];
    ASSERT_EQ_INT(wg_sim_ramp(&a, WG_P_XI_P, NULL, 0.12, 50.0, why, sizeof why), WG_OK);
    for (int k = 0; k < 3; k++) {
        wg_snapshot w;
        wg_sim_snapshot(&a, &w);
        int rc = wg_sim_restore(&b, &w, why, sizeof why);
        if (rc)
            TEST_FAIL_("restore after %d runs: %s", k, why);
        ASSERT_EQ_INT(wg_sim_run(&a, 77, NULL, NULL), WG_OK);
        ASSERT_EQ_INT(wg_sim_run(&b, 77, NULL, NULL), WG_OK);
        ASSERT_TRUE(memcmp(a.y, b.y, sizeof a.y) == 0 && a.tau == b.tau);
        ASSERT_TRUE(a.p.v[WG_P_XI_P] == b.p.v[WG_P_XI_P] && a.ramp.active == b.ramp.active);
    }
    wg_sim_fini(&a);
    wg_sim_fini(&b);
}

TEST_MAIN(TEST(test_restore_refuses_hostile_values), TEST(test_restore_accepts_live_ramps))

/* test_rig_point.c - the live point analysis of wgrig (rig_ana.c) gives
 * the offline sweep's result (wg_point_run) when fed the same sections: a
 * local sim plays the daemon (transient, then record periods delivered as
 * POINCARE would), for a period-1, a period-2 and an impacting orbit, and
 * an aperiodic one (extend rounds, LLE, classification). */
#include "test.h"
#include "rig_ana.h"
#include "rig_imp.h"

#include "wormgear/wg_status.h"

typedef struct feed { rig_rec *r; } feed;

static void on_section(void *ctx, const wg_section *s)
{
    rig_rec *r = ((feed *)ctx)->r;
    rig_rec_push(r, s->y, &s->stats, s->out.xn, s->out.dxn, (int64_t)s->stats.period);
}

/* The daemon's part: run `skip` periods, then record `want` sections. */
static void play(wg_sim *sim, rig_rec *r, int skip, int want)
{
    feed f = {r};
    wg_sink sink = {&f, NULL, on_section, NULL};
    uint64_t n = (uint64_t)sim->cfg.steps_per_period;
    ASSERT_EQ_INT(wg_sim_run(sim, (uint64_t)skip * n, NULL, NULL), WG_OK);
    r->n = 0;
    ASSERT_EQ_INT(wg_sim_run(sim, (uint64_t)want * n, &sink, NULL), WG_OK);
}

/* wgrig's run_point on a local sim, from state y at psi = 0. */
static void rig_point(const wg_params *p, const wg_sweep_opts *o, const double *y, wg_point *pt)
{
    wg_sim sim;
    wg_sim_config cfg = {o->model, o->stepper, o->steps};
    char why[256];
    ASSERT_EQ_INT(wg_sim_init(&sim, p, &cfg, why, sizeof why), WG_OK);
    wg_sim_set_state(&sim, y, 0, 0.0);
    rig_rec rec;
    ASSERT_EQ_INT(rig_rec_init(&rec, sim.nstate, o->record), 0);
    rig_ana a;
    rig_ana_init(&a, p, o->model, o->stepper, o->steps, o);
    play(&sim, &rec, o->transient, o->record);
    int n = rig_ana_period(&a, &rec, 0, pt, why, sizeof why);
    for (int at = 1; n == 0 && at <= o->extend; at++) {
        play(&sim, &rec, o->transient, o->record);
        n = rig_ana_period(&a, &rec, at, pt, why, sizeof why);
    }
    if (n == 0) {
        ASSERT_EQ_INT(rig_ana_lle(&a, &rec, pt, why, sizeof why), WG_OK);
        play(&sim, &rec, o->lle_periods, o->record);
        rig_ana_aperiodic(&a, &rec, pt);
    }
    rig_rec_fill(&rec, pt);
    rig_ana_fini(&a);
    rig_rec_fini(&rec);
    wg_sim_fini(&sim);
}

static void compare_at(double omega, int want_period)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = omega;
    wg_sweep_opts o;
    wg_sweep_opts_default(&o);
    o.steps = 128; /* above the RK4 limit of table3: wg_point_run keeps it */
    o.settle = 0;  /* the rig runs the whole transient; so does the offline point */
    double y0[WG_NSTATE_MAX] = {0}, y1[WG_NSTATE_MAX];
    wg_equilibrium(o.model, &p, y0);
    memcpy(y1, y0, sizeof y1);
    wg_point off, live;
    char why[256];
    ASSERT_EQ_INT(wg_point_run(&p, &o, y1, &off, why, sizeof why), WG_OK);
    rig_point(&p, &o, y0, &live);
    printf("omega %.3g: offline %s P%d %s imp %.3g min %.12g | live %s P%d %s imp %.3g min %.12g\n",
           omega, wg_regime_name(off.regime), off.period, wg_motion_name(off.motion),
           off.impacts, off.min_xn, wg_regime_name(live.regime), live.period,
           wg_motion_name(live.motion), live.impacts, live.min_xn);
    if (want_period >= 0)
        ASSERT_EQ_INT(off.period, want_period);
    ASSERT_EQ_INT(live.regime, off.regime);
    ASSERT_EQ_INT(live.period, off.period);
    ASSERT_EQ_INT(live.motion, off.motion);
    ASSERT_EQ_INT(live.steps, off.steps);
    ASSERT_TRUE(live.impacts == off.impacts);
    ASSERT_TRUE(live.min_xn == off.min_xn);
    ASSERT_TRUE(live.max_xn == off.max_xn);
    ASSERT_TRUE(live.err == off.err);
    ASSERT_TRUE(live.tol == off.tol);
    ASSERT_EQ_INT(live.nsec, off.nsec);
    ASSERT_NEAR(live.xn[live.nsec - 1], off.xn[off.nsec - 1], 1e-12);
    if (isfinite(off.lle))
        ASSERT_NEAR(live.lle, off.lle, 1e-9);
}

static void test_period1_no_impact(void) { compare_at(0.5, 1); }
static void test_period1_impacting(void) { compare_at(0.9, 1); }
static void test_period2(void) { compare_at(1.2, 2); }
static void test_aperiodic(void) { compare_at(1.4, -1); }

/* Impacts by period, and the windows a lost CONTACT message may touch. */
static void test_impacts_lost(void)
{
    rig_imp m;
    rig_imp_init(&m);
    for (int64_t p = 10; p < 20; p++) {
        ASSERT_EQ_INT(rig_imp_push(&m, p), 0);
        rig_imp_heard(&m, p);
    }
    ASSERT_EQ_INT(rig_imp_count(&m, 12, 15), 4);
    ASSERT_EQ_INT(rig_imp_lost(&m, 0, 1000), 0);
    rig_imp_lose(&m, 30); /* lost between period 19 and 30 */
    ASSERT_EQ_INT(rig_imp_lost(&m, 12, 18), 0);
    ASSERT_EQ_INT(rig_imp_lost(&m, 19, 19), 1);
    ASSERT_EQ_INT(rig_imp_lost(&m, 25, 40), 1);
    ASSERT_EQ_INT(rig_imp_lost(&m, 31, 40), 0);
    rig_imp_fini(&m);
    ASSERT_EQ_INT(m.last, -1);
    rig_imp_lose(&m, 5); /* before anything was heard: from the start */
    ASSERT_EQ_INT(rig_imp_lost(&m, 0, 0), 1);
    for (int i = 0; i < RIG_IMP_LOST_MAX + 1; i++)
        rig_imp_lose(&m, 1000 + i);
    ASSERT_EQ_INT(rig_imp_lost(&m, 5000, 6000), 1); /* too many: all of it */
    rig_imp_fini(&m);
}

TEST_MAIN(TEST(test_impacts_lost), TEST(test_period1_no_impact), TEST(test_period1_impacting), TEST(test_period2),
          TEST(test_aperiodic))

/* test_report.c - what the daemon publishes about itself and the run:
 * STATE, POINCARE and CONTACT with consecutive seq, the regime and motion
 * on STATUS, impacts per period of the new orbit after a change. */
#include "fixture.h"

/* STATE, POINCARE and CONTACT arrive with consecutive seq and nothing lost. */
static void test_stream_seq(void)
{
    wgd *d = setup(128);
    ASSERT_EQ_INT(set1(d, "omega", 1.35), WG_OK);
    stream_set_decimation(&d->st, 3);
    run(d, 128 * 1500);
    stream_flush(d);
    drain(d);
    ASSERT_EQ_INT(F.seq_gaps, 0);
    ASSERT_EQ_INT(F.pc_gaps, 0);
    ASSERT_EQ_INT(F.npc, 1500);
    ASSERT_EQ_INT(F.nsamples, 128 * 1500 / 3);
    uint64_t events = 0;
    for (int c = 0; c < WG_NCONTACT; c++)
        for (int k = 0; k < WG_NEVKIND; k++)
            events += d->sim.nevents[c][k];
    ASSERT_EQ_INT(F.nct, events);
    ASSERT_TRUE(F.nct > 0);
    ASSERT_TRUE(F.seq_next[0] > 100 && F.seq_next[1] > 5);
    ASSERT_EQ_INT(d->io.dropped, 0);
    teardown(d);
}

/* STATE carries theta1, theta2: the library's angles of the sample's state,
 * turning z2/z1 : 1 over whole wheel turns; a set of body data (z2) changes
 * them and nothing else. */
static void test_state_angles(void)
{
    wgd *d = setup(128);
    ASSERT_EQ_INT(set1(d, "omega", 0.7), WG_OK);
    stream_set_decimation(&d->st, 1);
    run(d, 128 * 37 * 2);
    stream_flush(d);
    drain(d);
    ASSERT_EQ_INT(F.nsamples, 128 * 37 * 2);
    double th[2], turn[2] = {0, 0};
    wg_sim_angles(&d->sim, th);
    ASSERT_TRUE(F.th1[F.nsamples - 1] == th[0] && F.th2[F.nsamples - 1] == th[1]);
    for (int i = 1; i < F.nsamples; i++) {
        double d1 = F.th1[i] - F.th1[i - 1], d2 = F.th2[i] - F.th2[i - 1];
        ASSERT_TRUE(F.th1[i] >= 0 && F.th1[i] < 2 * M_PI && F.th2[i] >= 0 && F.th2[i] < 2 * M_PI);
        turn[0] += d1 - 2 * M_PI * round(d1 / (2 * M_PI));
        turn[1] += d2 - 2 * M_PI * round(d2 / (2 * M_PI));
    }
    /* 74 periods less one step: 74/3 and 74/37 turns, up to the elastic parts */
    ASSERT_NEAR(turn[0] / (2 * M_PI), 74.0 / 3, 0.02);
    ASSERT_NEAR(turn[1] / (2 * M_PI), 2.0, 0.005);
    double y[WG_NSTATE_MAX];
    memcpy(y, d->sim.y, sizeof y);
    ASSERT_EQ_INT(set1(d, "z2", 41), WG_OK);
    ASSERT_TRUE(memcmp(y, d->sim.y, sizeof y) == 0);
    wg_sim_angles(&d->sim, th);
    double rigid2 = 2 * M_PI * (double)(d->sim.period % 41) / 41;
    ASSERT_NEAR(th[1], rigid2, 0.01);
    teardown(d);
}

/* STATUS reports the regime from the tracked Poincare points. */
static void test_status_regime(void)
{
    wgd *d = setup(64);
    ASSERT_EQ_INT(set1(d, "omega", 0.3), WG_OK);
    report_status(d);
    drain(d);
    ASSERT_STR(F.regime, "unknown");
    run(d, 64 * 400);
    report_status(d);
    drain(d);
    ASSERT_STR(F.regime, "period-1");
    ASSERT_STR(F.motion, "no_impact");
    ASSERT_EQ_INT(ramp(d, "omega", 0, 0, 0.35, 500, "tau"), WG_OK);
    run(d, 64);
    report_status(d);
    drain(d);
    ASSERT_STR(F.regime, "ramping");
    teardown(d);
}

/* After a change, STATUS describes the new orbit only: impacts per period
 * do not average in the periods before it. */
static void test_status_after_set(void)
{
    wgd *d = setup(128);
    ASSERT_EQ_INT(set1(d, "omega", 1.2), WG_OK); /* impacting, 0.5 per period */
    run(d, 128 * 400);
    report_status(d);
    drain(d);
    ASSERT_NEAR(F.impacts_per_period, 0.5, 0.05);
    run(d, 128 * 200); /* the same STATUS interval continues ... */
    ASSERT_EQ_INT(set1(d, "omega", 0.3), WG_OK); /* ... into a quiet orbit */
    run(d, 128 * 400);
    report_status(d);
    drain(d);
    ASSERT_STR(F.motion, "no_impact");
    ASSERT_NEAR(F.impacts_per_period, 0.0, 0);
    teardown(d);
}

/* The rates of a STATUS interval count the steps run in it, not the
 * difference of the state's counters: after a reset (steps and tau back to
 * 0) or a restore to an earlier state, STATUS said rtf -8.1 and 3.7e19
 * steps/s (an unsigned difference wrapped). */
static void test_rates_across_reset(void)
{
    wgd *d = setup(128);
    run(d, 128 * 50);
    d->stat.next_status_ns = 0; /* a STATUS is due: published, and the interval starts */
    report_tick(d, log_now_ns());
    drain(d);
    run(d, 128 * 20);
    wormgear_cmd_t c = {.op = "reset"};
    ASSERT_EQ_INT(send(d, &c), WG_OK);
    run(d, 128 * 5);
    int64_t t0 = log_now_ns();
    report_status(d);
    drain(d);
    double wall_max = (double)(log_now_ns() - t0) * 1e-9 + 60.0;
    printf("after a reset: rtf %g, %g steps/s\n", F.rtf, F.steps_per_s);
    ASSERT_TRUE(F.rtf > 0 && F.steps_per_s > 0);
    /* 25 periods' steps run in the interval, which lasted under a minute */
    ASSERT_TRUE(F.steps_per_s >= 128 * 25 / wall_max && F.steps_per_s < 1e10);
    teardown(d);
}

/* STATUS's motion and impacts per period describe the same periods: from
 * the start at omega = 1 the first periods impact and the orbit settles
 * impact-free; an interval that began after the last impact said "0
 * impacts/period" beside the tracker's "single_sided". Checked at every
 * STATUS of the first 300 periods, a STATUS every 10. */
static void test_motion_matches_impacts(void)
{
    wgd *d = setup(128);
    int impacting = 0, quiet = 0;
    for (int k = 0; k < 30; k++) {
        d->stat.next_status_ns = 0;
        report_tick(d, log_now_ns()); /* a STATUS, and a new interval */
        drain(d);
        if (k > 0) {
            int none = !strcmp(F.motion, "no_impact");
            impacting += !none, quiet += none;
            if (none != (F.impacts_per_period == 0))
                TEST_FAIL_("period %d: motion %s with %g impacts/period", 10 * k, F.motion,
                           F.impacts_per_period);
        }
        run(d, 128 * 10);
    }
    printf("STATUS: %d impacting, %d quiet\n", impacting, quiet);
    ASSERT_TRUE(impacting > 0 && quiet > 0); /* both seen: the start impacts, then settles */
    teardown(d);
}

/* The foreground line tells the same motion, regime and impacts per period
 * as STATUS, whichever period of a period-2 orbit (one impacting, one
 * free) came last. */
static void test_line_matches_status(void)
{
    wgd *d = setup(128);
    ASSERT_EQ_INT(set1(d, "omega", 1.2), WG_OK);
    run(d, 128 * 400);
    char line[512], want[96];
    for (int k = 0; k < 2; k++) {
        run(d, 128);
        report_status(d);
        drain(d);
        ASSERT_STR(F.motion, "single_sided");
        ASSERT_STR(F.regime, "period-2");
        report_line(d, line, sizeof line);
        snprintf(want, sizeof want, "| %s %s %.2f impacts/period |", F.regime, F.motion,
                 F.impacts_per_period);
        ASSERT_CONTAINS(line, want);
    }
    teardown(d);
}

/* contacts all N / mesh / none: what CONTACT carries, counted per
 * contact against the library's own event counts. */
static void test_contacts_setting(void)
{
    wgd *d = setup(128);
    ASSERT_EQ_INT(set1(d, "omega", 1.35), WG_OK); /* bearings and mesh impact */
    uint64_t before[WG_NCONTACT], n[WG_NCONTACT];
    wormgear_cmd_t c = {.op = "contacts", .name = "all", .nsteps = 10};
    ASSERT_EQ_INT(send(d, &c), WG_OK);
    ASSERT_CONTAINS(F.message, "1 in 10 events of each bearing");
    for (int round = 0; round < 3; round++) {
        for (int k = 0; k < WG_NCONTACT; k++) {
            before[k] = 0;
            for (int e = 0; e < WG_NEVKIND; e++)
                before[k] += d->sim.nevents[k][e];
        }
        memset(F.nct_by, 0, sizeof F.nct_by);
        run(d, 128 * 300);
        stream_flush(d);
        drain(d);
        for (int k = 0; k < WG_NCONTACT; k++) {
            n[k] = 0;
            for (int e = 0; e < WG_NEVKIND; e++)
                n[k] += d->sim.nevents[k][e];
            n[k] -= before[k];
        }
        ASSERT_TRUE(n[0] > 0 && n[1] > 100);
        if (round == 0) { /* 1 in 10 of each bearing's, every mesh event */
            ASSERT_EQ_INT(F.ct_every, 10);
            ASSERT_EQ_INT(F.nct_by[0], n[0]);
            for (int k = 1; k < WG_NCONTACT; k++)
                ASSERT_TRUE(F.nct_by[k] >= (int)(n[k] / 10) && F.nct_by[k] <= (int)(n[k] / 10) + 1);
            c = (wormgear_cmd_t){.op = "contacts", .name = "mesh"};
        } else if (round == 1) {
            ASSERT_EQ_INT(F.ct_every, 0);
            ASSERT_EQ_INT(F.nct_by[0], n[0]);
            for (int k = 1; k < WG_NCONTACT; k++)
                ASSERT_EQ_INT(F.nct_by[k], 0);
            c = (wormgear_cmd_t){.op = "contacts", .name = "none"};
        } else {
            for (int k = 0; k < WG_NCONTACT; k++)
                ASSERT_EQ_INT(F.nct_by[k], 0);
        }
        if (round < 2)
            ASSERT_EQ_INT(send(d, &c), WG_OK);
    }
    c = (wormgear_cmd_t){.op = "contacts", .name = "some"};
    ASSERT_EQ_INT(send(d, &c), WG_EINVAL);
    ASSERT_CONTAINS(F.message, "not one of all, mesh, none");
    c = (wormgear_cmd_t){.op = "contacts", .name = "all", .nsteps = -3};
    ASSERT_EQ_INT(send(d, &c), WG_ERANGE);
    ASSERT_EQ_INT(d->conf.contacts, CONTACTS_NONE); /* a refusal changes nothing */
    teardown(d);
}

/* STATUS's per-bearing impacts per period: at omega 1.2 and xi_p = 1.0 the
 * mesh never separates and the wheel bearing z2 rattles, once a period
 * (the sweep finds the same: lib.test_sweep); counted whatever the
 * contacts setting publishes. Which other bearings touch depends on where
 * their journals float in the clearance (no force holds them there): on
 * the last bits of the history, so STATUS is held to the library's own
 * count of each. */
static void test_status_bearing_impacts(void)
{
    wgd *d = setup(128);
    ASSERT_EQ_INT(set1(d, "xi_p", 1.0), WG_OK);
    ASSERT_EQ_INT(set1(d, "omega", 1.2), WG_OK);
    wormgear_cmd_t c = {.op = "contacts", .name = "none"};
    ASSERT_EQ_INT(send(d, &c), WG_OK);
    run(d, 128 * 600);
    stream_flush(d);
    drain(d);
    stream_stats_reset(&d->st); /* a new STATUS interval, past the transient */
    memset(F.pc_bimp, 0, sizeof F.pc_bimp);
    memset(F.pc_bvmax, 0, sizeof F.pc_bvmax);
    uint64_t ev0[WG_NBEARING], ev1;
    for (int j = 0; j < WG_NBEARING; j++)
        ev0[j] = d->sim.nevents[WG_C_X1 + j][WG_EV_DRIVE_IMPACT] +
                 d->sim.nevents[WG_C_X1 + j][WG_EV_BACK_IMPACT];
    run(d, 128 * 200);
    report_status(d);
    stream_flush(d);
    drain(d);
    /* POINCARE carries each period's bearing impacts: exactly the library's
     * events over the 200 periods, and the same largest speeds as STATUS */
    ASSERT_EQ_INT(F.pc_nbearing, WG_NBEARING);
    for (int j = 0; j < WG_NBEARING; j++) {
        ev1 = d->sim.nevents[WG_C_X1 + j][WG_EV_DRIVE_IMPACT] +
              d->sim.nevents[WG_C_X1 + j][WG_EV_BACK_IMPACT];
        ASSERT_EQ_INT(F.pc_bimp[j], (long)(ev1 - ev0[j]));
        ASSERT_TRUE(F.pc_bvmax[j] == F.bearing_vmax[j] || F.bearing_vmax[j] == 0);
    }
    ASSERT_EQ_INT(F.nbearing, WG_NBEARING);
    ASSERT_STR(F.motion, "no_impact");
    ASSERT_NEAR(F.impacts_per_period, 0, 0);
    for (int j = 0; j < WG_NBEARING; j++) {
        double want = F.pc_bimp[j] / 200.0; /* the library's, checked above */
        ASSERT_NEAR(F.bearing_ipp[j], want, 0.01); /* +-1 impact at the interval's ends */
        ASSERT_TRUE(want > 0 ? F.bearing_vmax[j] > 1e-3 : F.bearing_vmax[j] == 0);
    }
    ASSERT_NEAR(F.bearing_ipp[WG_C_Z2 - WG_C_X1], 1, 0.01);
    teardown(d);
}

/* A STATUS on our channel that we did not send is another daemon with our
 * URL and prefix (both answer every command; a new user ran tools/run.sh
 * twice and nothing said so): counted and logged. Our own echo is not. */
static void test_second_daemon_noticed(void)
{
    wgd *d = setup(128);
    for (int i = 0; i < 3; i++)
        report_status(d);
    drain(d);
    ASSERT_EQ_INT(d->stat.status_foreign, 0); /* our own three came back */
    double z[6] = {0};
    wormgear_status_t m = {.utime = 1700000000000000, .seq = 1, .scene = "table3",
                           .mode = "realtime", .run = "running", .health = "ok", .fault = "",
                           .tick_refusal = "", .motion = "", .nbearing = 6,
                           .bearing_impacts_per_period = z, .bearing_impact_vmax = z,
                           .regime = ""};
    wormgear_status_t_publish(d->io.lcm, "T_STATUS", &m); /* our seq 1, another utime */
    drain(d);
    ASSERT_EQ_INT(d->stat.status_foreign, 1);
    unsigned char junk[16] = {1, 2, 3};
    lcm_publish(d->io.lcm, "T_STATUS", junk, sizeof junk); /* not a status_t: ignored */
    drain(d);
    ASSERT_EQ_INT(d->stat.status_foreign, 1);
    teardown(d);
}

TEST_MAIN(TEST(test_state_angles), TEST(test_status_bearing_impacts), TEST(test_contacts_setting),
          TEST(test_stream_seq), TEST(test_status_regime), TEST(test_status_after_set),
          TEST(test_rates_across_reset), TEST(test_motion_matches_impacts),
          TEST(test_line_matches_status),
          TEST(test_second_daemon_noticed))

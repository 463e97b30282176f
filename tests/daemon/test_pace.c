/* test_pace.c - pacing as a pure function of (fake) monotonic time. */
#include "conf.h"
#include "pace.h"
#include "test.h"

#define MS 1000000LL
#define SEC 1000000000LL

/* tau_per_ns such that one wall ms is exactly 10 steps of h = 0.5. */
static pace_cfg cfg(int policy)
{
    return (pace_cfg){.tau_per_ns = 5.0 / MS, .tick_ns = MS, .catchup_ticks = 4,
                      .policy = policy, .stop_after = 3, .grace_ns = 0};
}

/* Steps due follow the clock, not the number of calls. */
static void test_due_follows_clock(void)
{
    pace_cfg c = cfg(POLICY_CONTINUE);
    pace p;
    pace_init(&p, &c, 1000 * MS, 0.0);
    double tau = 0, h = 0.5;
    pace_due d = pace_steps_due(&p, 1000 * MS, tau, h);
    ASSERT_EQ_INT(d.steps, 0);
    d = pace_steps_due(&p, 1001 * MS, tau, h);
    ASSERT_EQ_INT(d.steps, 10);
    tau += d.steps * h;
    /* a late tick (libev merged two): 2 ms worth due, not 1 */
    d = pace_steps_due(&p, 1003 * MS, tau, h);
    ASSERT_EQ_INT(d.steps, 20);
    ASSERT_EQ_INT(d.overrun, 0);
    tau += d.steps * h;
    /* half a step's worth of time: nothing due, lag below one step */
    d = pace_steps_due(&p, 1003 * MS + MS / 20, tau, h);
    ASSERT_EQ_INT(d.steps, 0);
    ASSERT_NEAR(pace_lag_s(&p), 0.05e-3, 1e-12);
    /* ahead of the clock (tau beyond target): nothing due, no lag */
    d = pace_steps_due(&p, 1004 * MS, tau + 100, h);
    ASSERT_EQ_INT(d.steps, 0);
    ASSERT_NEAR(pace_lag_s(&p), 0.0, 0.0);
}

/* Over 10 s of 1 ms ticks with jitter, simulated time tracks the clock. */
static void test_long_run_no_drift(void)
{
    pace_cfg c = cfg(POLICY_CONTINUE);
    c.tau_per_ns = 31901.0 * 1e-9; /* physical real time, table3 */
    pace p;
    pace_init(&p, &c, 0, 0.0);
    double tau = 0, h = 6.283185307179586 / (2.5 * 128);
    long long now = 0;
    unsigned seed = 12345;
    for (int i = 0; i < 10000; i++) {
        seed = seed * 1103515245u + 12345u;
        now += MS + (long long)(seed >> 16) % (MS / 2) - MS / 4; /* +-0.25 ms jitter */
        tau += pace_steps_due(&p, now, tau, h).steps * h;
    }
    ASSERT_NEAR(tau, pace_target(&p, now), h);
    ASSERT_EQ_INT(p.overruns, 0);
}

/* The cap limits one tick; the backlog is caught up later (continue). */
static void test_cap_and_overrun_continue(void)
{
    pace_cfg c = cfg(POLICY_CONTINUE);
    pace p;
    pace_init(&p, &c, 0, 0.0);
    double tau = 0, h = 0.5;
    pace_due d = pace_steps_due(&p, 10 * MS, tau, h); /* 100 due, cap 40 */
    ASSERT_EQ_INT(d.steps, 40);
    ASSERT_EQ_INT(d.overrun, 1);
    ASSERT_EQ_INT(p.overruns, 1);
    ASSERT_NEAR(pace_lag_s(&p), 6e-3, 1e-12);
    tau += d.steps * h;
    d = pace_steps_due(&p, 11 * MS, tau, h); /* 70 due: capped again */
    ASSERT_EQ_INT(d.steps, 40);
    ASSERT_EQ_INT(p.consecutive, 2);
    tau += d.steps * h;
    d = pace_steps_due(&p, 12 * MS, tau, h); /* 40 due: caught up */
    ASSERT_EQ_INT(d.steps, 40);
    ASSERT_EQ_INT(d.overrun, 0);
    ASSERT_EQ_INT(p.consecutive, 0);
    ASSERT_EQ_INT(p.overruns, 2);
    ASSERT_EQ_INT(d.stop, 0);
}

/* Freeze drops the backlog: the next tick is an ordinary one. */
static void test_freeze_drops_backlog(void)
{
    pace_cfg c = cfg(POLICY_FREEZE);
    pace p;
    pace_init(&p, &c, 0, 0.0);
    double tau = 0, h = 0.5;
    pace_due d = pace_steps_due(&p, 10 * MS, tau, h);
    ASSERT_EQ_INT(d.steps, 40);
    ASSERT_EQ_INT(d.overrun, 1);
    ASSERT_NEAR(pace_lag_s(&p), 0.0, 1e-15);
    tau += d.steps * h;
    d = pace_steps_due(&p, 11 * MS, tau, h);
    ASSERT_EQ_INT(d.steps, 10);
    ASSERT_EQ_INT(d.overrun, 0);
}

/* Stop after N consecutive overruns, not counting the start-up grace. */
static void test_stop_after_n_with_grace(void)
{
    pace_cfg c = cfg(POLICY_STOP);
    c.grace_ns = 110 * MS;
    pace p;
    pace_init(&p, &c, 0, 0.0);
    double tau = 0, h = 0.5;
    long long now = 0;
    for (int i = 0; i < 5; i++) { /* hopelessly behind, but within the grace */
        now += 20 * MS;
        pace_due d = pace_steps_due(&p, now, tau, h);
        tau += d.steps * h;
        ASSERT_EQ_INT(d.overrun, 1);
        ASSERT_EQ_INT(d.stop, 0);
    }
    ASSERT_EQ_INT(p.grace_overruns, 5);
    ASSERT_EQ_INT(p.overruns, 0);
    int stopped_at = 0;
    for (int i = 1; i <= 5 && !stopped_at; i++) {
        now = 100 * MS + i * 20 * MS;
        pace_due d = pace_steps_due(&p, now, tau, h);
        tau += d.steps * h;
        if (d.stop)
            stopped_at = i;
    }
    ASSERT_EQ_INT(stopped_at, 3);
    ASSERT_EQ_INT(p.overruns, 3);
    /* re-anchoring (resume) restarts the grace and the run of overruns */
    pace_anchor(&p, now, tau);
    ASSERT_EQ_INT(p.consecutive, 0);
    pace_due d = pace_steps_due(&p, now + 20 * MS, tau, h);
    ASSERT_EQ_INT(d.stop, 0);
    ASSERT_EQ_INT(p.grace_overruns, 6);
}

/* A rate change keeps simulated time continuous. */
static void test_rate_change_reanchors(void)
{
    pace_cfg c = cfg(POLICY_CONTINUE);
    pace p;
    pace_init(&p, &c, 0, 0.0);
    double tau = 0, h = 0.5;
    tau += pace_steps_due(&p, 2 * MS, tau, h).steps * h; /* 20 steps: tau 10 */
    ASSERT_NEAR(tau, 10.0, 0);
    pace_set_rate(&p, c.tau_per_ns * 0.1, 2 * MS, tau); /* slow motion x0.1 */
    pace_due d = pace_steps_due(&p, 5 * MS, tau, h);     /* 3 ms * 0.5 tau/ms = 1.5 tau */
    ASSERT_EQ_INT(d.steps, 3);
    ASSERT_NEAR(pace_target(&p, 5 * MS), 11.5, 1e-12);
}

/* pace_configure takes the pacing keys of the configuration and keeps the
 * overrun counters across a reconfiguration (mode command, reload); the
 * anchor moves to (now, tau) and the run of overruns restarts. */
static void test_configure_from_conf(void)
{
    conf k;
    conf_defaults(&k);
    k.rate = 0.5, k.tick_us = 2000, k.catchup_ticks = 4, k.overrun_policy = POLICY_STOP;
    k.overrun_stop_after = 7, k.startup_grace_s = 0.25;
    pace p = {.overruns = 3, .grace_overruns = 2, .consecutive = 5, .lag_tau = 1};
    pace_configure(&p, &k, 31901.0, 7 * SEC, 12.5);
    ASSERT_NEAR(p.cfg.tau_per_ns, 0.5 * 31901.0 * 1e-9, 0);
    ASSERT_EQ_INT(p.cfg.tick_ns, 2 * MS);
    ASSERT_NEAR(p.cfg.catchup_ticks, 4, 0);
    ASSERT_EQ_INT(p.cfg.policy, POLICY_STOP);
    ASSERT_EQ_INT(p.cfg.stop_after, 7);
    ASSERT_EQ_INT(p.cfg.grace_ns, 250 * MS);
    ASSERT_EQ_INT(p.overruns, 3);
    ASSERT_EQ_INT(p.grace_overruns, 2);
    ASSERT_EQ_INT(p.consecutive, 0);
    ASSERT_NEAR(pace_lag_s(&p), 0, 0);
    ASSERT_NEAR(pace_target(&p, 7 * SEC), 12.5, 0);
}

/* The overrun warning agrees with its figures. It said "more than 10 ticks
 * behind (lag 0.233 ms ...)", the lag being what was left over the cap;
 * now the whole backlog, the cap, and a cause the figures support. */
static void test_overrun_text(void)
{
    pace_cfg c = cfg(POLICY_CONTINUE);
    pace p;
    pace_init(&p, &c, 0, 0.0);
    char t[640];
    pace_due d = pace_steps_due(&p, 10 * MS, 0.0, 0.5); /* 10 ms of steps due, cap 4 ticks */
    ASSERT_EQ_INT(d.overrun, 1);
    ASSERT_NEAR(pace_lag_s(&p), 6e-3, 1e-12); /* left over the cap: not "how far behind" */
    pace_load l = {.gap_ns = 12 * MS, .cpu_ns = 3 * MS / 10, .busiest_ns = MS / 10,
                   .ns_per_step = 100, .h = 0.5, .rate = 1};
    pace_overrun_text(&p, &l, t, sizeof t);
    ASSERT_STR(t, "10.000 ms behind the pace, over the catch-up cap of 4 ticks (4.0 ms; policy "
                  "continue): 12.0 ms since the last tick, the loop ran 0.3 ms of it (the "
                  "longest handler 0.1 ms): the daemon was not scheduled (a busy or full "
                  "machine)");
    /* the loop busy all the time, stepping needing more than a core: the rate */
    l = (pace_load){.gap_ns = MS, .cpu_ns = MS, .busiest_ns = MS, .steps = 5,
                    .ns_per_step = 200000, .h = 0.5, .rate = 1000};
    pace_overrun_text(&p, &l, t, sizeof t);
    ASSERT_CONTAINS(t, "the loop ran 1.0 ms of it (the longest handler 1.0 ms): rate 1000 is "
                       "more than the model can run here (it needs 1e+04 steps/s, 200000 ns a "
                       "step: 200 % of a core; lower the rate, or use mode fast)");
    /* busy, the rate within reach, the time spent stepping: catching up */
    l = (pace_load){.gap_ns = MS, .cpu_ns = MS, .busiest_ns = MS, .steps = 9000,
                    .ns_per_step = 100, .h = 0.5, .rate = 1};
    pace_overrun_text(&p, &l, t, sizeof t);
    ASSERT_CONTAINS(t, ": the loop catching up a backlog (rate 1 needs 0 % of a core");
    /* a chunk preempted made the smoothed cost of a step 1e7 ns: the
     * interval's CPU time a step (1 ms / 9000) is what the rate needs */
    l.ns_per_step = 1e7;
    pace_overrun_text(&p, &l, t, sizeof t);
    ASSERT_CONTAINS(t, ": the loop catching up a backlog (rate 1 needs 0 % of a core");
    l.ns_per_step = 100;
    /* busy with something else */
    l.steps = 10;
    pace_overrun_text(&p, &l, t, sizeof t);
    ASSERT_CONTAINS(t, ": the daemon's own work besides stepping");
    l.ns_per_step = 0; /* no step measured yet */
    pace_overrun_text(&p, &l, t, sizeof t);
    ASSERT_CONTAINS(t, "ms): the daemon's own work");
    l.gap_ns = 0; /* the first tick: no interval, no cause */
    pace_overrun_text(&p, &l, t, sizeof t);
    ASSERT_CONTAINS(t, "(the longest handler 1.0 ms)");
    ASSERT_TRUE(t[strlen(t) - 1] == ')');
}

static void test_fast_chunk(void)
{
    ASSERT_EQ_INT(pace_fast_chunk(0, MS), 64);
    ASSERT_EQ_INT(pace_fast_chunk(100, MS), 10000);
    ASSERT_EQ_INT(pace_fast_chunk(1e6, MS), 64);
    ASSERT_EQ_INT(pace_fast_chunk(1e-6, SEC), 10000000);
}

TEST_MAIN(TEST(test_due_follows_clock), TEST(test_long_run_no_drift),
          TEST(test_cap_and_overrun_continue), TEST(test_freeze_drops_backlog),
          TEST(test_stop_after_n_with_grace), TEST(test_rate_change_reanchors),
          TEST(test_configure_from_conf), TEST(test_fast_chunk), TEST(test_overrun_text))

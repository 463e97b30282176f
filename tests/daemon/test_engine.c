/* test_engine.c - the step path: a blow-up keeps the last good state,
 * pauses and is on STATUS at once; the engine itself only steps and hands
 * a ramp's end and a fault to its caller. */
#include "fixture.h"

/* A blow-up: FAULT on STATUS at once, the last good state kept, paused;
 * the daemon goes on serving and reset clears it. */
static void test_blowup_fault(void)
{
    wgd *d = setup(128);
    run(d, 2000);
    d->sim.h *= 400; /* test only: force RK4 far past its stability limit */
    uint64_t done = cmd_run(d, 100000);
    drain(d);
    ASSERT_TRUE(done < 100000);
    ASSERT_EQ_INT(d->sim.steps, 2000 + done);
    ASSERT_TRUE(d->fault);
    ASSERT_EQ_INT(d->run, RUN_PAUSED);
    ASSERT_STR(F.health, "fault");
    ASSERT_CONTAINS(d->fault_msg, "blew up");
    double sum = 0;
    for (int i = 0; i < d->sim.nstate; i++)
        sum += fabs(d->sim.y[i]);
    ASSERT_TRUE(isfinite(sum) && sum < 1e9);
    wormgear_cmd_t c = {.op = "step", .nsteps = 1000};
    ASSERT_EQ_INT(send(d, &c), WG_ENONFINITE); /* stepping on: blows up again, refused */
    ASSERT_EQ_INT(simple(d, "get", ""), WG_OK);
    ASSERT_EQ_INT(simple(d, "reset", ""), WG_OK); /* h rebuilt, fault cleared */
    ASSERT_TRUE(!d->fault);
    run(d, 5000);
    report_status(d);
    drain(d);
    ASSERT_STR(F.health, "ok");
    teardown(d);
}

/* engine_run only steps: a ramp's end and a blow-up come back to the caller
 * as events and nothing is published; cmd_run (above) announces them. */
static void test_events_returned_not_published(void)
{
    wgd *d = setup(128);
    ASSERT_EQ_INT(ramp(d, "omega", 0, 0, 1.1, 100, "tau"), WG_OK);
    int params0 = F.nparams_msgs, status0 = F.nstatus, events = -1;
    uint64_t done = engine_run(d, 128 * 30, &events); /* about 30 * 2 pi tau > 100 */
    drain(d);
    ASSERT_EQ_INT(done, 128 * 30);
    ASSERT_EQ_INT(events, ENGINE_RAMP_ENDED);
    ASSERT_EQ_INT(d->sim.ramp.active, 0);
    ASSERT_EQ_INT(F.nparams_msgs, params0);
    ASSERT_EQ_INT(engine_run(d, 100, &events), 100);
    ASSERT_EQ_INT(events, 0);
    d->sim.h *= 400; /* test only: force RK4 far past its stability limit */
    done = engine_run(d, 100000, &events);
    drain(d);
    ASSERT_TRUE(done < 100000);
    ASSERT_EQ_INT(events, ENGINE_FAULTED);
    ASSERT_TRUE(d->fault);
    ASSERT_EQ_INT(d->run, RUN_PAUSED);
    ASSERT_EQ_INT(F.nstatus, status0);
    report_fault(d); /* what cmd_run does with ENGINE_FAULTED */
    drain(d);
    ASSERT_EQ_INT(F.nstatus, status0 + 1);
    ASSERT_STR(F.health, "fault");
    ASSERT_EQ_INT(simple(d, "reset", ""), WG_OK);
    teardown(d);
}

TEST_MAIN(TEST(test_blowup_fault), TEST(test_events_returned_not_published))

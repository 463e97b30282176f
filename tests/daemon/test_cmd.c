/* test_cmd.c - the command channel in-process: set validated whole and
 * applied atomically (every refusal class with its code and range, RK4
 * stability; a flag other than 0 or 1), set at the next Poincare section (and cancelled when its
 * section no longer comes), accept_commands, step, pause, resume, reset,
 * mode and TICK. */
#include "fixture.h"

static void test_set_atomic(void)
{
    wgd *d = setup(128);
    char *n[2] = {"omega", "xi_p"};
    double v[2] = {1.5, 0.1};
    wormgear_cmd_t c = {.op = "set", .nparams = 2, .names = n, .values = v};
    ASSERT_EQ_INT(send(d, &c), WG_OK);
    ASSERT_TRUE(F.accepted);
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.5, 0);
    ASSERT_NEAR(d->sim.p.v[WG_P_XI_P], 0.1, 0);
    ASSERT_STR(F.params_reason, "set");
    ASSERT_EQ_INT(F.params_cmd_seq, F.myseq);
    ASSERT_EQ_INT(F.params_cmd_utime, c.utime); /* PARAMS names its command too */
    /* one bad value: nothing applied */
    wg_params before = d->sim.p;
    double bad[2] = {2.0, 5.0};
    c.values = bad;
    ASSERT_EQ_INT(send(d, &c), WG_ERANGE);
    ASSERT_STR(F.code, "ERANGE");
    ASSERT_CONTAINS(F.message, "xi_p");
    ASSERT_CONTAINS(F.message, "[");
    ASSERT_TRUE(memcmp(&before, &d->sim.p, sizeof before) == 0);
    ASSERT_EQ_INT(d->stat.cmds_refused, 1);
    teardown(d);
}

static void test_set_bad_inputs(void)
{
    wgd *d = setup(128);
    wg_params before = d->sim.p;
    ASSERT_EQ_INT(set1(d, "omeg", 1.0), WG_EUNKNOWN);
    ASSERT_CONTAINS(F.message, "omeg");
    ASSERT_EQ_INT(set1(d, "omega", NAN), WG_ERANGE);
    ASSERT_EQ_INT(set1(d, "omega", INFINITY), WG_ERANGE);
    ASSERT_EQ_INT(set1(d, "b", -1.0), WG_ERANGE);
    char *dup[2] = {"omega", "omega"};
    double v[2] = {1, 2};
    wormgear_cmd_t c = {.op = "set", .nparams = 2, .names = dup, .values = v};
    ASSERT_EQ_INT(send(d, &c), WG_EINVAL);
    wormgear_cmd_t none = {.op = "set"};
    ASSERT_EQ_INT(send(d, &none), WG_EINVAL);
    ASSERT_EQ_INT(simple(d, "explode", ""), WG_EINVAL);
    ASSERT_CONTAINS(F.message, "unknown op");
    ASSERT_EQ_INT(set1(d, "a1", 0.9), WG_ERANGE); /* a1^2 + a2^2 + a3^2 = 1 broken */
    /* a flag other than 0 or 1: refused, whatever the op */
    char *om[1] = {"omega"};
    double v15[1] = {1.5};
    wormgear_cmd_t flag = {.op = "set", .nparams = 1, .names = om, .values = v15, .at_section = 7};
    ASSERT_EQ_INT(send(d, &flag), WG_EINVAL);
    ASSERT_CONTAINS(F.message, "each flag is 0 or 1");
    flag.at_section = 0, flag.has_from = -3;
    ASSERT_EQ_INT(send(d, &flag), WG_EINVAL);
    ASSERT_TRUE(memcmp(&before, &d->sim.p, sizeof before) == 0);
    /* still healthy: a good command goes through and the sim steps */
    ASSERT_EQ_INT(set1(d, "omega", 1.2), WG_OK);
    run(d, 1000);
    ASSERT_TRUE(!d->fault);
    teardown(d);
}

/* N = 16 is too coarse for a slow omega: ESTABILITY, nothing changed. */
static void test_set_stability(void)
{
    wgd *d = setup(16);
    wg_params before = d->sim.p;
    int rc = set1(d, "omega", 0.05);
    ASSERT_EQ_INT(rc, WG_ESTABILITY);
    ASSERT_CONTAINS(F.message, "need N >=");
    ASSERT_TRUE(memcmp(&before, &d->sim.p, sizeof before) == 0);
    teardown(d);
}

static void test_accept_commands_off(void)
{
    wgd *d = setup(128);
    d->conf.accept_commands = 0;
    ASSERT_EQ_INT(set1(d, "omega", 1.3), WG_ESTATE);
    ASSERT_CONTAINS(F.message, "accept_commands");
    ASSERT_EQ_INT(simple(d, "get", ""), WG_OK);
    ASSERT_STR(F.params_reason, "get");
    teardown(d);
}

/* set with at_section: validated at once, applied and ACKed on the next
 * Poincare section's step boundary, never mid-period. */
static void test_set_at_section(void)
{
    wgd *d = setup(128);
    run(d, 128 * 10 + 37); /* mid-period: k = 37 */
    ASSERT_EQ_INT(d->sim.k, 37);
    char *n[1] = {(char *)"omega"};
    double v = 1.3, bad = 99;
    wormgear_cmd_t c = {.op = "set", .nparams = 1, .names = n, .values = &v, .at_section = 1};
    send_pending(d, &c);
    ASSERT_TRUE(d->sync.active);
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.0, 0); /* not yet */
    /* a second one waits its turn: refused; an out-of-range one at once */
    wormgear_cmd_t c2 = {.op = "set", .nparams = 1, .names = n, .values = &v, .at_section = 1};
    ASSERT_EQ_INT(send(d, &c2), WG_ESTATE);
    ASSERT_CONTAINS(F.message, "already pending");
    ASSERT_EQ_INT(cmd_run(d, 128 - 37 - 1), 128 - 37 - 1); /* one step short */
    drain(d);
    ASSERT_TRUE(d->sync.active);
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.0, 0);
    int before = F.nack;
    double tau_section = d->sim.tau + d->sim.h; /* the next step ends the period */
    ASSERT_EQ_INT(cmd_run(d, 5), 5);
    drain(d);
    ASSERT_EQ_INT(F.nack, before + 1);
    ASSERT_EQ_INT(F.cmd_seq, c.seq);
    ASSERT_EQ_INT(F.cmd_utime, c.utime); /* a deferred ACK names its command too */
    ASSERT_EQ_INT(F.params_cmd_utime, c.utime);
    ASSERT_EQ_INT(F.rc, WG_OK);
    ASSERT_NEAR(F.ack_tau, tau_section, 1e-9); /* took effect at the section */
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.3, 0);
    ASSERT_EQ_INT(d->sim.k, 4);
    ASSERT_TRUE(!d->sync.active);
    /* refused on arrival when invalid, immediate at a section, reset cancels */
    c2.values = &bad;
    ASSERT_EQ_INT(send(d, &c2), WG_ERANGE);
    run(d, 124); /* k = 0 */
    v = 1.25;
    ASSERT_EQ_INT(send(d, &c2), WG_ERANGE);
    c2.values = &v;
    ASSERT_EQ_INT(send(d, &c2), WG_OK);
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.25, 0);
    run(d, 3);
    send_pending(d, &c);
    wormgear_cmd_t rs = {.op = "reset", .client = "tester", .unit = "", .name = "",
                         .seq = ++F.myseq};
    before = F.nack;
    wormgear_cmd_t_publish(d->io.lcm, "T_CMD", &rs);
    drain(d);
    ASSERT_EQ_INT(F.nack, before + 2); /* the pending set refused (ESTATE), then the reset */
    ASSERT_EQ_INT(F.cmd_seq, rs.seq);
    ASSERT_EQ_INT(F.rc, WG_OK);
    ASSERT_TRUE(!d->sync.active);
    wormgear_cmd_t r = {.op = "ramp", .nparams = 1, .names = n, .values = &v, .duration = 10,
                        .unit = "tau", .at_section = 1};
    ASSERT_EQ_INT(send(d, &r), WG_EINVAL);
    teardown(d);
}

/* Paused mid-period no section comes: a set --at-section went unanswered
 * (wgctl timed out) and was applied at some later resume. Refused now
 * (ESTATE, one ACK, nothing pending), unless a running step command
 * reaches the section; on a section it applies at once, as when running. */
static void test_set_at_section_paused(void)
{
    wgd *d = setup(128);
    run(d, 128 * 3 + 100); /* k = 100: 28 steps before the section */
    char *n[1] = {(char *)"omega"};
    double v = 1.3;
    wormgear_cmd_t c = {.op = "set", .nparams = 1, .names = n, .values = &v, .at_section = 1};
    ASSERT_EQ_INT(simple(d, "pause", ""), WG_OK);
    ASSERT_EQ_INT(send(d, &c), WG_ESTATE);
    ASSERT_CONTAINS(F.message, "no Poincare section comes while the run is paused");
    ASSERT_CONTAINS(F.message, "28 steps before the next section");
    ASSERT_CONTAINS(F.message, "resume first, or set without at_section");
    ASSERT_TRUE(!d->sync.active);
    ASSERT_EQ_INT(simple(d, "resume", ""), WG_OK);
    run(d, 128);
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.0, 0); /* nothing was left waiting */
    /* one pending when the pause comes: refused then (its own ACK, before
     * the pause's); it was applied at a later resume */
    send_pending(d, &c);
    ASSERT_TRUE(d->sync.active);
    int nack0 = F.nack;
    wormgear_cmd_t pz = {.op = "pause", .client = "tester", .unit = "", .name = "",
                         .seq = ++F.myseq};
    wormgear_cmd_t_publish(d->io.lcm, "T_CMD", &pz);
    drain(d);
    ASSERT_EQ_INT(F.nack, nack0 + 2);
    ASSERT_EQ_INT(F.cmd_seq, pz.seq);
    ASSERT_TRUE(!d->sync.active);
    ASSERT_EQ_INT(simple(d, "resume", ""), WG_OK);
    run(d, 128);
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.0, 0);
    /* paused, a step command that stops short of the section: refused */
    ASSERT_EQ_INT(simple(d, "pause", ""), WG_OK);
    wormgear_cmd_t s = {.op = "step", .nsteps = 1000000000000LL};
    send_pending(d, &s); /* its first 1000 steps run at once */
    uint64_t to = (128 - d->sim.k) % 128;
    ASSERT_TRUE(to > 0);
    d->step.left = to - 1; /* as if it had been given fewer steps */
    ASSERT_EQ_INT(send(d, &c), WG_ESTATE);
    /* ... one that reaches it: pending, applied and ACKed at the section */
    d->step.left = to;
    send_pending(d, &c);
    ASSERT_TRUE(d->sync.active);
    int before = F.nack;
    cmd_step_progress(d, 1000);
    drain(d);
    ASSERT_EQ_INT(F.nack, before + 2); /* the set's ACK at the section, then the step's */
    ASSERT_TRUE(!d->step.active && !d->sync.active);
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.3, 0);
    /* paused on a section: applied at once */
    ASSERT_EQ_INT(d->sim.k, 0);
    v = 1.2;
    ASSERT_EQ_INT(send(d, &c), WG_OK);
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.2, 0);
    teardown(d);
}

static void test_step_and_modes(void)
{
    wgd *d = setup(128);
    uint64_t s0 = d->sim.steps;
    wormgear_cmd_t c = {.op = "step", .nsteps = 500};
    ASSERT_EQ_INT(send(d, &c), WG_OK); /* lockstep: ACK once the steps are done */
    ASSERT_EQ_INT(d->sim.steps, s0 + 500);
    ASSERT_CONTAINS(F.message, "500");
    c.nsteps = 0;
    ASSERT_EQ_INT(send(d, &c), WG_ERANGE);
    /* a long step completes from the loop: the ACK waits for it */
    c.nsteps = 300000;
    int n0 = F.nack;
    wormgear_cmd_t_publish(d->io.lcm, "T_CMD", &(wormgear_cmd_t){.seq = ++F.myseq,
        .utime = 4242, .client = "tester", .op = "step", .nsteps = 300000, .unit = "",
        .name = ""});
    drain(d);
    ASSERT_EQ_INT(F.nack, n0);
    ASSERT_TRUE(d->step.active);
    c.nsteps = 10;
    ASSERT_EQ_INT(send(d, &c), WG_ESTATE); /* one at a time */
    while (d->step.active)
        cmd_step_progress(d, 50000);
    drain(d);
    ASSERT_EQ_INT(F.nack, n0 + 2);
    ASSERT_EQ_INT(F.cmd_seq, F.myseq - 1);
    ASSERT_EQ_INT(F.cmd_utime, 4242); /* the step's ACK, when it comes, names it */
    ASSERT_EQ_INT(F.rc, WG_OK);
    ASSERT_EQ_INT(d->sim.steps, s0 + 500 + 300000);
    /* realtime and running: step refused; paused: allowed */
    wormgear_cmd_t m = {.op = "mode", .name = "realtime", .rate = 0.5};
    ASSERT_EQ_INT(send(d, &m), WG_OK);
    ASSERT_NEAR(d->conf.rate, 0.5, 0);
    m.rate = 1e9;
    ASSERT_EQ_INT(send(d, &m), WG_ERANGE);
    ASSERT_STR(F.message, "rate: '1000000000' must be a number in [1e-06, 1000]");
    m.name = "warp";
    ASSERT_EQ_INT(send(d, &m), WG_EINVAL);
    ASSERT_EQ_INT(send(d, &c), WG_ESTATE);
    ASSERT_EQ_INT(simple(d, "pause", ""), WG_OK);
    ASSERT_EQ_INT(send(d, &c), WG_OK);
    ASSERT_EQ_INT(simple(d, "resume", ""), WG_OK);
    ASSERT_EQ_INT(d->run, RUN_RUNNING);
    /* reset: tau back to 0; with "params" also the scene's parameters */
    ASSERT_EQ_INT(set1(d, "omega", 1.7), WG_OK);
    ASSERT_EQ_INT(simple(d, "reset", ""), WG_OK);
    ASSERT_NEAR(d->sim.tau, 0, 0);
    ASSERT_EQ_INT(d->sim.steps, 0);
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.7, 0);
    ASSERT_EQ_INT(simple(d, "reset", "params"), WG_OK);
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], d->scene_params.v[WG_P_OMEGA], 0);
    ASSERT_EQ_INT(simple(d, "reset", "everything"), WG_EINVAL);
    teardown(d);
}

static int mode(wgd *d, const char *name)
{
    wormgear_cmd_t m = {.op = "mode", .name = (char *)name};
    return send(d, &m);
}

/* A long step command, started and left running. */
static void long_step(wgd *d)
{
    wormgear_cmd_t s = {.op = "step", .nsteps = 1000000000000LL};
    send_pending(d, &s);
    ASSERT_TRUE(d->step.active);
}

/* pause with a step running: two ACKs, the step's refusal (ESTATE) and
 * then the pause's; returns the pause's code. */
static int pause_cancelling(wgd *d)
{
    wormgear_cmd_t p = {.op = "pause", .client = "tester", .unit = "", .name = "",
                        .seq = ++F.myseq};
    int before = F.nack;
    uint64_t refused = d->stat.cmds_refused;
    wormgear_cmd_t_publish(d->io.lcm, "T_CMD", &p);
    drain(d);
    ASSERT_EQ_INT(F.nack, before + 2);
    ASSERT_EQ_INT(F.cmd_seq, p.seq);
    ASSERT_EQ_INT(d->stat.cmds_refused, refused + 1);
    return F.rc;
}

/* resume during a step said "running from tau ..." while STATUS said
 * stepping and the step went on; pause said "paused" and it went on too.
 * Now resume is refused (ESTATE, how to stop the step) and pause cancels
 * the step (its ACK: ESTATE), paused or in lockstep alike. */
static void test_step_pause_resume(void)
{
    wgd *d = setup(128);
    ASSERT_EQ_INT(mode(d, "realtime"), WG_OK);
    ASSERT_EQ_INT(simple(d, "pause", ""), WG_OK);
    long_step(d);
    ASSERT_EQ_INT(simple(d, "resume", ""), WG_ESTATE);
    ASSERT_CONTAINS(F.message, "a step command is running (");
    ASSERT_CONTAINS(F.message, "pause cancels it");
    ASSERT_EQ_INT(d->run, RUN_PAUSED); /* nothing changed */
    ASSERT_TRUE(d->step.active);
    ASSERT_STR(report_run_name(d), "stepping");
    cmd_step_progress(d, 5000);
    ASSERT_EQ_INT(pause_cancelling(d), WG_OK);
    ASSERT_CONTAINS(F.message, "the step command was cancelled after 6000 of 1000000000000 steps");
    ASSERT_TRUE(!d->step.active);
    ASSERT_STR(report_run_name(d), "paused");
    uint64_t steps = d->sim.steps;
    ASSERT_EQ_INT(cmd_step_progress(d, 1000), 0);
    ASSERT_EQ_INT(d->sim.steps, steps);
    ASSERT_EQ_INT(simple(d, "resume", ""), WG_OK); /* no step: resume as before */
    /* lockstep, running: the same */
    ASSERT_EQ_INT(mode(d, "lockstep"), WG_OK);
    long_step(d);
    ASSERT_EQ_INT(simple(d, "resume", ""), WG_ESTATE);
    ASSERT_TRUE(d->step.active);
    ASSERT_EQ_INT(pause_cancelling(d), WG_OK);
    ASSERT_TRUE(!d->step.active);
    teardown(d);
}

static void tick(wgd *d, int64_t seq, int64_t nsteps)
{
    wormgear_tick_t t = {.utime = (int64_t)(1000 + (uint64_t)seq), .seq = seq, .nsteps = nsteps,
                         .client = (char *)"rig-7"};
    wormgear_tick_t_publish(d->io.lcm, "T_TICK", &t);
    drain(d);
}

/* Issue 10, defects 3 and 6: TICK seq is wrap-safe (INT64_MAX, jumps, going
 * back), one gap counts at most a bound and a larger jump is a new sender;
 * a TICK only owes steps, which run in bounded chunks (the loop's job), so
 * a command is answered while a 1e7-step tick is still being worked off. */
static void test_ticks(void)
{
    wgd *d = setup(128);
    static const int64_t seqs[] = {0, INT64_MAX, INT64_MIN, 5, 1000000000005LL, -7, 6, 10};
    int nack = F.nack;
    for (unsigned i = 0; i < sizeof seqs / sizeof seqs[0]; i++)
        tick(d, seqs[i], 1);
    ASSERT_EQ_INT(F.nack, nack); /* a tick taken has no answer */
    /* 0 -> MAX: new sender; MAX -> MIN: in order (wraps); MIN -> 5: new; 5 -> 1e12+5:
     * new; -> -7: new (backwards); -7 -> 6: 12 lost; 6 -> 10: 3 lost */
    ASSERT_EQ_INT(d->stat.tick_gaps, 15);
    ASSERT_EQ_INT(d->stat.tick_senders, 4);
    ASSERT_EQ_INT(d->owed.ticks, 8);
    tick(d, 11, 10000000);
    ASSERT_EQ_INT(d->owed.ticks, 10000008);
    ASSERT_EQ_INT(d->sim.steps, 0); /* nothing ran in the LCM callback */
    ASSERT_EQ_INT(simple(d, "get", ""), WG_OK); /* answered with 1e7 steps owed */
    uint64_t done = lockstep_progress(d, 1000);
    ASSERT_EQ_INT(done, 1000);
    ASSERT_EQ_INT(d->owed.ticks, 10000008 - 1000);
    ASSERT_EQ_INT(d->stat.ticks_refused, 0);
    nack = F.nack; /* after the get's */
    tick(d, 12, 0); /* out of range: refused, with one answer naming the tick */
    ASSERT_EQ_INT(d->owed.ticks, 10000008 - 1000);
    ASSERT_EQ_INT(d->stat.ticks_refused, 1);
    ASSERT_STR(d->stat.tick_why, "TICK (seq 12, 0 steps) refused: a tick owes 1 to 10000000 steps");
    ASSERT_EQ_INT(F.nack, nack + 1);
    ASSERT_STR(F.op, "tick");
    ASSERT_STR(F.client, "rig-7");
    ASSERT_EQ_INT(F.cmd_seq, 12);
    ASSERT_EQ_INT(F.cmd_utime, 1012);
    ASSERT_EQ_INT(F.accepted, 0);
    ASSERT_STR(F.code, "ERANGE");
    ASSERT_STR(F.message, d->stat.tick_why);
    tick(d, 13, 10000001);
    ASSERT_EQ_INT(d->stat.ticks_refused, 2);
    for (int i = 0; i < 120; i++) /* up to the limit of owed steps */
        tick(d, 14 + i, 10000000);
    ASSERT_TRUE(d->owed.ticks <= 1000000000);
    ASSERT_EQ_INT(d->stat.ticks_refused, 2 + 21); /* 99 of the 120 fitted */
    ASSERT_CONTAINS(d->stat.tick_why, "TICK (seq 133, 10000000 steps) refused: 999999008 steps "
                    "from earlier ticks still to run, at most 1e+09 may be owed");
    ASSERT_EQ_INT(F.nack, nack + 23); /* one answer each refused, none for those taken */
    ASSERT_STR(F.code, "ESTATE");
    ASSERT_EQ_INT(F.cmd_seq, 133);
    report_status(d);
    drain(d);
    ASSERT_EQ_INT(F.ticks_refused, 23);
    ASSERT_STR(F.tick_refusal, d->stat.tick_why);
    ASSERT_EQ_INT(F.ticks_lost, 15); /* the gaps; not the refusals */
    ASSERT_EQ_INT(F.msgs_dropped, 0); /* every message published */
    ASSERT_EQ_INT(simple(d, "pause", ""), WG_OK); /* a stopped run: owed ticks lapse */
    ASSERT_EQ_INT(lockstep_progress(d, 1000), 0);
    ASSERT_EQ_INT(d->owed.ticks, 0);
    tick(d, 134, 5); /* paused: lapses, not refused (STATUS run says why) */
    ASSERT_EQ_INT(d->stat.ticks_refused, 23);
    tick(d, 135, -1); /* refused whatever the run */
    ASSERT_EQ_INT(d->stat.ticks_refused, 24);
    teardown(d);
}

/* A refused tick changes nothing else (PROTOCOL.md), the seq count
 * included: one refused ERANGE at seq 100002 after 0 ... 2 (a stray's, a
 * forger's) put 99999 into ticks_lost and moved the seq expected, so the
 * rig's real next tick (3) was logged and counted as a new sender. The
 * same for one refused for the backlog (ESTATE), and a rig's own tick
 * refused in its place leaves no hole for its next to be counted lost. */
static void test_tick_refused_not_counted(void)
{
    wgd *d = setup(128);
    for (int64_t q = 0; q < 3; q++)
        tick(d, q, 10);
    tick(d, 3 + 99999, 0); /* refused: ERANGE */
    ASSERT_STR(F.code, "ERANGE");
    ASSERT_EQ_INT(F.cmd_seq, 3 + 99999);
    ASSERT_EQ_INT(d->stat.tick_gaps, 0);
    ASSERT_EQ_INT(d->stat.tick_senders, 0);
    tick(d, 3, 10); /* the rig's next: in order */
    ASSERT_EQ_INT(d->stat.tick_gaps, 0);
    ASSERT_EQ_INT(d->stat.tick_senders, 0);
    ASSERT_EQ_INT(d->owed.ticks, 40);
    d->owed.ticks = 1000000000 - 5; /* as if the rig were 1e9 steps behind */
    int nack = F.nack;
    tick(d, 50000, 10);             /* refused: ESTATE, too many owed */
    tick(d, -7, 10);                /* backwards, refused too */
    ASSERT_EQ_INT(F.nack, nack + 2);
    ASSERT_STR(F.code, "ESTATE");
    ASSERT_EQ_INT(d->stat.ticks_refused, 3);
    d->owed.ticks = 40;
    tick(d, 4, 10);
    ASSERT_EQ_INT(d->stat.tick_gaps, 0);
    ASSERT_EQ_INT(d->stat.tick_senders, 0);
    tick(d, 5, 0); /* the rig's own, refused in its place */
    tick(d, 6, 10);
    ASSERT_EQ_INT(d->stat.ticks_refused, 4);
    ASSERT_EQ_INT(d->owed.ticks, 60);
    report_status(d);
    drain(d);
    ASSERT_EQ_INT(F.ticks_refused, 4);
    ASSERT_EQ_INT(F.ticks_lost, 0); /* none was lost on the way */
    ASSERT_EQ_INT(d->stat.tick_senders, 0);
    tick(d, 9, 10); /* a real gap still counts */
    ASSERT_EQ_INT(d->stat.tick_gaps, 2);
    teardown(d);
}

/* Owed steps lapse when the run pauses or leaves lockstep (PROTOCOL.md):
 * they were kept (only the loop's own call noticed, and the loop never
 * called it while paused), so 100 ticks of 1e7 steps ran on after a pause
 * and resume, or after realtime and back. STATUS said "waiting" meanwhile:
 * the run is "stepping" while steps are owed. */
static void test_ticks_lapse(void)
{
    wgd *d = setup(128);
    ASSERT_STR(report_run_name(d), "waiting");
    for (int i = 0; i < 100; i++)
        tick(d, i, 10000000);
    ASSERT_EQ_INT(d->owed.ticks, 1000000000);
    ASSERT_STR(report_run_name(d), "stepping");
    ASSERT_EQ_INT(lockstep_progress(d, 1000), 1000);
    ASSERT_EQ_INT(simple(d, "pause", ""), WG_OK);
    ASSERT_EQ_INT(d->owed.ticks, 0); /* at once, not when the loop next looks */
    ASSERT_STR(report_run_name(d), "paused");
    ASSERT_EQ_INT(simple(d, "resume", ""), WG_OK);
    ASSERT_EQ_INT(d->owed.ticks, 0);
    ASSERT_STR(report_run_name(d), "waiting");
    /* leaving lockstep: they lapse; coming back does not bring them back */
    tick(d, 100, 10000000);
    ASSERT_EQ_INT(d->owed.ticks, 10000000);
    ASSERT_EQ_INT(mode(d, "realtime"), WG_OK);
    ASSERT_EQ_INT(d->owed.ticks, 0);
    ASSERT_EQ_INT(mode(d, "lockstep"), WG_OK);
    ASSERT_EQ_INT(d->owed.ticks, 0);
    ASSERT_STR(report_run_name(d), "waiting");
    /* lockstep to lockstep is not leaving it: kept */
    tick(d, 101, 5000);
    ASSERT_EQ_INT(mode(d, "lockstep"), WG_OK);
    ASSERT_EQ_INT(d->owed.ticks, 5000);
    /* a fault pauses the run: they lapse too */
    engine_fault(d, "test fault");
    ASSERT_EQ_INT(d->owed.ticks, 0);
    /* the pace's owed steps lapse outside realtime alike */
    d->owed.realtime = 123;
    ASSERT_EQ_INT(mode(d, "fast"), WG_OK);
    ASSERT_EQ_INT(d->owed.realtime, 0);
    teardown(d);
}

/* The ACKs one command got (op, seq), however many others come between:
 * the fixture keeps only the last. */
typedef struct acks_of {
    const char *op;
    int64_t seq;
    int n;
    char code[32], message[700];
} acks_of;

static void on_ack_of(const lcm_recv_buf_t *rb, const char *ch, const wormgear_ack_t *m,
                      void *u)
{
    (void)rb, (void)ch;
    acks_of *a = u;
    if (m->cmd_seq != a->seq || strcmp(m->op, a->op))
        return;
    a->n++;
    snprintf(a->code, sizeof a->code, "%s", m->code);
    snprintf(a->message, sizeof a->message, "%s", m->message);
}

/* Paused mid-period, a set at the section waits for a running step
 * command that reaches it; a mode change cancelled that step and left the
 * set waiting, unanswered (its sender timed out), until a later resume
 * applied it. Now whatever takes its section away refuses it at once,
 * once: a mode command (its ACK after the step's, before the mode's), a
 * reload's mode change, a fault (cmd_sync_check); a step cancelled while
 * the run goes on leaves it waiting, as a section still comes. */
static void test_set_at_section_step_cancelled(void)
{
    wgd *d = setup(128);
    run(d, 128 * 3 + 100);
    char *n[1] = {(char *)"omega"};
    double v = 1.1;
    wormgear_cmd_t c = {.op = "set", .nparams = 1, .names = n, .values = &v, .at_section = 1};
    acks_of got = {.op = "set"};
    void *sub = wormgear_ack_t_subscribe(d->io.lcm, "T_ACK", on_ack_of, &got);
    /* the mode command */
    ASSERT_EQ_INT(simple(d, "pause", ""), WG_OK);
    long_step(d);
    send_pending(d, &c);
    got.seq = c.seq;
    ASSERT_TRUE(d->sync.active);
    wormgear_cmd_t m = {.op = "mode", .client = "tester", .unit = "", .name = "fast",
                        .seq = ++F.myseq};
    int nack = F.nack;
    uint64_t refused = d->stat.cmds_refused;
    wormgear_cmd_t_publish(d->io.lcm, "T_CMD", &m);
    drain(d);
    ASSERT_EQ_INT(F.nack, nack + 3); /* the step's refusal, the set's, the mode's OK */
    ASSERT_EQ_INT(d->stat.cmds_refused, refused + 2);
    ASSERT_EQ_INT(F.cmd_seq, m.seq);
    ASSERT_EQ_INT(F.rc, WG_OK);
    ASSERT_EQ_INT(got.n, 1);
    ASSERT_STR(got.code, "ESTATE");
    ASSERT_CONTAINS(got.message, "set at the next section cancelled by a mode change, which "
                    "cancelled the step command that was to reach it: no Poincare section "
                    "comes while the run is paused (tau ");
    ASSERT_CONTAINS(got.message, "set it again after resume, or without at_section");
    ASSERT_TRUE(!d->sync.active && !d->step.active);
    ASSERT_EQ_INT(simple(d, "resume", ""), WG_OK);
    run(d, 256);
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.0, 0); /* never applied later */
    ASSERT_EQ_INT(got.n, 1);
    /* a reload that changes the mode (loop.c's apply_mode) */
    ASSERT_EQ_INT(mode(d, "lockstep"), WG_OK);
    run(d, 100);
    ASSERT_EQ_INT(simple(d, "pause", ""), WG_OK);
    long_step(d);
    send_pending(d, &c);
    got = (acks_of){.op = "set", .seq = c.seq};
    d->conf.mode = MODE_REALTIME;
    cmd_mode_changed(d, "a mode change (reload)");
    drain(d);
    ASSERT_EQ_INT(got.n, 1);
    ASSERT_STR(got.code, "ESTATE");
    ASSERT_CONTAINS(got.message, "cancelled by a mode change (reload), which cancelled the "
                    "step command");
    ASSERT_TRUE(!d->sync.active);
    /* running, a step cancelled by a mode change: a section still comes */
    ASSERT_EQ_INT(mode(d, "lockstep"), WG_OK);
    ASSERT_EQ_INT(simple(d, "resume", ""), WG_OK);
    run(d, 100);
    long_step(d);
    send_pending(d, &c);
    got = (acks_of){.op = "set", .seq = c.seq};
    m.seq = ++F.myseq;
    nack = F.nack;
    wormgear_cmd_t_publish(d->io.lcm, "T_CMD", &m);
    drain(d);
    ASSERT_EQ_INT(F.nack, nack + 2); /* the step's refusal, the mode's OK */
    ASSERT_TRUE(d->sync.active && !d->step.active);
    ASSERT_EQ_INT(got.n, 0);
    run(d, 128);
    ASSERT_EQ_INT(got.n, 1);
    ASSERT_STR(got.code, "OK");
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.1, 0);
    /* a fault outside the step path (loop.c: overrun_policy = stop) */
    run(d, 50);
    v = 1.2;
    send_pending(d, &c);
    got = (acks_of){.op = "set", .seq = c.seq};
    engine_fault(d, "test fault");
    cmd_sync_check(d, "the overrun stop");
    drain(d);
    ASSERT_EQ_INT(got.n, 1);
    ASSERT_STR(got.code, "ESTATE");
    ASSERT_CONTAINS(got.message, "set at the next section cancelled by the overrun stop: no "
                    "Poincare section comes");
    ASSERT_EQ_INT(simple(d, "resume", ""), WG_OK);
    run(d, 256);
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.1, 0);
    ASSERT_EQ_INT(got.n, 1);
    wormgear_ack_t_unsubscribe(d->io.lcm, sub);
    teardown(d);
}

TEST_MAIN(TEST(test_set_atomic), TEST(test_set_bad_inputs), TEST(test_set_stability),
          TEST(test_accept_commands_off), TEST(test_set_at_section), TEST(test_step_and_modes),
          TEST(test_ticks), TEST(test_ticks_lapse), TEST(test_step_pause_resume),
          TEST(test_set_at_section_paused), TEST(test_tick_refused_not_counted),
          TEST(test_set_at_section_step_cancelled))

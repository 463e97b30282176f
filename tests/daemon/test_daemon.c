/* test_daemon.c - the daemon's modules in-process on memq://: command
 * validation and atomic apply, decode errors, ramp continuity through the
 * command path, save/restore bit-exact, step, blow-up handling, stream seq. */
#include "cmd.h"
#include "engine.h"
#include "snap.h"
#include "report.h"

/* Each test must tear its daemon down (teardown() clears F.d). */
#define TEST_TEARDOWN_CHECK() ASSERT_TRUE(F.d == NULL)
#include "test.h"
#include "wgd.h"
#include "wire.h"
#include "wormgear/wg_status.h"

#include <unistd.h>

enum { MAXS = 200000 };

typedef struct fx {
    wgd *d;
    int nack;
    int accepted, rc;
    int64_t cmd_seq;
    char client[96], code[32], message[700];
    int nparams_msgs;
    char params_reason[32];
    int64_t params_cmd_seq;
    int64_t seq_next[3], seq_gaps;  /* STATE POINCARE CONTACT */
    int nsamples, npc, nct;
    double *tau, *omega, *xn;        /* STATE samples */
    int64_t pc_last_period;
    int pc_gaps;
    char health[16], regime[24], motion[24];
    double impacts_per_period;
    double ack_tau;
    int nstatus;
    int64_t myseq;
    void *subs[6];
} fx;

static fx F;
static char statedir[] = "/tmp/wgd-test-XXXXXX";

static void on_ack(const lcm_recv_buf_t *rb, const char *ch, const wormgear_ack_t *m, void *u)
{
    (void)rb, (void)ch, (void)u;
    F.nack++;
    F.accepted = m->accepted;
    F.rc = m->status;
    F.cmd_seq = m->cmd_seq;
    F.ack_tau = m->tau;
    snprintf(F.client, sizeof F.client, "%s", m->client);
    snprintf(F.code, sizeof F.code, "%s", m->code);
    snprintf(F.message, sizeof F.message, "%s", m->message);
}

static void on_params(const lcm_recv_buf_t *rb, const char *ch, const wormgear_params_t *m,
                      void *u)
{
    (void)rb, (void)ch, (void)u;
    F.nparams_msgs++;
    snprintf(F.params_reason, sizeof F.params_reason, "%s", m->reason);
    F.params_cmd_seq = m->cmd_seq;
}

static void seqcheck(int i, int64_t seq)
{
    if (seq != F.seq_next[i])
        F.seq_gaps++;
    F.seq_next[i] = seq + 1;
}

static void on_state(const lcm_recv_buf_t *rb, const char *ch, const wormgear_state_t *m, void *u)
{
    (void)rb, (void)ch, (void)u;
    seqcheck(0, m->seq);
    for (int i = 0; i < m->n && F.nsamples < MAXS; i++, F.nsamples++) {
        F.tau[F.nsamples] = m->tau[i];
        F.omega[F.nsamples] = m->omega[i];
        F.xn[F.nsamples] = m->xn[i];
    }
}

static void on_pc(const lcm_recv_buf_t *rb, const char *ch, const wormgear_poincare_t *m, void *u)
{
    (void)rb, (void)ch, (void)u;
    seqcheck(1, m->seq);
    for (int i = 0; i < m->n; i++) {
        if (F.pc_last_period >= 0 && m->period[i] != F.pc_last_period + 1)
            F.pc_gaps++;
        F.pc_last_period = m->period[i];
    }
    F.npc += m->n;
}

static void on_ct(const lcm_recv_buf_t *rb, const char *ch, const wormgear_contact_t *m, void *u)
{
    (void)rb, (void)ch, (void)u;
    seqcheck(2, m->seq);
    F.nct += m->n;
}

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const wormgear_status_t *m,
                      void *u)
{
    (void)rb, (void)ch, (void)u;
    F.nstatus++;
    snprintf(F.health, sizeof F.health, "%s", m->health);
    snprintf(F.regime, sizeof F.regime, "%s", m->regime);
    snprintf(F.motion, sizeof F.motion, "%s", m->motion);
    F.impacts_per_period = m->impacts_per_period;
}

/* A daemon without its loop: engine, lcm (memq), streams, commands, report. */
static wgd *setup(int steps_per_period)
{
    static double tau[MAXS], omega[MAXS], xn[MAXS];
    memset(&F, 0, sizeof F);
    F.tau = tau, F.omega = omega, F.xn = xn;
    F.pc_last_period = -1;
    wgd *d = calloc(1, sizeof *d);
    conf_defaults(&d->conf);
    d->conf.mode = MODE_LOCKSTEP;
    d->conf.steps_per_period = steps_per_period;
    snprintf(d->conf.state_dir, sizeof d->conf.state_dir, "%s", statedir);
    log_init(&d->log, 0);
    d->log.max_prio = LOG_ERR; /* refusals are expected here */
    d->tfd = -1;
    ASSERT_EQ_INT(engine_init(d), WG_OK);
    ASSERT_EQ_INT(lcmio_init(&d->io, "memq://", "T_", d->init_why, sizeof d->init_why),
                  WG_OK);
    stream_init(&d->st, d->sim.nstate, &d->scene.scale, 1);
    ASSERT_EQ_INT(cmd_init(d), WG_OK);
    pace_configure(&d->pace, &d->conf, d->scene.scale.omega_n_rad_s, log_now_ns(),
                   d->sim.tau);
    report_init(d);
    stream_set_decimation(&d->st, 1);
    lcm_t *l = d->io.lcm;
    F.subs[0] = wormgear_ack_t_subscribe(l, "T_ACK", on_ack, NULL);
    F.subs[1] = wormgear_params_t_subscribe(l, "T_PARAMS", on_params, NULL);
    F.subs[2] = wormgear_state_t_subscribe(l, "T_STATE", on_state, NULL);
    F.subs[3] = wormgear_poincare_t_subscribe(l, "T_POINCARE", on_pc, NULL);
    F.subs[4] = wormgear_contact_t_subscribe(l, "T_CONTACT", on_ct, NULL);
    F.subs[5] = wormgear_status_t_subscribe(l, "T_STATUS", on_status, NULL);
    F.d = d;
    return d;
}

static void teardown(wgd *d)
{
    lcm_t *l = d->io.lcm;
    wormgear_ack_t_unsubscribe(l, F.subs[0]);
    wormgear_params_t_unsubscribe(l, F.subs[1]);
    wormgear_state_t_unsubscribe(l, F.subs[2]);
    wormgear_poincare_t_unsubscribe(l, F.subs[3]);
    wormgear_contact_t_unsubscribe(l, F.subs[4]);
    wormgear_status_t_unsubscribe(l, F.subs[5]);
    cmd_fini(d);
    lcmio_fini(&d->io);
    engine_fini(d);
    log_fini(&d->log);
    free(d);
    F.d = NULL;
}

static void drain(wgd *d)
{
    while (lcmio_drain(&d->io, 1000) > 0)
        ;
}

/* Publish a command and handle everything up to its ACK; returns its code. */
static int send(wgd *d, wormgear_cmd_t *c)
{
    c->client = c->client ? c->client : (char *)"tester";
    c->op = c->op ? c->op : (char *)"";
    c->unit = c->unit ? c->unit : (char *)"";
    c->name = c->name ? c->name : (char *)"";
    c->seq = ++F.myseq;
    int before = F.nack;
    wormgear_cmd_t_publish(d->io.lcm, "T_CMD", c);
    drain(d);
    ASSERT_EQ_INT(F.nack, before + 1);
    ASSERT_EQ_INT(F.cmd_seq, c->seq);
    return F.rc;
}

/* Publish a command that is answered later; nothing may answer it now. */
static void send_pending(wgd *d, wormgear_cmd_t *c)
{
    c->client = (char *)"tester", c->unit = (char *)"", c->name = (char *)"";
    c->seq = ++F.myseq;
    int before = F.nack;
    wormgear_cmd_t_publish(d->io.lcm, "T_CMD", c);
    drain(d);
    ASSERT_EQ_INT(F.nack, before);
}

static int set1(wgd *d, const char *name, double v)
{
    char *n[1] = {(char *)name};
    wormgear_cmd_t c = {.op = "set", .nparams = 1, .names = n, .values = &v};
    return send(d, &c);
}

static int simple(wgd *d, const char *op, const char *name)
{
    wormgear_cmd_t c = {.op = (char *)op, .name = (char *)name};
    return send(d, &c);
}

static int ramp(wgd *d, const char *name, int has_from, double from, double to, double dur,
                const char *unit)
{
    char *n[1] = {(char *)name};
    wormgear_cmd_t c = {.op = "ramp", .nparams = 1, .names = n, .values = &to,
                        .has_from = (int8_t)has_from, .from = from, .duration = dur,
                        .unit = (char *)unit};
    return send(d, &c);
}

static void run(wgd *d, uint64_t n)
{
    while (n) {
        uint64_t k = n < 5000 ? n : 5000;
        ASSERT_EQ_INT(cmd_run(d, k), k);
        stream_flush(d);
        drain(d);
        n -= k;
    }
}

/* ---- set: validation and atomic apply ---------------------------------------- */

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

/* ---- undecodable commands ------------------------------------------------------ */

static void test_decode_errors(void)
{
    wgd *d = setup(128);
    unsigned char junk[37];
    for (unsigned i = 0; i < sizeof junk; i++)
        junk[i] = (unsigned char)(i * 37 + 11);
    lcm_publish(d->io.lcm, "T_CMD", junk, sizeof junk);
    drain(d);
    ASSERT_EQ_INT(F.nack, 1);
    ASSERT_STR(F.code, "EDECODE");
    ASSERT_EQ_INT(F.cmd_seq, -1);
    ASSERT_STR(F.client, "");
    ASSERT_CONTAINS(F.message, "unknown");
    /* a real cmd_t cut short: client and seq recovered from its header */
    char *n[1] = {"omega"};
    double v = 1.1;
    wormgear_cmd_t c = {.seq = 4242, .client = "cutter", .op = "set", .nparams = 1,
                        .names = n, .values = &v, .unit = "", .name = ""};
    unsigned char buf[512];
    int len = wormgear_cmd_t_encode(buf, 0, sizeof buf, &c);
    ASSERT_TRUE(len > 50);
    lcm_publish(d->io.lcm, "T_CMD", buf, 50);
    drain(d);
    ASSERT_EQ_INT(F.nack, 2);
    ASSERT_STR(F.code, "EDECODE");
    ASSERT_EQ_INT(F.cmd_seq, 4242);
    ASSERT_STR(F.client, "cutter");
    ASSERT_CONTAINS(F.message, "truncated");
    lcm_publish(d->io.lcm, "T_CMD", buf, 0); /* empty */
    drain(d);
    ASSERT_EQ_INT(F.nack, 3);
    ASSERT_EQ_INT(F.cmd_seq, -1);
    ASSERT_EQ_INT(d->stat.cmds_refused, 3);
    ASSERT_EQ_INT(set1(d, "omega", 1.1), WG_OK); /* still serving */
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

/* ---- raw bytes: the wire check in front of the generated decoder ------------ */

static int encode_full(unsigned char *buf, int max)
{
    char *n[3] = {"omega", "xi_p", "k_a"};
    double v[3] = {1.1, 0.09, 0.3};
    wormgear_cmd_t c = {.seq = 7, .client = "wire", .op = "set", .nparams = 3, .names = n,
                        .values = v, .has_from = 1, .from = 2, .duration = 3, .unit = "s",
                        .nsteps = 9, .name = "x", .rate = 1};
    return wormgear_cmd_t_encode(buf, 0, max, &c);
}

static void test_wire_check(void)
{
    unsigned char buf[1024];
    char why[160];
    int len = encode_full(buf, sizeof buf);
    ASSERT_EQ_INT(wire_cmd_check(buf, (size_t)len, why, sizeof why), WG_OK);
    for (int cut = 0; cut < len; cut++) /* every strict prefix is refused */
        ASSERT_EQ_INT(wire_cmd_check(buf, (size_t)cut, why, sizeof why), WG_EDECODE);
    /* nparams (after fingerprint, utime, seq, client, op) set huge / negative */
    size_t at = 24 + 4 + 5 + 4 + 4;
    unsigned char bad[1024];
    memcpy(bad, buf, (size_t)len);
    bad[at] = 0x7f, bad[at + 1] = bad[at + 2] = bad[at + 3] = 0xff;
    ASSERT_EQ_INT(wire_cmd_check(bad, (size_t)len, why, sizeof why), WG_EDECODE);
    ASSERT_CONTAINS(why, "nparams");
    bad[at] = 0xff;
    ASSERT_EQ_INT(wire_cmd_check(bad, (size_t)len, why, sizeof why), WG_EDECODE);
    memcpy(bad, buf, (size_t)len);
    bad[24] = 0x80; /* client length negative */
    ASSERT_EQ_INT(wire_cmd_check(bad, (size_t)len, why, sizeof why), WG_EDECODE);
    ASSERT_CONTAINS(why, "string length");
    memcpy(bad, buf, (size_t)len);
    bad[28 + 4] = 'X'; /* the client's NUL */
    ASSERT_EQ_INT(wire_cmd_check(bad, (size_t)len, why, sizeof why), WG_EDECODE);
    ASSERT_CONTAINS(why, "NUL");
    char client[65];
    int64_t seq;
    wire_cmd_header(buf, 40, client, sizeof client, &seq);
    ASSERT_STR(client, "wire");
    ASSERT_EQ_INT(seq, 7);
}

/* Random corruption of a valid command: every message gets exactly one ACK,
 * nothing crashes or leaks (run under ASan), the daemon keeps serving. */
static void test_fuzz_one_ack_each(void)
{
    wgd *d = setup(128);
    unsigned char buf[1024], m[1024];
    int len = encode_full(buf, sizeof buf);
    unsigned seed = 20240611u;
    printf("  fuzz seed %u\n", seed);
    for (int i = 0; i < 1000; i++) {
        memcpy(m, buf, (size_t)len);
        for (int k = 0; k < 1 + i % 4; k++) {
            seed = seed * 1103515245u + 12345u;
            m[(seed >> 8) % (unsigned)len] ^= (unsigned char)(1u << ((seed >> 4) % 8));
        }
        seed = seed * 1103515245u + 12345u;
        int n0 = F.nack;
        cmd_handle(d, m, (size_t)(i % 7 ? len : (int)((seed >> 8) % (unsigned)len)));
        drain(d);
        ASSERT_EQ_INT(F.nack, n0 + 1);
    }
    ASSERT_EQ_INT(set1(d, "omega", 1.0), WG_OK);
    run(d, 1000);
    teardown(d);
}

/* ---- ramp through the command path --------------------------------------------- */

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

/* ---- save / restore ----------------------------------------------------------- */

typedef struct shot {
    double y[WG_NSTATE_MAX], tau, tau_c;
    uint32_t k;
    uint64_t steps, period;
    wg_params p;
} shot;

static shot take(const wgd *d)
{
    shot s;
    memset(&s, 0, sizeof s);
    memcpy(s.y, d->sim.y, sizeof s.y);
    s.tau = d->sim.tau, s.tau_c = d->sim.tau_c, s.k = d->sim.k;
    s.steps = d->sim.steps, s.period = d->sim.period, s.p = d->sim.p;
    return s;
}

static void bitexact_case(int with_ramp)
{
    wgd *d = setup(128);
    ASSERT_EQ_INT(set1(d, "omega", 1.35), WG_OK); /* an impacting regime */
    run(d, 128 * 50 + 37);
    if (with_ramp)
        ASSERT_EQ_INT(ramp(d, "omega", 0, 0, 1.6, 2000, "tau"), WG_OK);
    run(d, 1001);
    ASSERT_EQ_INT(simple(d, "save", "bx"), WG_OK);
    run(d, 128 * 40);
    shot a = take(d);
    ASSERT_EQ_INT(simple(d, "restore", "bx"), WG_OK);
    ASSERT_STR(F.params_reason, "restore");
    run(d, 128 * 40);
    shot b = take(d);
    ASSERT_TRUE(memcmp(&a, &b, sizeof a) == 0);
    ASSERT_NEAR(b.tau, a.tau, 0);
    ASSERT_NEAR(b.y[0], a.y[0], 0);
    teardown(d);
}

static void test_save_restore_bitexact(void) { bitexact_case(0); }
static void test_save_restore_bitexact_ramp(void) { bitexact_case(1); }

static void test_save_restore_refusals(void)
{
    wgd *d = setup(128);
    const char *bad[] = {"../etc/passwd", "a/b", "..", ".hidden", "", "x y"};
    for (unsigned i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        ASSERT_EQ_INT(simple(d, "save", bad[i]), WG_EINVAL);
        ASSERT_EQ_INT(simple(d, "restore", bad[i]), WG_EINVAL);
    }
    ASSERT_EQ_INT(simple(d, "restore", "never-saved"), WG_EIO);
    /* a snapshot of another N: ESTATE, nothing changed */
    snap s;
    char path[600], why[600];
    snap_take(&s, &d->sim, "table3");
    s.w.steps_per_period = 256;
    ASSERT_EQ_INT(snap_write(&s, statedir, "n256", path, sizeof path, why, sizeof why), WG_OK);
    shot a = take(d);
    ASSERT_EQ_INT(simple(d, "restore", "n256"), WG_ESTATE);
    ASSERT_CONTAINS(F.message, "N = 256");
    shot b = take(d);
    ASSERT_TRUE(memcmp(&a, &b, sizeof a) == 0);
    /* a corrupted file: refused with file:line */
    FILE *f = fopen(path, "a");
    fprintf(f, "param omega = 99\n");
    fclose(f);
    ASSERT_EQ_INT(simple(d, "restore", "n256"), WG_ERANGE);
    ASSERT_CONTAINS(F.message, "n256.wgstate:");
    teardown(d);
}

/* ---- step, pause, reset --------------------------------------------------------- */

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
        .client = "tester", .op = "step", .nsteps = 300000, .unit = "", .name = ""});
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

static void cleanup(void)
{
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", statedir);
    if (system(cmd) != 0)
        fprintf(stderr, "cannot remove %s\n", statedir);
}

static int init_dir(void) { return mkdtemp(statedir) ? 0 : -1; }

#define main tests_main
TEST_MAIN(TEST(test_set_atomic), TEST(test_set_bad_inputs), TEST(test_set_stability),
          TEST(test_decode_errors), TEST(test_wire_check), TEST(test_fuzz_one_ack_each),
          TEST(test_accept_commands_off), TEST(test_ramp_continuity),
          TEST(test_ramp_refused_atomic), TEST(test_save_restore_bitexact),
          TEST(test_save_restore_bitexact_ramp), TEST(test_save_restore_refusals),
          TEST(test_step_and_modes), TEST(test_blowup_fault), TEST(test_stream_seq), TEST(test_status_regime), TEST(test_status_after_set), TEST(test_set_at_section))
#undef main

int main(int argc, char **argv)
{
    if (init_dir()) {
        perror("mkdtemp");
        return 1;
    }
    int rc = tests_main(argc, argv);
    cleanup();
    return rc;
}

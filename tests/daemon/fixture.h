/* fixture.h - the daemon's modules in-process on memq://, for the tests of
 * tests/daemon/: a daemon without its loop (engine, lcm, streams, commands,
 * report) and an LCM listener on every channel it publishes.
 *
 * setup(N) builds it in lockstep mode with a state directory of its own;
 * send() publishes a command and handles everything up to its ACK; run()
 * steps through the daemon's step path (cmd_run). Every test ends with
 * teardown(), and the check after each test proves it did: no daemon left,
 * no half-written snapshot in the state directory (and, from test.h, no
 * file descriptor left open). Header-only (static), like tests/lib's. */
#ifndef WGD_FIXTURE_H
#define WGD_FIXTURE_H

#include "cmd.h"
#include "lockstep.h"
#include "engine.h"
#include "report.h"

/* Each test must tear its daemon down (teardown() clears F.d), and leave
 * no temporary snapshot file behind. */
#define TEST_TEARDOWN_CHECK()                                                             \
    do {                                                                                  \
        ASSERT_TRUE(F.d == NULL);                                                         \
        ASSERT_EQ_INT(fx_temp_files(), 0);                                                \
    } while (0)
#include "test.h"
#include "wgd.h"
#include "wormgear/wg_status.h"

#include <unistd.h>

enum { MAXS = 200000 };

typedef struct fx {
    wgd *d;
    int nack;
    int accepted, rc;
    int64_t cmd_seq, cmd_utime;
    char client[300], code[32], message[700], op[40];
    int nparams_msgs;
    char params_reason[32];
    int64_t params_cmd_seq, params_cmd_utime;
    int64_t seq_next[3], seq_gaps;  /* STATE POINCARE CONTACT */
    int nsamples, npc, nct;
    long pc_bimp[WG_NBEARING];          /* POINCARE: bearing impacts, largest speeds */
    double pc_bvmax[WG_NBEARING];
    int pc_nbearing;
    int nct_by[WG_NCONTACT], ct_every;   /* CONTACT events per contact; last bearing_every */
    double *tau, *omega, *xn, *th1, *th2; /* STATE samples */
    int64_t pc_last_period;
    int pc_gaps;
    char health[16], regime[24], motion[24];
    double impacts_per_period, rtf, steps_per_s;
    int nbearing;
    double bearing_ipp[WG_NBEARING], bearing_vmax[WG_NBEARING];
    double ack_tau;
    int nstatus;
    int64_t msgs_dropped, ticks_refused, ticks_lost; /* STATUS */
    char tick_refusal[512];
    int64_t myseq;
    void *subs[6];
} fx;

static fx F;
static char statedir[] = "/tmp/wgd-test-XXXXXX";

static void fx_cleanup(void)
{
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", statedir);
    if (system(cmd) != 0)
        fprintf(stderr, "cannot remove %s\n", statedir);
}

/* The state directory of this run: made on first use, removed at exit. */
static inline const char *fx_statedir(void)
{
    static int made;
    if (!made) {
        ASSERT_TRUE(mkdtemp(statedir) != NULL);
        made = atexit(fx_cleanup) == 0;
    }
    return statedir;
}

/* Files a save left half-written in the state directory (NAME.tmp.PID). */
static inline int fx_temp_files(void)
{
    DIR *dir = opendir(statedir);
    struct dirent *e;
    int n = 0;
    while (dir && (e = readdir(dir)))
        n += strstr(e->d_name, ".tmp.") != NULL;
    if (dir)
        closedir(dir);
    return n;
}

static void on_ack(const lcm_recv_buf_t *rb, const char *ch, const wormgear_ack_t *m, void *u)
{
    (void)rb, (void)ch, (void)u;
    F.nack++;
    F.accepted = m->accepted;
    F.rc = m->status;
    F.cmd_seq = m->cmd_seq;
    F.cmd_utime = m->cmd_utime;
    F.ack_tau = m->tau;
    snprintf(F.client, sizeof F.client, "%s", m->client); /* up to 299 bytes */
    snprintf(F.code, sizeof F.code, "%s", m->code);
    snprintf(F.op, sizeof F.op, "%s", m->op);
    snprintf(F.message, sizeof F.message, "%s", m->message);
}

static void on_params(const lcm_recv_buf_t *rb, const char *ch, const wormgear_params_t *m,
                      void *u)
{
    (void)rb, (void)ch, (void)u;
    F.nparams_msgs++;
    snprintf(F.params_reason, sizeof F.params_reason, "%s", m->reason);
    F.params_cmd_seq = m->cmd_seq;
    F.params_cmd_utime = m->cmd_utime;
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
        F.th1[F.nsamples] = m->theta1[i];
        F.th2[F.nsamples] = m->theta2[i];
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
        for (int j = 0; j < m->nbearing && j < WG_NBEARING; j++) {
            F.pc_bimp[j] += m->bearing_impacts[i][j];
            F.pc_bvmax[j] = fmax(F.pc_bvmax[j], m->bearing_vmax[i][j]);
        }
        F.pc_nbearing = m->nbearing;
    }
    F.npc += m->n;
}

static void on_ct(const lcm_recv_buf_t *rb, const char *ch, const wormgear_contact_t *m, void *u)
{
    (void)rb, (void)ch, (void)u;
    seqcheck(2, m->seq);
    F.nct += m->n;
    F.ct_every = m->bearing_every;
    for (int i = 0; i < m->n; i++)
        if (m->contact[i] >= 0 && m->contact[i] < WG_NCONTACT)
            F.nct_by[m->contact[i]]++;
}

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const wormgear_status_t *m,
                      void *u)
{
    (void)rb, (void)ch, (void)u;
    F.nstatus++;
    F.msgs_dropped = m->msgs_dropped;
    F.ticks_refused = m->ticks_refused;
    F.ticks_lost = m->ticks_lost;
    snprintf(F.tick_refusal, sizeof F.tick_refusal, "%s", m->tick_refusal);
    snprintf(F.health, sizeof F.health, "%s", m->health);
    snprintf(F.regime, sizeof F.regime, "%s", m->regime);
    snprintf(F.motion, sizeof F.motion, "%s", m->motion);
    F.impacts_per_period = m->impacts_per_period;
    F.rtf = m->rtf, F.steps_per_s = m->steps_per_s;
    F.nbearing = m->nbearing;
    for (int j = 0; j < m->nbearing && j < WG_NBEARING; j++)
        F.bearing_ipp[j] = m->bearing_impacts_per_period[j],
        F.bearing_vmax[j] = m->bearing_impact_vmax[j];
}

/* A daemon without its loop: engine, lcm (memq), streams, commands, report. */
static inline wgd *setup(int steps_per_period)
{
    static double tau[MAXS], omega[MAXS], xn[MAXS], th1[MAXS], th2[MAXS];
    memset(&F, 0, sizeof F);
    F.tau = tau, F.omega = omega, F.xn = xn, F.th1 = th1, F.th2 = th2;
    F.pc_last_period = -1;
    wgd *d = calloc(1, sizeof *d);
    conf_defaults(&d->conf);
    d->conf.mode = MODE_LOCKSTEP;
    d->conf.steps_per_period = steps_per_period;
    snprintf(d->conf.state_dir, sizeof d->conf.state_dir, "%s", fx_statedir());
    log_init(&d->log, 0);
    d->log.max_prio = LOG_ERR; /* refusals are expected here */
    d->tfd = -1;
    ASSERT_EQ_INT(engine_init(d), WG_OK);
    ASSERT_EQ_INT(lcmio_init(&d->io, "memq://", "T_", d->init_why, sizeof d->init_why),
                  WG_OK);
    stream_init(&d->st, d->sim.nstate, &d->scene.scale, 1);
    ASSERT_EQ_INT(cmd_key_init(d), WG_OK); /* as main.c's modules, in order */
    ASSERT_EQ_INT(cmd_init(d), WG_OK);
    ASSERT_EQ_INT(lockstep_init(d), WG_OK);
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

static inline void teardown(wgd *d)
{
    lcm_t *l = d->io.lcm;
    wormgear_ack_t_unsubscribe(l, F.subs[0]);
    wormgear_params_t_unsubscribe(l, F.subs[1]);
    wormgear_state_t_unsubscribe(l, F.subs[2]);
    wormgear_poincare_t_unsubscribe(l, F.subs[3]);
    wormgear_contact_t_unsubscribe(l, F.subs[4]);
    wormgear_status_t_unsubscribe(l, F.subs[5]);
    cmd_fini(d);
    cmd_key_fini(d);
    lcmio_fini(&d->io);
    engine_fini(d);
    log_fini(&d->log);
    free(d);
    F.d = NULL;
}

/* Everything published so far received, and every command handled. */
static inline void drain(wgd *d)
{
    while (lcmio_drain(&d->io, 1000) > 0 || cmd_process(d, INT64_MAX) > 0)
        ;
}

/* Publish a command and handle everything up to its ACK; returns its code. */
static inline int send(wgd *d, wormgear_cmd_t *c)
{
    c->client = c->client ? c->client : (char *)"tester";
    c->op = c->op ? c->op : (char *)"";
    c->unit = c->unit ? c->unit : (char *)"";
    c->name = c->name ? c->name : (char *)"";
    c->seq = ++F.myseq;
    c->utime = c->utime ? c->utime : 1000003 * c->seq; /* a time of its own, echoed */
    int before = F.nack;
    wormgear_cmd_t_publish(d->io.lcm, "T_CMD", c);
    drain(d);
    ASSERT_EQ_INT(F.nack, before + 1);
    ASSERT_EQ_INT(F.cmd_seq, c->seq);
    ASSERT_EQ_INT(F.cmd_utime, c->utime); /* the ACK names the command: client, seq, utime */
    return F.rc;
}

/* Publish a command that is answered later; nothing may answer it now. */
static inline void send_pending(wgd *d, wormgear_cmd_t *c)
{
    c->client = (char *)"tester", c->unit = (char *)"", c->name = (char *)"";
    c->seq = ++F.myseq;
    c->utime = 1000003 * c->seq;
    int before = F.nack;
    wormgear_cmd_t_publish(d->io.lcm, "T_CMD", c);
    drain(d);
    ASSERT_EQ_INT(F.nack, before);
}

static inline int set1(wgd *d, const char *name, double v)
{
    char *n[1] = {(char *)name};
    wormgear_cmd_t c = {.op = "set", .nparams = 1, .names = n, .values = &v};
    return send(d, &c);
}

static inline int simple(wgd *d, const char *op, const char *name)
{
    wormgear_cmd_t c = {.op = (char *)op, .name = (char *)name};
    return send(d, &c);
}

static inline int ramp(wgd *d, const char *name, int has_from, double from, double to,
                       double dur, const char *unit)
{
    char *n[1] = {(char *)name};
    wormgear_cmd_t c = {.op = "ramp", .nparams = 1, .names = n, .values = &to,
                        .has_from = (int8_t)has_from, .from = from, .duration = dur,
                        .unit = (char *)unit};
    return send(d, &c);
}

static inline void run(wgd *d, uint64_t n)
{
    while (n) {
        uint64_t k = n < 5000 ? n : 5000;
        ASSERT_EQ_INT(cmd_run(d, k), k);
        stream_flush(d);
        drain(d);
        n -= k;
    }
}

#endif

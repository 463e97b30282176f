/* test_pair - wg_sim_run_pair advances two sims as wg_sim_run advances
 * each alone, to the bit: states, time, counters, sections, period
 * statistics and events, on every instruction set; with different
 * parameters and N (the paired loop), with different specialisations or a
 * per-step callback (in turn), when one of the two blows up, and when a
 * sink's callback ramps or respecialises a sim mid-run; and the
 * sweep threads' coroutines (lib/duo.h) that pair the runs of several
 * tasks. White box (lib/internal.h, lib/duo.h): it picks the instruction
 * set and checks which loop runs. */
#include "test.h"

#include "duo.h"
#include "internal.h"
#include "kern_fix.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_status.h"

#include <stdlib.h>

typedef struct runrec {
    int nsec;
    double ysec[8][WG_NSTATE_MAX];
    wg_period stats[8];
    double tau[8];
    uint64_t nev;
    double ev_tau; /* of the last event */
} runrec;

static void on_sec(void *ctx, const wg_section *sec)
{
    runrec *r = ctx;
    int i = r->nsec++ % 8;
    memcpy(r->ysec[i], sec->y, sizeof r->ysec[i]);
    r->stats[i] = sec->stats;
    r->tau[i] = sec->tau;
}

static void on_ev(void *ctx, const wg_event *ev)
{
    runrec *r = ctx;
    r->nev++;
    r->ev_tau = ev->tau;
}

static void on_step(void *ctx, const struct wg_sim *s)
{
    (void)ctx;
    (void)s;
}

typedef struct spec {
    const char *scene; /* NULL: the defaults (table3) */
    double omega, xi_p, s0;
    int N, general;    /* general: an on_step sink forces the general step */
    uint64_t n;        /* steps to run */
} spec;

/* A sim for sp on instruction set isa, with rk4-event (rk4: the plain rk4
 * stepper, whose dead zones are min/max instead of zone-locked); isa -1:
 * the sets a user gets, with no WG_ISA (on an Intel CPU with AVX-512, the
 * batched loop's AVX-512 and the run's own kernels' 4-wide set). */
static void sim_of_stepper(const spec *sp, int isa, int rk4, wg_sim *s)
{
    wg_params p;
    wg_params_default(&p);
    if (sp->scene) {
        wg_scene sc;
        char why[600];
        ASSERT_EQ_INT(wg_scene_open(&sc, sp->scene, why, sizeof why), WG_OK);
        p = sc.p;
    }
    p.v[WG_P_OMEGA] = sp->omega;
    p.v[WG_P_XI_P] = sp->xi_p;
    /* as kfix_sim_on, with either stepper, or with no WG_ISA */
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, rk4 ? WG_STEPPER_RK4 : WG_STEPPER_RK4_EVENT, sp->N};
    char why[300];
    if (isa >= 0)
        ASSERT_TRUE(setenv("WG_ISA", kernel_isa_name(isa), 1) == 0);
    else
        unsetenv("WG_ISA");
    ASSERT_EQ_INT(wg_sim_init(s, &p, &cfg, why, sizeof why), WG_OK);
    unsetenv("WG_ISA");
    if (isa >= 0) {
        ASSERT_EQ_INT(s->core->isa, isa);
    } else {
        ASSERT_EQ_INT(s->core->isa, kernel_isa_choose());
        ASSERT_EQ_INT(s->core->isa_one, kernel_isa_one(kernel_isa_choose()));
        /* the run's own kernels are the isa_one set's (every set gives the
         * same bits, so only this tells which one runs) */
        ASSERT_TRUE(s->core->kernel == kernel_select(s->core->kflags, s->core->isa_one));
        ASSERT_TRUE(s->core->krun == krun_select(s->core->kflags, s->core->isa_one));
    }
    if (sp->s0 != 0.0) {
        double y0[WG_NSTATE_MAX] = {0};
        y0[6] = sp->s0;
        wg_sim_set_state(s, y0, 0, 0.0);
    }
}

static void sim_of(const spec *sp, int isa, wg_sim *s) { sim_of_stepper(sp, isa, 0, s); }

/* a and p ran the same steps to the same bits: state, time, phase,
 * counters, events, the period in progress, and what their sinks saw. */
static void same_run(const wg_sim *a, const wg_sim *p, const runrec *ra, const runrec *rp)
{
    ASSERT_TRUE(memcmp(a->y, p->y, sizeof a->y) == 0);
    ASSERT_TRUE(a->tau == p->tau && a->tau_c == p->tau_c);
    ASSERT_TRUE(a->k == p->k && a->period == p->period && a->steps == p->steps);
    ASSERT_TRUE(a->nsplit == p->nsplit);
    ASSERT_TRUE(memcmp(a->nevents, p->nevents, sizeof a->nevents) == 0);
    ASSERT_TRUE(memcmp(&a->core->cur, &p->core->cur, sizeof a->core->cur) == 0);
    ASSERT_TRUE(memcmp(ra, rp, sizeof *ra) == 0);
}

/* Runs a and b by wg_sim_run_pair until one is done or fails, then the
 * other alone: each call must return as soon as either is. */
static void run_paired(wg_sim *s[2], const spec sp[2], runrec r[2], uint64_t done[2], int rc[2])
{
    wg_sink sk[2];
    const wg_sink *skp[2] = {&sk[0], &sk[1]};
    for (int j = 0; j < 2; j++) {
        memset(&r[j], 0, sizeof r[j]);
        sk[j] = (wg_sink){&r[j], sp[j].general ? on_step : NULL, on_sec, on_ev};
        done[j] = 0;
        rc[j] = WG_OK;
    }
    int calls = 0;
    while (done[0] < sp[0].n && done[1] < sp[1].n && !rc[0] && !rc[1]) {
        uint64_t left[2] = {sp[0].n - done[0], sp[1].n - done[1]}, d[2] = {9, 9};
        wg_sim_run_pair(s, left, skp, d, rc);
        ASSERT_TRUE(d[0] == left[0] || d[1] == left[1] || rc[0] || rc[1]);
        ASSERT_TRUE(d[0] <= left[0] && d[1] <= left[1]);
        done[0] += d[0], done[1] += d[1];
        calls++;
    }
    ASSERT_TRUE(calls == 1);
    for (int j = 0; j < 2; j++) {
        if (rc[j] || done[j] == sp[j].n)
            continue;
        uint64_t d = 0;
        rc[j] = wg_sim_run(s[j], sp[j].n - done[j], &sk[j], &d);
        done[j] += d;
    }
}

/* Each of the two specs alone, then both paired, on every instruction set:
 * the same bits. want_rc: the status each run must end with. */
static void check_pair(const spec sp[2], const int want_rc[2], int paired_loop)
{
    for (int isa = 0; isa < KISA_N; isa++) {
        if (!kernel_isa_supported(isa))
            continue;
        wg_sim alone[2], pa, pb, *both[2] = {&pa, &pb};
        runrec ra[2], rp[2];
        uint64_t da[2], dp[2];
        int rca[2], rcp[2];
        for (int j = 0; j < 2; j++) {
            sim_of(&sp[j], isa, &alone[j]);
            memset(&ra[j], 0, sizeof ra[j]);
            wg_sink sk = {&ra[j], sp[j].general ? on_step : NULL, on_sec, on_ev};
            da[j] = 0;
            rca[j] = wg_sim_run(&alone[j], sp[j].n, &sk, &da[j]);
            ASSERT_EQ_INT(rca[j], want_rc[j]);
            sim_of(&sp[j], isa, both[j]);
        }
        wg_krun2_fn f = krun2_select(pa.core->kflags, isa);
        ASSERT_EQ_INT(f != NULL && pa.core->kflags == pb.core->kflags, paired_loop);
        run_paired(both, sp, rp, dp, rcp);
        for (int j = 0; j < 2; j++) {
            const wg_sim *a = &alone[j], *p = both[j];
            ASSERT_EQ_INT(rcp[j], rca[j]);
            ASSERT_TRUE(dp[j] == da[j]);
            same_run(a, p, &ra[j], &rp[j]);
            wg_sim_fini(&alone[j]);
            wg_sim_fini(both[j]);
        }
        printf("%s: %llu and %llu steps, %llu and %llu events, rc %d and %d: equal\n",
               kernel_isa_name(isa), (unsigned long long)da[0], (unsigned long long)da[1],
               (unsigned long long)ra[0].nev, (unsigned long long)ra[1].nev, rca[0], rca[1]);
    }
}

/* table3 impacting (omega 0.7, N 128) beside table3 without impacts
 * (omega 0.5, another xi_p, N 256), a period and a few steps shorter: the
 * paired loop, stopping for the one's splits and period ends. */
static void test_pair_differs_in_params(void)
{
    const spec sp[2] = {{NULL, 0.7, 0.10, 0, 128, 0, 60 * 128},
                        {NULL, 0.5, 0.08, 0, 256, 0, 29 * 256 + 5}};
    const int ok[2] = {WG_OK, WG_OK};
    check_pair(sp, ok, 1);
    const spec rev[2] = {sp[1], sp[0]}; /* and the other one first */
    check_pair(rev, ok, 1);
}

/* Different specialisations (the torsional scene, no pairing), and a
 * per-step callback on one side: the two run in turn. */
static void test_pair_in_turn(void)
{
    const int ok[2] = {WG_OK, WG_OK};
    const spec mixed[2] = {{"torsional", 1.0, 0.10, 0, 128, 0, 40 * 128},
                           {NULL, 0.7, 0.10, 0, 128, 0, 50 * 128 + 3}};
    check_pair(mixed, ok, 0);
    const spec general[2] = {{NULL, 0.7, 0.10, 0, 128, 1, 30 * 128},
                             {NULL, 1.45, 0.12, 0, 128, 0, 45 * 128}};
    check_pair(general, ok, 1);
}

/* One of the two blows up (from s = 6e8, past the bound at its second
 * step, taken by the general step): it stops with WG_ENONFINITE at the step where it stops alone,
 * the pair returns, and the other's run is unchanged. */
static void test_pair_blowup(void)
{
    const spec sp[2] = {{NULL, 0.7, 0.10, 6e8, 128, 0, 8 * 128},
                        {NULL, 0.7, 0.10, 0, 128, 0, 20 * 128}};
    const int want[2] = {WG_ENONFINITE, WG_OK};
    check_pair(sp, want, 1);
}

/* A sink that, at its sim's 5th section, starts an omega ramp to 0.72 over
 * 60 tau (every step then by the general step), and at the 15th, the ramp
 * over, sets b_j = 0 and xi_p 0.09 (another specialisation: linear
 * bearings): each time the paired loop must be left at once. */
typedef struct changer {
    runrec r;
    wg_sim *sim;
    int rc;
} changer;

static void on_sec_change(void *ctx, const wg_section *sec)
{
    changer *c = ctx;
    on_sec(&c->r, sec);
    if (c->r.nsec == 15) {
        wg_params p = c->sim->p;
        char why[300];
        p.v[WG_P_B_J] = 0.0;
        p.v[WG_P_XI_P] = 0.09;
        c->rc = wg_sim_set_params(c->sim, &p, why, sizeof why);
    }
    if (c->r.nsec == 5) {
        char why[300];
        c->rc |= wg_sim_ramp(c->sim, WG_P_OMEGA, NULL, 0.72, 60.0, why, sizeof why);
    }
}

static void test_pair_sink_changes_sim(void)
{
    const spec sp[2] = {{NULL, 0.7, 0.10, 0, 128, 0, 0}, {NULL, 0.5, 0.10, 0, 128, 0, 0}};
    const uint64_t n = 30 * 128;
    int isa = kernel_isa_choose();
    wg_sim alone, a, b;
    changer ca, cp;
    runrec rb;
    memset(&ca, 0, sizeof ca);
    memset(&cp, 0, sizeof cp);
    memset(&rb, 0, sizeof rb);
    sim_of(&sp[0], isa, &alone);
    sim_of(&sp[0], isa, &a);
    sim_of(&sp[1], isa, &b);
    unsigned before = a.core->kflags;
    ca.sim = &alone, cp.sim = &a;
    wg_sink ska = {&ca, NULL, on_sec_change, on_ev}, skp = {&cp, NULL, on_sec_change, on_ev};
    wg_sink skb = {&rb, NULL, on_sec, on_ev};
    ASSERT_EQ_INT(wg_sim_run(&alone, n, &ska, NULL), WG_OK);
    /* a change made inside a run takes effect at once, as one made between
     * runs: the same sink on runs of one period each */
    wg_sim ref;
    changer cr;
    memset(&cr, 0, sizeof cr);
    sim_of(&sp[0], isa, &ref);
    cr.sim = &ref;
    wg_sink skr = {&cr, NULL, on_sec_change, on_ev};
    for (int k = 0; k < 30; k++)
        ASSERT_EQ_INT(wg_sim_run(&ref, 128, &skr, NULL), WG_OK);
    same_run(&ref, &alone, &cr.r, &ca.r);
    wg_sim_fini(&ref);
    wg_sim *const s[2] = {&a, &b};
    const uint64_t nn[2] = {n, 2 * n};
    const wg_sink *const sk[2] = {&skp, &skb};
    uint64_t done[2];
    int rc[2];
    wg_sim_run_pair(s, nn, sk, done, rc);
    ASSERT_TRUE(rc[0] == WG_OK && rc[1] == WG_OK && (done[0] == n || done[1] == 2 * n));
    for (int j = 0; j < 2; j++) { /* the rest of the one not done, alone */
        uint64_t d = 0;
        ASSERT_EQ_INT(wg_sim_run(s[j], nn[j] - done[j], sk[j], &d), WG_OK);
        done[j] += d;
    }
    ASSERT_TRUE(ca.rc == WG_OK && cp.rc == WG_OK);
    ASSERT_TRUE(a.core->kflags != before && !(a.core->kflags & KF_BJ));
    same_run(&alone, &a, &ca.r, &cp.r);
    /* the other sim: as alone */
    wg_sim b2;
    runrec rb2;
    memset(&rb2, 0, sizeof rb2);
    sim_of(&sp[1], isa, &b2);
    wg_sink skb2 = {&rb2, NULL, on_sec, on_ev};
    ASSERT_EQ_INT(wg_sim_run(&b2, done[1], &skb2, NULL), WG_OK);
    same_run(&b2, &b, &rb2, &rb);
    ASSERT_TRUE(a.p.v[WG_P_OMEGA] == 0.72 && !a.ramp.active);
    printf("a sink ramped one sim's omega, then changed its specialisation: %d sections, %llu "
           "events, the same as alone\n", cp.r.nsec, (unsigned long long)cp.r.nev);
    wg_sim_fini(&alone);
    wg_sim_fini(&a);
    wg_sim_fini(&b);
    wg_sim_fini(&b2);
}

/* L sims by wg_sim_run_batch, each call with the ones not yet done, until
 * all are (each call must return once one of them is done or fails), and
 * each alone by wg_sim_run, on every instruction set: the same bits; with
 * want_batched, most steps in the batched loop on AVX2 and AVX-512 (none
 * on the baseline, which has no batched loop). Last, the batch on the sets
 * a user gets (no WG_ISA: the batched loop's and the runs' own may
 * differ) against each run alone on the baseline.
 * Returns the number of calls. */
static int check_batch(int L, const spec *sp, const int *want_rc, int want_batched, int rk4)
{
    int calls = 0;
    for (int pass = 0; pass <= KISA_N; pass++) {
        const int user = pass == KISA_N, isa = user ? kernel_isa_choose() : pass;
        if (!kernel_isa_supported(isa))
            continue;
        wg_sim alone[KB_LANES], bs[KB_LANES];
        runrec ra[KB_LANES], rb[KB_LANES];
        wg_sink sk[KB_LANES];
        uint64_t done[KB_LANES] = {0};
        int rc[KB_LANES] = {0};
        for (int j = 0; j < L; j++) {
            sim_of_stepper(&sp[j], user ? KISA_SSE2 : isa, rk4, &alone[j]);
            memset(&ra[j], 0, sizeof ra[j]);
            wg_sink ska = {&ra[j], sp[j].general ? on_step : NULL, on_sec, on_ev};
            ASSERT_EQ_INT(wg_sim_run(&alone[j], sp[j].n, &ska, NULL), want_rc[j]);
            sim_of_stepper(&sp[j], user ? -1 : isa, rk4, &bs[j]);
            memset(&rb[j], 0, sizeof rb[j]);
            sk[j] = (wg_sink){&rb[j], sp[j].general ? on_step : NULL, on_sec, on_ev};
        }
        calls = 0;
        for (;;) {
            wg_sim *s[KB_LANES];
            uint64_t n[KB_LANES], d[KB_LANES];
            const wg_sink *k[KB_LANES];
            int r[KB_LANES], idx[KB_LANES], m = 0;
            for (int j = 0; j < L; j++)
                if (done[j] < sp[j].n && rc[j] == WG_OK) {
                    s[m] = &bs[j], n[m] = sp[j].n - done[j], k[m] = &sk[j], d[m] = 99;
                    idx[m++] = j;
                }
            if (m == 0)
                break;
            wg_sim_run_batch(m, s, n, k, d, r);
            calls++;
            int one = 0;
            for (int i = 0; i < m; i++) {
                ASSERT_TRUE(d[i] <= n[i]);
                one |= d[i] == n[i] || r[i] != WG_OK;
                done[idx[i]] += d[i];
                rc[idx[i]] = r[i];
            }
            ASSERT_TRUE(one);
        }
        uint64_t steps = 0, batched = 0;
        for (int j = 0; j < L; j++) {
            steps += bs[j].steps;
            batched += bs[j].core->batched;
            ASSERT_EQ_INT(rc[j], want_rc[j]);
            same_run(&alone[j], &bs[j], &ra[j], &rb[j]);
            wg_sim_fini(&alone[j]);
            wg_sim_fini(&bs[j]);
        }
        printf("%s%s%s: %d sims in %d calls, %llu of %llu steps in the batched loop: each as "
               "alone%s\n", kernel_isa_name(isa), user ? ", own kernels " : "",
               user ? kernel_isa_name(kernel_isa_one(isa)) : "", L, calls,
               (unsigned long long)batched, (unsigned long long)steps,
               user ? " on sse2" : "");
        if (isa != KISA_SSE2 && want_batched) /* most steps in one loop */
            ASSERT_TRUE(batched > steps / 2);
        else if (isa == KISA_SSE2)
            ASSERT_TRUE(batched == 0);
    }
    return calls;
}

/* Eight sims in the batched loop: impacting and not, chaotic, other N,
 * another damping, runs of other lengths (a period's end in mid-loop, a
 * run ending mid-period), one that blows up at its second step. */
static void test_batch_eight(void)
{
    const spec sp[8] = {{NULL, 0.7, 0.10, 0, 128, 0, 60 * 128},
                        {NULL, 0.5, 0.08, 0, 256, 0, 29 * 256 + 5},
                        {NULL, 1.45, 0.12, 0, 128, 0, 45 * 128 + 77},
                        {NULL, 0.7, 0.10, 6e8, 128, 0, 8 * 128},
                        {NULL, 2.5, 0.10, 0, 128, 0, 70 * 128},
                        {NULL, 0.9, 0.05, 0, 256, 0, 20 * 256 + 1},
                        {NULL, 1.2, 0.15, 0, 200, 0, 33 * 200},
                        {NULL, 0.75, 0.10, 0, 128, 0, 52 * 128 + 64}};
    const int want[8] = {WG_OK, WG_OK, WG_OK, WG_ENONFINITE, WG_OK, WG_OK, WG_OK, WG_OK};
    ASSERT_TRUE(check_batch(8, sp, want, 1, 0) >= 7);
    ASSERT_TRUE(check_batch(3, sp + 4, want + 4, 1, 0) >= 2);
    ASSERT_TRUE(check_batch(1, sp + 2, want + 2, 0, 0) == 1);
}

/* Other specialisations in the batched loop: the plain rk4 stepper (dead
 * zones by min/max instead of zone-locked; four sims, most steps batched),
 * and the lowfreq and realistic scenes, two of each and all four. */
static void test_batch_kinds(void)
{
    const spec rk4[4] = {{NULL, 0.7, 0.10, 0, 128, 0, 40 * 128},
                         {NULL, 0.5, 0.08, 0, 256, 0, 20 * 256 + 5},
                         {NULL, 1.45, 0.12, 0, 128, 0, 45 * 128},
                         {NULL, 0.75, 0.10, 0, 128, 0, 33 * 128 + 64}};
    const spec low[4] = {{"lowfreq", 0.5, 0.10, 0, 128, 0, 30 * 128},
                         {"lowfreq", 0.7, 0.05, 0, 128, 0, 40 * 128 + 3},
                         {"realistic", 0.5, 0.10, 0, 128, 0, 30 * 128},
                         {"realistic", 0.9, 0.10, 0, 256, 0, 20 * 256}};
    const int ok[4] = {WG_OK, WG_OK, WG_OK, WG_OK};
    check_batch(4, rk4, ok, 1, 1);
    check_batch(2, low, ok, 0, 0);
    check_batch(2, low + 2, ok, 0, 0);
    check_batch(4, low, ok, 0, 0); /* the two scenes in one batch */
}

/* A batch that cannot run in one loop: another specialisation (the
 * torsional scene) or a per-step callback in it: the sims run in turn,
 * each still as alone. */
static void test_batch_in_turn(void)
{
    const spec sp[4] = {{NULL, 0.7, 0.10, 0, 128, 0, 40 * 128},
                        {"torsional", 1.0, 0.10, 0, 128, 0, 40 * 128},
                        {NULL, 0.5, 0.08, 0, 256, 0, 29 * 256 + 5},
                        {NULL, 1.45, 0.12, 0, 128, 1, 30 * 128}};
    const int ok[4] = {WG_OK, WG_OK, WG_OK, WG_OK};
    check_batch(4, sp, ok, 0, 0);
    const spec gen[3] = {sp[0], sp[3], sp[2]};
    check_batch(3, gen, ok, 0, 0);
    /* more than eight: refused, nothing runs */
    wg_sim one;
    sim_of(&sp[0], kernel_isa_choose(), &one);
    wg_sim *s9[9];
    uint64_t n9[9], d9[9];
    const wg_sink *k9[9];
    int r9[9];
    for (int j = 0; j < 9; j++)
        s9[j] = &one, n9[j] = 128, k9[j] = NULL, d9[j] = 7, r9[j] = WG_OK;
    wg_sim_run_batch(9, s9, n9, k9, d9, r9);
    for (int j = 0; j < 9; j++)
        ASSERT_TRUE(r9[j] == WG_EINVAL && d9[j] == 0);
    ASSERT_TRUE(one.steps == 0);
    wg_sim_fini(&one);
}

/* What batch3_changer reports of sim 0. */
typedef struct batch3 {
    uint64_t done0;         /* its steps in the batch call */
    unsigned kflags0;       /* its specialisation before and after */
    unsigned kflags1;
    uint64_t batched;       /* its steps in the batched loop */
} batch3;

/* Three sims in one batch (table3 at omega 0.7, 0.5, 1.45), the first with
 * the sink `change` (a changer) for n steps, the others recording only for
 * 2n, then each alone to its end: the first must end as the same sink
 * leaves it alone, the others as alone. */
static batch3 batch3_changer(void (*change)(void *, const wg_section *), uint64_t n)
{
    const spec sp[3] = {{NULL, 0.7, 0.10, 0, 128, 0, 0}, {NULL, 0.5, 0.10, 0, 128, 0, 0},
                        {NULL, 1.45, 0.12, 0, 128, 0, 0}};
    int isa = kernel_isa_choose();
    wg_sim alone, s3[3];
    changer ca, cp;
    runrec r3[3], rr;
    memset(&ca, 0, sizeof ca);
    memset(&cp, 0, sizeof cp);
    memset(r3, 0, sizeof r3);
    sim_of(&sp[0], isa, &alone);
    for (int j = 0; j < 3; j++)
        sim_of(&sp[j], isa, &s3[j]);
    batch3 out = {0, s3[0].core->kflags, 0, 0};
    ca.sim = &alone, cp.sim = &s3[0];
    wg_sink ska = {&ca, NULL, change, on_ev};
    wg_sink sk[3] = {{&cp, NULL, change, on_ev}, {&r3[1], NULL, on_sec, on_ev},
                     {&r3[2], NULL, on_sec, on_ev}};
    ASSERT_EQ_INT(wg_sim_run(&alone, n, &ska, NULL), WG_OK);
    wg_sim *const s[3] = {&s3[0], &s3[1], &s3[2]};
    const uint64_t nn[3] = {n, 2 * n, 2 * n};
    const wg_sink *const skp[3] = {&sk[0], &sk[1], &sk[2]};
    uint64_t done[3];
    int rc[3];
    wg_sim_run_batch(3, s, nn, skp, done, rc);
    ASSERT_TRUE(rc[0] == WG_OK && rc[1] == WG_OK && rc[2] == WG_OK);
    ASSERT_TRUE(done[0] == n || done[1] == 2 * n || done[2] == 2 * n);
    out.done0 = done[0];
    for (int j = 0; j < 3; j++) { /* the rest of each, alone */
        uint64_t d = 0;
        ASSERT_EQ_INT(wg_sim_run(s[j], nn[j] - done[j], &sk[j], &d), WG_OK);
        done[j] += d;
    }
    ASSERT_TRUE(ca.rc == WG_OK && cp.rc == WG_OK);
    same_run(&alone, &s3[0], &ca.r, &cp.r);
    for (int j = 1; j < 3; j++) {
        wg_sim b;
        memset(&rr, 0, sizeof rr);
        sim_of(&sp[j], isa, &b);
        wg_sink skb = {&rr, NULL, on_sec, on_ev};
        ASSERT_EQ_INT(wg_sim_run(&b, done[j], &skb, NULL), WG_OK);
        same_run(&b, &s3[j], &rr, &r3[j]);
        wg_sim_fini(&b);
    }
    out.kflags1 = s3[0].core->kflags;
    out.batched = s3[0].core->batched;
    wg_sim_fini(&alone);
    for (int j = 0; j < 3; j++)
        wg_sim_fini(&s3[j]);
    return out;
}

/* A sink that ramps omega and then respecialises its sim mid-run (as in
 * test_pair_sink_changes_sim), in a batch of three: the loop is left at
 * once, and each sim ends as alone. */
static void test_batch_sink_changes_sim(void)
{
    batch3 b = batch3_changer(on_sec_change, 30 * 128);
    ASSERT_TRUE(!(b.kflags1 & KF_BJ));
    printf("a sink in a batch ramped its sim, then respecialised it: the same as alone\n");
}

/* A sink that at its sim's 5th section sets xi_p 0.09 and k_1x 10 % up:
 * the same specialisation, so its lane stays in the batch, which must load
 * the new constants with the lane's state for the next steps to be alone's
 * (a lane loaded again with its state alone fails here). */
static void on_sec_retune(void *ctx, const wg_section *sec)
{
    changer *c = ctx;
    on_sec(&c->r, sec);
    if (c->r.nsec == 5) {
        wg_params p = c->sim->p;
        char why[300];
        p.v[WG_P_XI_P] = 0.09;
        p.v[WG_P_K1X] *= 1.1;
        c->rc = wg_sim_set_params(c->sim, &p, why, sizeof why);
    }
}

static void test_batch_sink_retunes_sim(void)
{
    const uint64_t n = 20 * 128;
    batch3 b = batch3_changer(on_sec_retune, n);
    ASSERT_TRUE(b.done0 == n && b.kflags1 == b.kflags0);
    if (kbatch_select(b.kflags0, kernel_isa_choose(), 3)) /* changed inside the batched loop */
        ASSERT_TRUE(b.batched > n / 2);
    printf("a sink in a batch retuned its sim (xi_p, k_1x) at its 5th section: the same as "
           "alone, %llu of %llu steps batched\n", (unsigned long long)b.batched,
           (unsigned long long)n);
}

/* A duo task: its runs, one after another, each recorded; or none. */
typedef struct dtask {
    spec sp;
    int nrun;                 /* runs asked for, of len[i] steps */
    uint64_t len[3];
    int rc[3];
    wg_sim sim;
    runrec r;
} dtask;

/* Task t's runs made again alone by wg_sim_run: its sim must end the same
 * (it is then freed); the steps and events of that run. */
static void same_as_alone(dtask *t, int isa, uint64_t *steps, uint64_t *nev)
{
    wg_sim a;
    runrec ra;
    memset(&ra, 0, sizeof ra);
    sim_of(&t->sp, isa, &a);
    wg_sink sk = {&ra, NULL, on_sec, on_ev};
    for (int j = 0; j < t->nrun; j++)
        ASSERT_EQ_INT(wg_sim_run(&a, t->len[j], &sk, NULL), t->rc[j]);
    same_run(&a, &t->sim, &ra, &t->r);
    *steps = a.steps;
    *nev = ra.nev;
    wg_sim_fini(&a);
    wg_sim_fini(&t->sim);
}

static void dtask_body(duo *d, void *arg)
{
    dtask *t = arg;
    wg_sink sk = {&t->r, NULL, on_sec, on_ev};
    for (int i = 0; i < t->nrun; i++)
        t->rc[i] = duo_run(d, &t->sim, t->len[i], &sk);
}

/* Three tasks on one thread with the scheduler (and a fourth that asks for
 * nothing): runs of different lengths (one of zero steps), one sim that
 * blows up at its second step (its status comes back, and its next run
 * fails at once, as wg_sim_run's would), one impacting. Each sim ends as
 * the same runs made alone by wg_sim_run leave it, to the bit. */
static void test_duo_tasks(void)
{
    int isa = kernel_isa_choose();
    static dtask t[4] = {
        {.sp = {NULL, 0.5, 0.08, 0, 256, 0, 0}, .nrun = 3, .len = {40 * 256, 0, 17 * 256 + 9}},
        {.sp = {NULL, 0.7, 0.10, 6e8, 128, 0, 0}, .nrun = 2, .len = {8 * 128, 128}},
        {.sp = {NULL, 0.7, 0.12, 0, 128, 0, 0}, .nrun = 2, .len = {25 * 128, 30 * 128}},
        {.sp = {NULL, 1.0, 0.10, 0, 128, 0, 0}, .nrun = 0}};
    void *args[4];
    for (int i = 0; i < 4; i++) {
        sim_of(&t[i].sp, isa, &t[i].sim);
        memset(&t[i].r, 0, sizeof t[i].r);
        args[i] = &t[i];
    }
    ASSERT_EQ_INT(duo_main(4, dtask_body, args, NULL, NULL), WG_OK);
    ASSERT_EQ_INT(t[1].rc[0], WG_ENONFINITE);
    ASSERT_EQ_INT(t[1].rc[1], WG_ENONFINITE);
    for (int i = 0; i < 4; i++) {
        uint64_t steps, nev;
        same_as_alone(&t[i], isa, &steps, &nev);
        printf("task %d: %llu steps, %llu events: equal\n", i, (unsigned long long)steps,
               (unsigned long long)nev);
    }
    ASSERT_EQ_INT(duo_main(0, dtask_body, args, NULL, NULL), WG_EINVAL);
}

/* duo_run2: a task's two runs at once. */
typedef struct d2task {
    spec sp[2];
    int nrun;
    uint64_t len[3]; /* each run of both sims */
    int rc[3], want[3];
    int same_rc; /* duo_run2 of one sim twice */
    wg_sim sim[2];
} d2task;

/* A task of test_duo_run2: a d2task (two), or a dtask. */
typedef struct eithertask {
    int two;
    void *t;
} eithertask;

static void either_body(duo *d, void *arg)
{
    const eithertask *e = arg;
    if (!e->two) {
        dtask_body(d, e->t);
        return;
    }
    d2task *t = e->t;
    t->same_rc = duo_run2(d, &t->sim[0], &t->sim[0], 128); /* refused: nothing runs */
    for (int i = 0; i < t->nrun; i++)
        t->rc[i] = duo_run2(d, &t->sim[0], &t->sim[1], t->len[i]);
}

/* Five tasks on one thread each asking for two runs at once (ten runs: more
 * than a batch's eight lanes, so the oldest eight are batched and the rest
 * wait), beside a task asking for one at a time: each sim ends as its runs
 * made alone by wg_sim_run leave it, to the bit. duo_run2 returns the
 * first sim's status, else the second's: one task's first sim blows up,
 * another's second; one sim given twice is refused and runs nothing. */
static void test_duo_run2(void)
{
    const int isa = kernel_isa_choose();
    static d2task t[5] = {
        {.sp = {{NULL, 0.5, 0.08, 0, 128, 0, 0}, {NULL, 0.5, 0.08, 1e-6, 128, 0, 0}},
         .nrun = 3, .len = {20 * 128, 0, 7 * 128 + 5}},
        {.sp = {{NULL, 0.7, 0.10, 6e8, 128, 0, 0}, {NULL, 0.7, 0.10, 0, 128, 0, 0}},
         .nrun = 2, .len = {8 * 128, 128}, .want = {WG_ENONFINITE, WG_ENONFINITE}},
        {.sp = {{NULL, 0.7, 0.12, 0, 128, 0, 0}, {NULL, 0.7, 0.12, 6e8, 128, 0, 0}},
         .nrun = 2, .len = {9 * 128, 3 * 128}, .want = {WG_ENONFINITE, WG_ENONFINITE}},
        {.sp = {{NULL, 1.45, 0.10, 0, 128, 0, 0}, {NULL, 1.45, 0.10, 1e-7, 128, 0, 0}},
         .nrun = 1, .len = {30 * 128}},
        {.sp = {{NULL, 0.9, 0.05, 0, 256, 0, 0}, {NULL, 2.5, 0.10, 0, 256, 0, 0}},
         .nrun = 2, .len = {11 * 256, 13 * 256}}};
    static dtask one = {.sp = {NULL, 0.75, 0.10, 0, 128, 0, 0}, .nrun = 2,
                        .len = {25 * 128, 12 * 128}};
    eithertask e[6];
    void *args[6];
    for (int i = 0; i < 5; i++) {
        for (int j = 0; j < 2; j++)
            sim_of(&t[i].sp[j], isa, &t[i].sim[j]);
        e[i] = (eithertask){1, &t[i]};
    }
    sim_of(&one.sp, isa, &one.sim);
    memset(&one.r, 0, sizeof one.r);
    e[5] = (eithertask){0, &one};
    for (int i = 0; i < 6; i++)
        args[i] = &e[i];
    ASSERT_EQ_INT(duo_main(6, either_body, args, NULL, NULL), WG_OK);
    uint64_t batched = 0, steps = 0;
    for (int i = 0; i < 5; i++) {
        ASSERT_EQ_INT(t[i].same_rc, WG_EINVAL);
        for (int r = 0; r < t[i].nrun; r++)
            ASSERT_EQ_INT(t[i].rc[r], t[i].want[r]);
        for (int j = 0; j < 2; j++) {
            wg_sim a;
            sim_of(&t[i].sp[j], isa, &a);
            for (int r = 0; r < t[i].nrun; r++)
                wg_sim_run(&a, t[i].len[r], NULL, NULL);
            runrec none;
            memset(&none, 0, sizeof none);
            same_run(&a, &t[i].sim[j], &none, &none);
            batched += t[i].sim[j].core->batched;
            steps += t[i].sim[j].steps;
            wg_sim_fini(&a);
            wg_sim_fini(&t[i].sim[j]);
        }
    }
    uint64_t s1, n1;
    same_as_alone(&one, isa, &s1, &n1);
    printf("duo_run2: ten runs of five tasks and one task's own: each sim as alone; %llu of "
           "%llu steps in the batched loop (%s)\n", (unsigned long long)batched,
           (unsigned long long)steps, kernel_isa_name(isa));
    if (kbatch_select(KF_BEAR | KF_LOCK, isa, 8))
        ASSERT_TRUE(batched > steps / 2);
}

/* duo_wait: a task that waits for another's work. */
typedef struct wtask {
    dtask *t;
    int *made;     /* runs the maker has ended */
    int need;      /* this one's run waits for that many (0: it makes them) */
    int looked;    /* times it found them not made */
} wtask;

static void wtask_body(duo *d, void *arg)
{
    wtask *w = arg;
    wg_sink sk = {&w->t->r, NULL, on_sec, on_ev};
    for (int i = 0; i < w->t->nrun; i++) {
        while (*w->made < w->need) {
            w->looked++;
            duo_wait(d);
        }
        w->t->rc[i] = duo_run(d, &w->t->sim, w->t->len[i], &sk);
        if (w->need == 0)
            ++*w->made;
    }
}

typedef struct wseen {
    const int *made;
    int seen, calls[2];
} wseen;

/* The idle function: has the maker ended a run since the waiting looked? */
static int widle(void *ctx, int block)
{
    wseen *ws = ctx;
    ws->calls[block]++;
    if (*ws->made == ws->seen)
        return block; /* nothing from another thread could come: look again */
    ws->seen = *ws->made;
    return 1;
}

/* Two tasks wait (duo_wait) for a third's runs before their own, without
 * an idle function (woken when no task can go on) and with one (woken
 * when it says the maker ended a run). Every sim ends as alone. */
static void test_duo_wait(void)
{
    int isa = kernel_isa_choose();
    for (int mode = 0; mode < 2; mode++) {
        static dtask t[3];
        t[0] = (dtask){.sp = {NULL, 0.5, 0.08, 0, 128, 0, 0}, .nrun = 2, .len = {6 * 128, 5 * 128}};
        t[1] = (dtask){.sp = {NULL, 0.7, 0.10, 0, 128, 0, 0}, .nrun = 1, .len = {9 * 128}};
        t[2] = (dtask){.sp = {NULL, 0.9, 0.12, 0, 128, 0, 0}, .nrun = 1, .len = {4 * 128}};
        int made = 0;
        wtask w[3] = {{&t[0], &made, 0, 0}, {&t[1], &made, 1, 0}, {&t[2], &made, 2, 0}};
        wseen ws = {&made, 0, {0, 0}};
        void *args[3];
        for (int i = 0; i < 3; i++) {
            sim_of(&t[i].sp, isa, &t[i].sim);
            memset(&t[i].r, 0, sizeof t[i].r);
            args[i] = &w[i];
        }
        ASSERT_EQ_INT(duo_main(3, wtask_body, args, mode ? widle : NULL, &ws), WG_OK);
        ASSERT_EQ_INT(made, 2);
        ASSERT_TRUE(w[1].looked >= 1 && w[2].looked >= 1); /* both had to wait */
        if (mode)
            ASSERT_TRUE(ws.calls[0] > 0);
        for (int i = 0; i < 3; i++) {
            uint64_t steps, nev;
            same_as_alone(&t[i], isa, &steps, &nev);
        }
        printf("duo_wait %s an idle function: waited %d and %d times; idle asked %d, %d "
               "(blocking) times\n", mode ? "with" : "without", w[1].looked, w[2].looked,
               ws.calls[0], ws.calls[1]);
    }
}

TEST_MAIN(TEST(test_pair_differs_in_params), TEST(test_pair_in_turn), TEST(test_pair_blowup),
          TEST(test_pair_sink_changes_sim), TEST(test_batch_eight), TEST(test_batch_kinds),
          TEST(test_batch_in_turn), TEST(test_batch_sink_changes_sim),
          TEST(test_batch_sink_retunes_sim), TEST(test_duo_tasks), TEST(test_duo_run2),
          TEST(test_duo_wait))

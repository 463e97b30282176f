/* Run-time dispatch of the kernels (white box): every instruction set this
 * CPU runs (sse2, the x86-64 baseline, and avx2, avx512 when present) and
 * both step paths of wg_sim_run (the run of plain steps in the kernel's own
 * loop, and the general step it hands back to) agree within the step's
 * truncation error -- one step of each of the 64 specialisations, and whole
 * runs with impacts and located events. The kernels are written to give the
 * same bits on every path (kern_tmpl.h); across instruction sets the test
 * prints whether they did and fails only past the truncation-error bound,
 * and on one instruction set it asserts the two step paths bitwise equal
 * (the general step reuses the state the run of plain steps computed). */
#include "wormgear/wg_scene.h"

#include "kern_fix.h"

#include <stdlib.h>

/* One step of length h with the sse2 kernel, and its local truncation error
 * estimated by two half steps (Richardson: |y_h - y_h/2| 16/15). */
static double truncation(wg_kernel_fn k, const wg_kcoef *kc, const wg_params *p,
                         const double *y0, double h)
{
    wg_exc e[3], e1[3], e2[3];
    double y1[16], ym[16], y2[16];
    for (int j = 0; j < 3; j++) {
        wg_exc_eval(p, 0.4 + 0.5 * h * j, 1.0, &e[j]);
        wg_exc_eval(p, 0.4 + 0.25 * h * j, 1.0, &e1[j]);
        wg_exc_eval(p, 0.4 + 0.5 * h + 0.25 * h * j, 1.0, &e2[j]);
    }
    k(y0, y1, kc, e, h);
    k(y0, ym, kc, e1, 0.5 * h);
    k(ym, y2, kc, e2, 0.5 * h);
    return maxdiff(y1, y2, 14) * 16.0 / 15.0;
}

/* Every specialisation, every supported instruction set: one step from the
 * same state equals the baseline's within 1e-3 of the step's truncation
 * error (zones unlocked and locked alike). */
static void test_kernels_agree_across_isas(void)
{
    int nsame = 0, ncmp = 0;
    double worst = 0;
    for (unsigned f = 0; f < KF_NKERNEL; f++) {
        if (kfix_skip(f))
            continue;
        wg_params p;
        wg_sim s;
        double y0[16], yb[16], y1[16] = {0};
        kfix_setup(f, &p, &s, y0);
        memcpy(yb, y0, sizeof yb);
        wg_exc e[3];
        double h = 0.02;
        for (int j = 0; j < 3; j++)
            wg_exc_eval(&p, 0.4 + 0.5 * h * j, 1.0, &e[j]);
        wg_kernel_fn base = kernel_select(f, KISA_SSE2);
        base(y0, yb, &s.core->kc, e, h);
        double tol = 1e-3 * truncation(base, &s.core->kc, &p, y0, h);
        for (int isa = KISA_SSE2 + 1; isa < KISA_N; isa++) {
            if (!kernel_isa_supported(isa))
                continue;
            memcpy(y1, y0, sizeof y1);
            kernel_select(f, isa)(y0, y1, &s.core->kc, e, h);
            double d = maxdiff(y1, yb, 14);
            if (d > tol)
                fprintf(stderr, "flags %u %s: diff %.3g > tol %.3g\n", f,
                        kernel_isa_name(isa), d, tol);
            ASSERT_TRUE(d <= tol);
            worst = fmax(worst, d);
            nsame += memcmp(y1, yb, sizeof y1) == 0;
            ncmp++;
        }
        wg_sim_fini(&s);
    }
    printf("kernels: %d comparisons with the sse2 baseline, %d bitwise equal, max diff %.3g\n",
           ncmp, nsame, worst);
}

typedef struct runrec {
    int nsec;
    double ysec[8][WG_NSTATE_MAX];
    double xn[8][2]; /* the period's min and max x_n */
    int motion[8], impacts[8];
    uint64_t nev;
} runrec;

static void on_sec(void *ctx, const wg_section *sec)
{
    runrec *r = ctx;
    int i = r->nsec++ % 8;
    memcpy(r->ysec[i], sec->y, sizeof r->ysec[i]);
    r->xn[i][0] = sec->stats.min_xn;
    r->xn[i][1] = sec->stats.max_xn;
    r->motion[i] = sec->stats.motion;
    r->impacts[i] = sec->stats.impacts;
}

static void on_ev(void *ctx, const wg_event *ev)
{
    (void)ev;
    ((runrec *)ctx)->nev++;
}

static void on_step(void *ctx, const struct wg_sim *s)
{
    (void)ctx;
    (void)s;
}

/* p at omega (table3 at 0.7: single-sided impacts every period, so the run
 * of plain steps stops and the general step splits), N steps per period, 60
 * periods; with `general` an on_step sink forces the general step
 * throughout. */
static void run_params(wg_params p, double omega, int isa, int N, int general, wg_sim *s,
                       runrec *r)
{
    p.v[WG_P_OMEGA] = omega;
    kfix_sim_on(s, &p, N, isa);
    memset(r, 0, sizeof *r);
    wg_sink sink = {r, general ? on_step : NULL, on_sec, on_ev};
    uint64_t done = 0;
    ASSERT_EQ_INT(wg_sim_run(s, 60 * (uint64_t)N, &sink, &done), WG_OK);
    ASSERT_TRUE(done == 60 * (uint64_t)N);
}

static void run_point(int isa, int N, int general, wg_sim *s, runrec *r)
{
    wg_params p;
    wg_params_default(&p);
    run_params(p, 0.7, isa, N, general, s, r);
}

/* The torsional path (s and s' only) on each instruction set, at omega 1.0
 * (an impact a period): its run of plain steps and its general step give
 * the same bits, events and sections. */
static void test_torsional_paths(void)
{
    wg_scene sc;
    char why[600];
    ASSERT_EQ_INT(wg_scene_open(&sc, "torsional", why, sizeof why), WG_OK);
    ASSERT_TRUE(wg_params_torsional(&sc.p));
    for (int isa = 0; isa < KISA_N; isa++) {
        if (!kernel_isa_supported(isa))
            continue;
        wg_sim a, b;
        runrec ra, rb;
        run_params(sc.p, 1.0, isa, 128, 0, &a, &ra);
        run_params(sc.p, 1.0, isa, 128, 1, &b, &rb);
        ASSERT_TRUE(ra.nev > 100); /* it impacts: the run of plain steps stops */
        ASSERT_TRUE(memcmp(a.y, b.y, sizeof a.y) == 0 && a.tau == b.tau);
        ASSERT_TRUE(memcmp(&ra, &rb, sizeof ra) == 0);
        wg_sim_fini(&a);
        wg_sim_fini(&b);
    }
}

/* Whole runs: each instruction set, and the general step alone, against
 * the baseline's run of plain steps. Sections, motion, impacts, events and
 * located splits match; states and the periods' x_n extrema within 1e-3 of
 * the run's truncation error (the N = 128 run against N = 256). On one
 * instruction set the run of plain steps (which also takes the steps that
 * end a period or turn x_n' round) and the general step give the same bits. */
static void test_runs_agree_across_paths(void)
{
    wg_sim s0, s2, s, sg;
    runrec r0, r2, r, rg;
    run_point(KISA_SSE2, 128, 0, &s0, &r0);
    run_point(KISA_SSE2, 256, 0, &s2, &r2);
    double tol = 1e-3 * maxdiff(s0.y, s2.y, 14);
    ASSERT_TRUE(tol > 0);
    ASSERT_TRUE(r0.nev > 60);          /* it does impact: events are located */
    ASSERT_TRUE(s0.nsplit > 60);
    ASSERT_TRUE(r0.motion[0] >= WG_MOTION_SINGLE);
    int nsame = 0, nrun = 0;
    for (int isa = 0; isa < KISA_N; isa++) {
        for (int general = 0; general < 2; general++) {
            if (!kernel_isa_supported(isa) || (isa == KISA_SSE2 && !general))
                continue;
            run_point(isa, 128, general, &s, &r);
            double d = maxdiff(s.y, s0.y, 14);
            for (int i = 0; i < 8; i++)
                d = fmax(d, fmax(maxdiff(r.ysec[i], r0.ysec[i], 14),
                                 maxdiff(r.xn[i], r0.xn[i], 2)));
            if (d > tol)
                fprintf(stderr, "%s%s: diff %.3g > tol %.3g\n", kernel_isa_name(isa),
                        general ? " general step" : "", d, tol);
            ASSERT_TRUE(d <= tol);
            ASSERT_EQ_INT(r.nsec, r0.nsec);
            ASSERT_TRUE(r.nev == r0.nev && s.nsplit == s0.nsplit && s.steps == s0.steps);
            ASSERT_EQ_INT(memcmp(r.motion, r0.motion, sizeof r.motion), 0);
            ASSERT_EQ_INT(memcmp(r.impacts, r0.impacts, sizeof r.impacts), 0);
            ASSERT_TRUE(fabs(s.tau - s0.tau) <= 1e-12 * s0.tau);
            nsame += memcmp(s.y, s0.y, sizeof s.y) == 0 && s.tau == s0.tau;
            nrun++;
            if (isa == KISA_SSE2) { /* its general step against its run of plain steps */
                ASSERT_TRUE(memcmp(s.y, s0.y, sizeof s.y) == 0 && s.tau == s0.tau);
                ASSERT_TRUE(memcmp(&r, &r0, sizeof r) == 0);
            } else if (!general) { /* the same instruction set's general step */
                run_point(isa, 128, 1, &sg, &rg);
                ASSERT_TRUE(memcmp(s.y, sg.y, sizeof s.y) == 0 && s.tau == sg.tau);
                ASSERT_TRUE(memcmp(&r, &rg, sizeof r) == 0);
                wg_sim_fini(&sg);
            }
            wg_sim_fini(&s);
        }
    }
    printf("runs: %d paths against sse2's run of plain steps, %d bitwise equal; tol %.3g "
           "(truncation %.3g); chosen by default here: %s\n",
           nrun, nsame, tol, 1e3 * tol, kernel_isa_name(kernel_isa_choose()));
    wg_sim_fini(&s0);
    wg_sim_fini(&s2);
}

/* Near the blow-up bound the run of plain steps refuses every step (some
 * |y_i| >= fin / 16) and the general step takes it: a run from a state of
 * order 1e8 (its sum still below ABSURD) gives the same bits with and
 * without the run of plain steps, and reaches the refused range; from 6e8
 * both declare the blow-up at the same step (a run of plain steps that
 * accepted a step the general step's sum test refuses would go further). */
/* table3 at omega 0.7 from s = s0 (everything else at rest), up to 8 periods
 * one at a time, the run of plain steps on or (general) forced off: the
 * status of the first run that fails (or WG_OK), steps done, the largest
 * |y_i| after each period, the final state. */
static int run_large(double s0, int general, uint64_t *done, double *peak, double *yend)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = 0.7;
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, 128};
    double y0[WG_NSTATE_MAX] = {0};
    y0[6] = s0;
    wg_sim s;
    char why[300];
    ASSERT_EQ_INT(wg_sim_init(&s, &p, &cfg, why, sizeof why), WG_OK);
    wg_sim_set_state(&s, y0, 0, 0.0);
    runrec r;
    memset(&r, 0, sizeof r);
    wg_sink sink = {&r, general ? on_step : NULL, on_sec, on_ev};
    int rc = WG_OK;
    *done = 0;
    for (int per = 0; per < 8 && rc == WG_OK; per++) {
        uint64_t d = 0;
        rc = wg_sim_run(&s, 128, &sink, &d);
        *done += d;
        for (int j = 0; j < 14; j++)
            *peak = fmax(*peak, fabs(s.y[j]));
    }
    memcpy(yend, s.y, sizeof(double) * WG_NSTATE_MAX);
    wg_sim_fini(&s);
    return rc;
}

static void test_large_state_handover(void)
{
    double yend[2][WG_NSTATE_MAX], ylast[WG_NSTATE_MAX], peak = 0, blown = 0;
    uint64_t done[2];
    for (int general = 0; general < 2; general++) {
        ASSERT_EQ_INT(run_large(2e8, general, &done[general], &peak, yend[general]), WG_OK);
        ASSERT_TRUE(done[general] == 8 * 128);
    }
    /* past the bound: both paths declare the blow-up at the same step */
    for (int general = 0; general < 2; general++)
        ASSERT_EQ_INT(run_large(6e8, general, &done[general], &blown, ylast), WG_ENONFINITE);
    ASSERT_TRUE(done[0] == done[1] && done[0] > 0);
    printf("large state: peak |y_i| %.3g (refused above %.3g), fast and general runs %s; "
           "from 6e8 both stop at step %llu\n", peak, ABSURD * (1 - 1e-9) / 16,
           memcmp(yend[0], yend[1], sizeof yend[0]) ? "differ" : "equal",
           (unsigned long long)done[0]);
    ASSERT_TRUE(peak >= ABSURD * (1 - 1e-9) / 16);
    ASSERT_EQ_INT(memcmp(yend[0], yend[1], sizeof yend[0]), 0);
}

/* WG_ISA picks a supported set by name and falls back to the widest for an
 * unknown or unsupported one. */
static void test_isa_choice(void)
{
    int widest = kernel_isa_supported(KISA_AVX512) ? KISA_AVX512
                 : kernel_isa_supported(KISA_AVX2) ? KISA_AVX2 : KISA_SSE2;
    unsetenv("WG_ISA");
    ASSERT_EQ_INT(kernel_isa_choose(), widest);
    ASSERT_TRUE(kernel_isa_supported(KISA_SSE2));
    setenv("WG_ISA", "sse2", 1);
    ASSERT_EQ_INT(kernel_isa_choose(), KISA_SSE2);
    setenv("WG_ISA", "mmx", 1);
    ASSERT_EQ_INT(kernel_isa_choose(), widest);
    unsetenv("WG_ISA");
    ASSERT_STR(kernel_isa_name(KISA_AVX2), "avx2");
    ASSERT_STR(kernel_isa_name(KISA_AVX512VL), "avx512vl");
    /* AVX-512VL: AVX-512F and AVX2 too; the 4-wide set is it where the CPU
     * has it, else AVX2's */
    if (kernel_isa_supported(KISA_AVX512VL))
        ASSERT_TRUE(kernel_isa_supported(KISA_AVX512) && kernel_isa_supported(KISA_AVX2));
    const int w4 = kernel_isa_4wide();
    ASSERT_EQ_INT(w4, kernel_isa_supported(KISA_AVX512VL) ? KISA_AVX512VL : KISA_AVX2);
    setenv("WG_ISA", "avx512vl", 1); /* chosen where the CPU runs it, else ignored */
    ASSERT_EQ_INT(kernel_isa_choose(),
                  kernel_isa_supported(KISA_AVX512VL) ? KISA_AVX512VL : widest);
    unsetenv("WG_ISA");
    /* a run's own kernels: the 4-wide set for AVX-512 on an Intel CPU
     * unless WG_ISA names avx512; any other set as it is */
    ASSERT_EQ_INT(kernel_isa_one(KISA_SSE2), KISA_SSE2);
    ASSERT_EQ_INT(kernel_isa_one(KISA_AVX2), KISA_AVX2);
    ASSERT_EQ_INT(kernel_isa_one(KISA_AVX512VL), KISA_AVX512VL);
    if (kernel_isa_supported(KISA_AVX512)) {
        int intel = 0;
#if defined(__x86_64__) && defined(__GNUC__)
        intel = __builtin_cpu_is("intel");
#endif
        ASSERT_EQ_INT(kernel_isa_one(KISA_AVX512), intel ? w4 : KISA_AVX512);
        setenv("WG_ISA", "avx512", 1);
        ASSERT_EQ_INT(kernel_isa_one(KISA_AVX512), KISA_AVX512);
        setenv("WG_ISA", "avx2", 1);
        ASSERT_EQ_INT(kernel_isa_one(KISA_AVX512), intel ? w4 : KISA_AVX512);
        unsetenv("WG_ISA");
        printf("a run's own kernels on this %s CPU: %s\n", intel ? "Intel" : "non-Intel",
               kernel_isa_name(kernel_isa_one(KISA_AVX512)));
        /* a batch of four or fewer on AVX-512 takes the 4-wide loop, of
         * five or more the 8-wide one; a 4-wide set keeps its own */
        const unsigned f = KF_BEAR | KF_LOCK;
        for (int L = 3; L <= 8; L++) {
            ASSERT_TRUE(kbatch_select(f, KISA_AVX512, L) ==
                        kbatch_select(f, L <= 4 ? w4 : KISA_AVX512, 8));
            if (kernel_isa_supported(KISA_AVX512VL)) /* a 4-wide set keeps its own loop */
                ASSERT_TRUE(kbatch_select(f, KISA_AVX512VL, L) !=
                            kbatch_select(f, KISA_AVX2, L));
        }
    }
    /* wg_sim_isa_name: the set of a sim's own steps, as wgsim and the
     * daemon report it; the printed form's step is the baseline's */
    wg_params p;
    wg_params_default(&p);
    for (int model = 0; model < 2; model++)
        for (int isa = -1; isa < KISA_N; isa++) {
            if (isa >= 0 && !kernel_isa_supported(isa))
                continue;
            if (isa >= 0)
                setenv("WG_ISA", kernel_isa_name(isa), 1);
            wg_sim s;
            wg_sim_config cfg = {model ? WG_MODEL_PRINTED : WG_MODEL_CONSISTENT,
                                 WG_STEPPER_DEFAULT, 128};
            char why[300];
            const int want = kernel_isa_one(kernel_isa_choose()); /* WG_ISA as the sim sees it */
            ASSERT_EQ_INT(wg_sim_init(&s, &p, &cfg, why, sizeof why), WG_OK);
            unsetenv("WG_ISA");
            ASSERT_STR(wg_sim_isa_name(&s), model ? "baseline" : kernel_isa_name(want));
            wg_sim_fini(&s);
        }
}

TEST_MAIN(TEST(test_kernels_agree_across_isas), TEST(test_runs_agree_across_paths),
          TEST(test_large_state_handover), TEST(test_torsional_paths),
          TEST(test_isa_choice))

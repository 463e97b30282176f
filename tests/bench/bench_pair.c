/* bench_pair - is the table3 step bound by its dependency chain or by the
 * machine's throughput? The full kernel (full+bj+b+ka+em, kern_tmpl.h, one
 * instruction set per build of this file: KW = 2 sse2, 4 avx2, 8 avx512)
 * runs in a loop that keeps the state in registers, first one trajectory,
 * then two independent ones interleaved in the same loop body. If the step
 * were latency-bound, two would cost about what one costs (ratio near 2);
 * if throughput-bound, twice as much (ratio near 1). No bookkeeping (that
 * is wg_krun's: compare bench_step), the excitation from a 64-entry table.
 * Then the latency of one link of the step's path through the sum across
 * the bearing lanes, in dependent adds (the traced bound's unit). Last,
 * whole runs through the library (its own choice of instruction set, with
 * the bookkeeping, zone tests and period ends): eight table3 sims one
 * after the other by wg_sim_run, two at a time by wg_sim_run_pair (what a
 * sweep thread does with --pair 2), then all eight by wg_sim_run_batch
 * (--pair 8), and three at a time by it (a study thread's three chains),
 * without impacts and impacting.
 * Thread CPU time, medians of REPS repetitions interleaved.
 * usage: bench_pair_{sse2,avx2,avx512} [STEPS] [REPS] (--help: what they allow) */
#ifndef KW
#define KW 2
#endif
#define KSUF bench
#include "kern_tmpl.h"

#include "bench_args.h"
#include "bench_common.h"
#include "bench_lat.h"
#include "wormgear/wg_sim.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define FULL 0, 1, 1, 1, 1 /* LOCK, BJ, MB, KA, EM */

__attribute__((noinline)) static void one(const wg_kcoef *K, const wg_exc *e, double h,
                                          double *y, long n)
{
    vconst C;
    vconst_load(&C, K);
    kst a = kst_load(y);
    for (long i = 0; i < n; i++)
        a = rk4_full_st(&C, K, e + 3 * (i & 63), h, a, FULL);
    kst_store(y, a);
}

__attribute__((noinline)) static void two(const wg_kcoef *K, const wg_exc *e, double h,
                                          double *y, double *y2, long n)
{
    vconst C;
    vconst_load(&C, K);
    kst a = kst_load(y), b = kst_load(y2);
    for (long i = 0; i < n; i++) {
        kst a1 = rk4_full_st(&C, K, e + 3 * (i & 63), h, a, FULL);
        kst b1 = rk4_full_st(&C, K, e + 3 * ((i + 32) & 63), h, b, FULL);
        a = a1;
        b = b1;
    }
    kst_store(y, a);
    kst_store(y2, b);
}

/* The kernel's sum across the bearing lanes (hsumb) followed by the
 * broadcast of its result and one vector add, as a dependent chain of n
 * links: a link the step's critical path goes through twice
 * (tools/chainbound.py counts it), timed against a dependent add (dep_ns,
 * the unit bench_gsl prices the chain bound in). */
__attribute__((noinline)) static double hsum_chain(const double *d6, long n)
{
    vb d[NB], p[NB];
    for (int b = 0; b < NB; b++)
        d[b] = p[b] = vload6(d6, b);
    for (long i = 0; i < n; i++) {
        double h = hsumb(p);
        __asm__("" : "+x"(h));
        vb s = vsplat(h);
        for (int b = 0; b < NB; b++)
            p[b] = s + d[b];
    }
    return hsumb(p);
}

enum { NS = 8 }; /* sims a benchmark row runs */

/* Sims j0..j1-1 (at most NS) by wg_sim_run_batch, len steps each, called
 * again with the ones left each time one is done. */
static void batch_runs(wg_sim *s, int j0, int j1, uint64_t len)
{
    uint64_t left[NS];
    for (int j = j0; j < j1; j++)
        left[j - j0] = len;
    for (;;) {
        wg_sim *sp[NS];
        uint64_t n[NS], done[NS];
        const wg_sink *sk[NS];
        int rc[NS], idx[NS], m = 0;
        for (int j = j0; j < j1; j++)
            if (left[j - j0])
                sp[m] = &s[j], n[m] = left[j - j0], sk[m] = NULL, idx[m++] = j - j0;
        if (!m)
            break;
        wg_sim_run_batch(m, sp, n, sk, done, rc);
        for (int i = 0; i < m; i++)
            left[idx[i]] -= rc[i] ? left[idx[i]] : done[i];
    }
}

/* ns a step of eight sims (omega w + 0.01 j, xi_p 0.10 + 0.005 j, N 256),
 * 200 periods each: one after another by wg_sim_run, two at a time by
 * wg_sim_run_pair (--pair 2), all eight by wg_sim_run_batch (one per
 * vector lane where the CPU has AVX2 or AVX-512), and three at a time by
 * it (3, 3, 2: a study thread's three chains). */
static void runs(double w, double *alone, double *paired, double *batched, double *by3)
{
    wg_sim s[NS];
    char why[300];
    const uint64_t len = 200 * 256;
    for (int j = 0; j < NS; j++) {
        wg_params p;
        wg_params_default(&p);
        p.v[WG_P_OMEGA] = w + 0.01 * j;
        p.v[WG_P_XI_P] = 0.10 + 0.005 * j;
        wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, 256};
        if (wg_sim_init(&s[j], &p, &cfg, why, sizeof why)) {
            fprintf(stderr, "bench_pair: %s\n", why);
            exit(1);
        }
        wg_sim_run(&s[j], 50 * 256, NULL, NULL); /* onto the attractor */
    }
    double a = bench_now_ns();
    for (int j = 0; j < NS; j++)
        wg_sim_run(&s[j], len, NULL, NULL);
    double b = bench_now_ns();
    for (int j = 0; j < NS; j += 2) {
        wg_sim *const sp[2] = {&s[j], &s[j + 1]};
        uint64_t n[2] = {len, len}, done[2];
        const wg_sink *const sk[2] = {NULL, NULL};
        int rc[2];
        while (n[0] && n[1]) {
            wg_sim_run_pair(sp, n, sk, done, rc);
            n[0] -= done[0], n[1] -= done[1];
        }
        wg_sim_run(sp[0], n[0], NULL, NULL);
        wg_sim_run(sp[1], n[1], NULL, NULL);
    }
    double c = bench_now_ns();
    batch_runs(s, 0, NS, len);
    double d = bench_now_ns();
    for (int j = 0; j < NS; j += 3)
        batch_runs(s, j, j + 3 < NS ? j + 3 : NS, len);
    double e = bench_now_ns();
    *alone = (b - a) / (double)(NS * len);
    *paired = (c - b) / (double)(NS * len);
    *batched = (d - c) / (double)(NS * len);
    *by3 = (e - d) / (double)(NS * len);
    for (int j = 0; j < NS; j++)
        wg_sim_fini(&s[j]);
}

int main(int argc, char **argv)
{
    double steps = 2e6, nrep = 7;
    bench_arg args[] = {
        {"STEPS", "steps a trajectory times each repetition, a whole number from 1000 to 1e9 "
                  "(default 2e6)", 1000, 1e9, &steps, NULL, 0},
        {"REPS", "repetitions, interleaved, each figure the median, 1 to 64 (default 7)", 1, 64,
         &nrep, NULL, 0}};
    char prog[32];
    snprintf(prog, sizeof prog, "bench_pair_%s", KW == 2 ? "sse2" : KW == 4 ? "avx2" : "avx512");
    int rc = bench_args(prog, "The full kernel alone, one trajectory against two interleaved; "
                        "then whole runs: eight sims alone, paired, batched.", "", argc, argv,
                        args, 2, NULL);
    if (rc >= 0)
        return rc;
    long n = (long)steps;
    int reps = (int)nrep;
#if KW == 4
    if (!__builtin_cpu_supports("avx2")) {
        printf("bench_pair: this CPU has no AVX2\n");
        return 0;
    }
#elif KW == 8
    if (!__builtin_cpu_supports("avx512f")) {
        printf("bench_pair: this CPU has no AVX-512F\n");
        return 0;
    }
#endif
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = 0.5; /* table3's non-impacting point */
    wg_sim s;
    char why[300];
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4, 128};
    if (wg_sim_init(&s, &p, &cfg, why, sizeof why)) {
        fprintf(stderr, "bench_pair: %s\n", why);
        return 1;
    }
    if (s.core->kflags != (KF_BEAR | KF_BJ | KF_MB | KF_KA | KF_EM)) {
        fprintf(stderr, "bench_pair: table3 did not select the full kernel\n");
        return 1;
    }
    wg_exc e[3 * 64 + 3];
    double h = 2.0 * 3.14159265358979 / (128 * 0.5);
    for (int i = 0; i < 3 * 64 + 3; i++)
        wg_exc_eval(&p, 0.5 * h * i, 0.5, &e[i]);
    double y[16] = {0}, y2[16];
    wg_sim_run(&s, 128 * 50, NULL, NULL); /* a state on the orbit */
    memcpy(y, s.y, sizeof(double) * 14);
    memcpy(y2, y, sizeof y2);
    y2[6] += 1e-3;
    double t1[64], t2[64], ratio[64];
    for (int r = 0; r < reps; r++) {
        double a = bench_now_ns();
        one(&s.core->kc, e, h, y, 2 * n);
        double b = bench_now_ns();
        two(&s.core->kc, e, h, y, y2, n);
        double c = bench_now_ns();
        t1[r] = (b - a) / (2.0 * n);
        t2[r] = (c - b) / (2.0 * n);
        ratio[r] = t1[r] / t2[r];
    }
    double ta[64], th[64], d6[6] = {1e-300, -1e-300, 2e-300, -2e-300, 3e-300, -3e-300};
    double sink = 0.0;
    for (int r = 0; r < reps; r++) {
        ta[r] = dep_ns(2 * n).add;
        double b = bench_now_ns();
        sink += hsum_chain(d6, 2 * n);
        th[r] = (bench_now_ns() - b) / (2.0 * n);
    }
    if (!(y[6] == y[6]) || !(y2[6] == y2[6])) {
        fprintf(stderr, "bench_pair: the trajectories blew up\n");
        return 1;
    }
    printf("bench_pair (KW = %d): %ld steps x %d reps, thread CPU time, medians\n", KW, 2 * n,
           reps);
    printf("one trajectory      %.1f ns/step\n", bench_median(t1, reps));
    printf("two interleaved     %.1f ns/step\n", bench_median(t2, reps));
    printf("throughput gain     %.2fx (2: latency-bound, 1: throughput-bound)\n",
           bench_median(ratio, reps));
    double la = bench_median(ta, reps), lh = bench_median(th, reps);
    printf("dependent add       %.3f ns\n", la);
    /* printing something that depends on sink keeps the chain from being dropped */
    printf("hsumb+vsplat+add    %.3f ns = %.1f dependent adds (a link of the step's path; "
           "tools/chainbound.py prices it as 4 adds + 2 min/shuffle = 6)%s\n",
           lh, lh / la, sink == 1.0 ? " " : "");
    static const double omega[2] = {0.5, 0.7};
    const int isa = kernel_isa_choose();
    printf("runs on the sets a sim chooses (WG_ISA=sse2|avx2|avx512|avx512vl picks one): %s "
           "batched (eight; three at a time: %s), %s alone and paired\n", kernel_isa_name(isa),
           isa == KISA_AVX512 ? kernel_isa_name(kernel_isa_4wide()) : kernel_isa_name(isa),
           kernel_isa_name(kernel_isa_one(isa)));
    for (int k = 0; k < 2; k++) {
        double ra[64], rp[64], rb[64], r3[64], rr[64], rs[64];
        for (int r = 0; r < reps; r++) {
            runs(omega[k], &ra[r], &rp[r], &rb[r], &r3[r]);
            rr[r] = ra[r] / rp[r];
            rs[r] = ra[r] / rb[r];
        }
        printf("runs, omega %.2f..%.2f %s  alone %.1f, paired %.1f, batched %.1f ns/step: "
               "%.2fx, %.2fx; batched three at a time %.1f\n",
               omega[k], omega[k] + 0.07, k ? "(impacting) " : "(no impact)",
               bench_median(ra, reps), bench_median(rp, reps), bench_median(rb, reps),
               bench_median(rr, reps), bench_median(rs, reps), bench_median(r3, reps));
    }
    wg_sim_fini(&s);
    return 0;
}

/* bench_gsl - cost of one RK4 step: wg_sim's specialised kernels (rk4 and
 * rk4-event) against GSL odeiv2's rk4 stepper and a plain hand-written RK4,
 * both of those on the same right-hand side (wg_exc_eval at the stage time +
 * the reference wg_rhs). All contenders run in this process, interleaved
 * within each repetition, each continuing its own trajectory on the settled
 * orbit; the ratios are taken per repetition and the median is reported.
 * Steps are h = 2 pi/(omega N), N = 128; GSL's local time restarts every
 * mesh period, as ours does. Also: the bare kernel (no driver bookkeeping)
 * and the dependency-chain bound: the operations on the step's critical path
 * (tools/chainbound.py) priced at latencies timed in the same repetition. Times are thread CPU time (bench_common.h).
 * usage: bench_gsl [STEPS] [REPS] (--help: what they allow) */
#include "bench_args.h"
#include "bench_common.h"
#include "bench_lat.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_sim.h"
#include "internal.h" /* white box: the bare kernel of a wg_sim */

#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { N = 128, MAXREP = 31 };

typedef struct gslrun {
    bench_ode o;
    gsl_odeiv2_system sys;
    gsl_odeiv2_step *st;
    double y[14], yerr[14];
    int k; /* step within the period */
    double h;
} gslrun;

static void gsl_steps(gslrun *g, long n)
{
    for (long i = 0; i < n; i++) {
        gsl_odeiv2_step_apply(g->st, g->k * g->h, g->h, g->y, g->yerr, NULL, NULL, &g->sys);
        if (++g->k == N)
            g->k = 0; /* local time restarts at psi = 0 */
    }
}

static void hand_steps(bench_ode *o, double *y, int *k, double h, long n)
{
    for (long i = 0; i < n; i++) {
        bench_hand_rk4(o, *k * h, h, y);
        if (++*k == N)
            *k = 0;
    }
}

/* The specialised kernel alone (no driver bookkeeping: no contact or zone
 * checks, events, sections, time), stepping its own copy of the state with
 * the sim's table -- what the dependency-chain bound is compared with. */
static void bare_steps(const wg_sim *s, double *y, uint32_t *k, long n)
{
    double yb[2][WG_NSTATE_MAX];
    memcpy(yb[0], y, sizeof yb[0]);
    memcpy(yb[1], y, sizeof yb[1]);
    int cur = 0;
    uint32_t kk = *k, nn = (uint32_t)s->cfg.steps_per_period;
    for (long i = 0; i < n; i++) {
        s->core->kernel(yb[cur], yb[!cur], &s->core->kc, &s->core->table[2 * kk], s->h);
        cur = !cur;
        if (++kk == nn)
            kk = 0;
    }
    memcpy(y, yb[cur], sizeof yb[0]);
    *k = kk;
}

/* The dependency-chain bound on this machine, now: the critical path of one
 * RK4 step of the kernel, traced through its dataflow by tools/chainbound.py
 * (so many add/sub, multiplies and other single operations -- min, max,
 * logic, shuffles -- one after the other), each priced at its latency on
 * this CPU, timed as a chain of dependent operations in the same repetition
 * as the kernels, so frequency and CPU sharing cancel. The latencies differ
 * between CPUs (Zen 2/3: add 3 cycles, mul 3, min 1; this VM's Zen 5: add 2,
 * mul 3, min 2), so they are measured, not assumed. */
enum { CHAIN_FULL_ADD = 24, CHAIN_FULL_MUL = 12, CHAIN_FULL_OTHER = 4 };
enum { CHAIN_TORS_ADD = 22, CHAIN_TORS_MUL = 8, CHAIN_TORS_OTHER = 0 };

typedef struct row {
    const char *scene, *label;
    double omega;
    double target; /* issue 13's rk4-event / bound for this row (0: none) */
} row;

int main(int argc, char **argv)
{
    double steps = 2e6, nrep = 9;
    bench_arg args[] = {
        {"STEPS", "our steps a row times each repetition (GSL's and the hand RK4's a tenth, at "
                  "least 1000), a whole number from 1000 to 1e9 (default 2e6)", 1000, 1e9, &steps,
         NULL, 0},
        {"REPS", "repetitions, interleaved, each ratio the median, 1 to 31 (default 9)", 1,
         MAXREP, &nrep, NULL, 0}};
    int rc = bench_args("bench_gsl", "One RK4 step: our kernels against GSL's rk4 and a hand "
                        "RK4, and against the dependency-chain bound (issue 13, item 1). "
                        "WG_ISA=sse2|avx2|avx512|avx512vl: the kernels' set; WG_SCENE_PATH: "
                        "the scenes.", "", argc, argv, args, 2, NULL);
    if (rc >= 0)
        return rc;
    long n = (long)steps;
    int reps = (int)nrep;
    long ng = n / 10 > 1000 ? n / 10 : 1000; /* GSL and hand RK4 are ~10x slower */
    static const row rows[] = {
        {"table3", "table3 (no impact)", 0.5, 1.5},   {"table3", "table3 (impacting)", 0.7, 2.0},
        {"table3", "table3 (chaotic band)", 1.45, 0}, {"table3", "table3 (real-time point)", 2.5, 0},
        {"lowfreq", "lowfreq", 0.5, 0},
        {"realistic", "realistic", 0.5, 0},           {"torsional", "torsional", 0.5, 1.3},
    };
    enum { NROWS = sizeof rows / sizeof rows[0] };
    double event_ratio[NROWS]; /* rk4-event / bound, the median */
    gsl_set_error_handler_off();
    /* every row times a run alone: its own kernels (kernel_isa_one) */
    const char *isa = kernel_isa_name(kernel_isa_one(kernel_isa_choose())),
               *want = getenv("WG_ISA");
    printf("bench_gsl: N = %d, %ld steps (ours) / %ld (GSL, hand) x %d reps, medians; kernels "
           "for %s (a run's own; WG_ISA=sse2|avx2|avx512|avx512vl chooses)\n\n",
           N, n, ng, reps, isa);
    if (want && *want && strcmp(want, isa) != 0) /* misspelt, or a set this CPU lacks */
        printf("WG_ISA=%s is not a kernel set this CPU runs (sse2, avx2, avx512, avx512vl where "
               "the CPU has them): the %s kernels ran\n\n", want, isa);
    printf("| scene | omega | kernel (rk4) | bare kernel ns/step | rk4 ns/step | rk4-event ns/step "
           "| GSL rk4 ns/step (RHS calls) | hand RK4 ns/step | GSL / rk4 | GSL / rk4-event "
           "| hand / rk4 | rk4 / bare | chain bound ns (add+mul+other on the path; their ns) "
           "| bare / bound | rk4 / bound | rk4-event / bound |\n"
           "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    char why[600], kname[64];
    for (int r = 0; r < NROWS; r++) {
        wg_scene sc;
        if (wg_scene_open(&sc, rows[r].scene, why, sizeof why)) {
            fprintf(stderr, "bench_gsl: %s\n", why);
            return 1;
        }
        wg_params p = sc.p;
        p.v[WG_P_OMEGA] = rows[r].omega;
        wg_sim s[2];
        for (int st = 0; st < 2; st++) {
            wg_sim_config cfg = {WG_MODEL_CONSISTENT, st, N};
            if (wg_sim_init(&s[st], &p, &cfg, why, sizeof why)) {
                fprintf(stderr, "bench_gsl: %s\n", why);
                return 1;
            }
            wg_sim_run(&s[st], (uint64_t)N * 300, NULL, NULL); /* onto the orbit */
        }
        wg_sim_kernel_name(&s[0], kname, sizeof kname);
        double h = s[0].h;
        gslrun g = {.o = {&p, rows[r].omega, 0.0, 0}, .k = 0, .h = h};
        g.sys = (gsl_odeiv2_system){bench_gsl_rhs, NULL, 14, &g.o};
        g.st = gsl_odeiv2_step_alloc(gsl_odeiv2_step_rk4, 14);
        memcpy(g.y, s[0].y, sizeof g.y);
        bench_ode ho = {&p, rows[r].omega, 0.0, 0};
        double yh[14];
        int kh = 0;
        memcpy(yh, s[0].y, sizeof yh);
        double yk[WG_NSTATE_MAX];
        uint32_t kk = 0;
        memcpy(yk, s[0].y, sizeof yk);
        double la[MAXREP], lm[MAXREP], lo[MAXREP];
        double t[5][MAXREP], rg[MAXREP], rge[MAXREP], rh[MAXREP], rb[MAXREP];
        double bound[MAXREP], bb[MAXREP], br[MAXREP], bre[MAXREP];
        const int full = (s[0].core->kflags & KF_BEAR) != 0;
        const int na = full ? CHAIN_FULL_ADD : CHAIN_TORS_ADD;
        const int nm = full ? CHAIN_FULL_MUL : CHAIN_TORS_MUL;
        const int no = full ? CHAIN_FULL_OTHER : CHAIN_TORS_OTHER;
        uint64_t calls0 = g.o.nrhs;
        for (int i = 0; i < reps; i++) {
            for (int st = 0; st < 2; st++) {
                double t0 = bench_now_ns();
                if (wg_sim_run(&s[st], (uint64_t)n, NULL, NULL)) {
                    fprintf(stderr, "bench_gsl: blow-up\n");
                    return 1;
                }
                t[st][i] = (bench_now_ns() - t0) / (double)n;
            }
            double t0 = bench_now_ns();
            gsl_steps(&g, ng);
            t[2][i] = (bench_now_ns() - t0) / (double)ng;
            t0 = bench_now_ns();
            hand_steps(&ho, yh, &kh, h, ng);
            t[3][i] = (bench_now_ns() - t0) / (double)ng;
            t0 = bench_now_ns();
            bare_steps(&s[0], yk, &kk, n);
            t[4][i] = (bench_now_ns() - t0) / (double)n;
            rb[i] = t[0][i] / t[4][i];
            oplat L = dep_ns(20000000);
            la[i] = L.add, lm[i] = L.mul, lo[i] = L.other;
            bound[i] = na * L.add + nm * L.mul + no * L.other;
            bb[i] = t[4][i] / bound[i];
            br[i] = t[0][i] / bound[i];
            bre[i] = t[1][i] / bound[i];
            rg[i] = t[2][i] / t[0][i];
            rge[i] = t[2][i] / t[1][i];
            rh[i] = t[3][i] / t[0][i];
        }
        double calls = (double)(g.o.nrhs - calls0) / ((double)ng * reps);
        if (!isfinite(g.y[0]) || !isfinite(yh[0]) || !isfinite(yk[0]))
            fprintf(stderr, "bench_gsl: GSL or hand RK4 went non-finite on %s\n", rows[r].label);
        printf("| %s | %.2f | %s | %.1f | %.1f | %.1f | %.0f (%.0f) | %.0f | **%.2fx** | %.2fx | "
               "%.2fx | %.2fx | %.1f (%d+%d+%d; %.2f/%.2f/%.2f) | %.2fx | **%.2fx** | **%.2fx** |\n",
               rows[r].label, rows[r].omega, kname, bench_median(t[4], reps), bench_median(t[0], reps),
               bench_median(t[1], reps), bench_median(t[2], reps), calls,
               bench_median(t[3], reps), bench_median(rg, reps), bench_median(rge, reps),
               bench_median(rh, reps), bench_median(rb, reps), bench_median(bound, reps), na, nm,
               no, bench_median(la, reps), bench_median(lm, reps), bench_median(lo, reps),
               bench_median(bb, reps), bench_median(br, reps), bench_median(bre, reps));
        event_ratio[r] = bench_median(bre, reps);
        fflush(stdout);
        gsl_odeiv2_step_free(g.st);
        wg_sim_fini(&s[0]);
        wg_sim_fini(&s[1]);
    }
    printf("\nissue 13, item 1 (rk4-event / chain bound, medians of this run):");
    for (int r = 0, k = 0; r < NROWS; r++)
        if (rows[r].target > 0)
            printf("%s %s %.2fx (target %.1fx: %s)", k++ ? ";" : "", rows[r].label,
                   event_ratio[r], rows[r].target, event_ratio[r] <= rows[r].target ? "met" : "missed");
    printf("\n");
    /* the pieces: one reference RHS call, one libm excitation evaluation */
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = 0.7;
    double y[14], dy[14] = {0}, tr[MAXREP], te[MAXREP], acc = 0;
    wg_equilibrium(WG_MODEL_CONSISTENT, &p, y);
    wg_exc e;
    wg_exc_eval(&p, 0.3, 0.7, &e);
    const long m = n;
    for (int i = 0; i < reps; i++) {
        double t0 = bench_now_ns();
        for (long j = 0; j < m; j++) {
            y[6] += 1e-18 * dy[6 + (j & 1)]; /* chain the calls */
            wg_rhs(WG_MODEL_CONSISTENT, &p, &e, y, dy);
        }
        tr[i] = (bench_now_ns() - t0) / (double)m;
        t0 = bench_now_ns();
        for (long j = 0; j < m; j++) {
            wg_exc_eval(&p, 1e-6 * (double)j, 0.7, &e);
            acc += e.kp;
        }
        te[i] = (bench_now_ns() - t0) / (double)m;
    }
    printf("\nreal time at omega 2.5, N 128 is 1.62 M steps/s (MODEL.md s3): the share of one core "
           "is ns/step x 1.62e-3 (table3 row at 2.5).\n");
    printf("\nreference wg_rhs: %.1f ns/call; wg_exc_eval (libm): %.1f ns/call (checksum %.3g)\n",
           bench_median(tr, reps), bench_median(te, reps), acc + y[6]);
    return 0;
}

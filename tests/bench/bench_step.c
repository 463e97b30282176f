/* bench_step - ns per RK4 step of wg_sim_run for each scene, stepper and
 * kernel specialisation; the speedup of each specialised kernel over the
 * full one on the same scene. Timings are medians of REPS runs (for an even
 * REPS the mean of the middle two: bench_common.h's), measured in one
 * process. A specialisation is compared with the full kernel by giving the
 * dropped term a negligible nonzero value (1e-300 for b_j, k_a, e_m; mu =
 * 1e-300 for the torsional path), which selects the general kernel on an
 * otherwise identical scene. Last, the daemon's streaming path: every
 * step by the general step, for a per-step callback, in runs of 500 steps.
 * usage: bench_step [STEPS] [REPS] (--help: what they allow) */
#include "bench_args.h"
#include "bench_common.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_sim.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { MAXREP = 32 }; /* the timings a row keeps */

static void on_step(void *ctx, const wg_sim *s) { *(double *)ctx += s->y[6]; }

/* Median ns/step of `reps` runs of n steps (after a 200-period warm-up);
 * with `streamed`, an on_step sink (as the daemon's stream) and the run cut
 * into calls of 500 steps. */
static double time_steps(const wg_params *p, int stepper, int N, long n, int reps, char *kname,
                         double *splits_per_step, int streamed)
{
    wg_sim s;
    char why[300];
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, stepper, N};
    if (wg_sim_init(&s, p, &cfg, why, sizeof why)) {
        fprintf(stderr, "bench_step: %s\n", why);
        exit(1);
    }
    wg_sim_kernel_name(&s, kname, 64);
    wg_sim_run(&s, (uint64_t)N * 200, NULL, NULL); /* settle onto the orbit */
    double t[MAXREP];
    uint64_t sp0 = s.nsplit;
    double acc = 0.0;
    wg_sink sink = {&acc, on_step, NULL, NULL};
    const uint64_t chunk = streamed ? 500 : (uint64_t)n;
    const uint64_t total = ((uint64_t)n + chunk - 1) / chunk * chunk;
    for (int r = 0; r < reps; r++) { /* reps <= MAXREP: bench_args */
        double t0 = (double)cli_mono_ns();
        for (uint64_t done = 0; done < total; done += chunk)
            if (wg_sim_run(&s, chunk, streamed ? &sink : NULL, NULL)) {
                fprintf(stderr, "bench_step: blow-up\n");
                exit(1);
            }
        t[r] = ((double)cli_mono_ns() - t0) / (double)total;
    }
    *splits_per_step = (double)(s.nsplit - sp0) / ((double)total * reps);
    wg_sim_fini(&s);
    return bench_median(t, reps);
}

typedef struct row {
    const char *scene, *label, *set; /* set: "name=value" tweak or NULL */
    int stepper;
    double omega;
} row;

int main(int argc, char **argv)
{
    double steps = 2e6, nrep = 7;
    bench_arg args[] = {
        {"STEPS", "steps a row times each repetition, a whole number from 1000 to 1e9 "
                  "(default 2e6)", 1000, 1e9, &steps, NULL, 0},
        {"REPS", "repetitions a row takes the median of, 1 to 32 (default 7)", 1, MAXREP, &nrep,
         NULL, 0}};
    int rc = bench_args("bench_step", "The step's cost per scene, stepper and kernel "
                        "specialisation, in ns of wall time a step (WG_SCENE_PATH: the scenes).",
                        "", argc, argv, args, 2, NULL);
    if (rc >= 0)
        return rc;
    long n = (long)steps;
    int reps = (int)nrep;
    const int N = 128;
    static const row rows[] = {
        {"table3", "table3 (no impact)", NULL, WG_STEPPER_RK4, 0.5},
        {"table3", "table3 (no impact)", NULL, WG_STEPPER_RK4_EVENT, 0.5},
        {"table3", "table3 (impacting)", NULL, WG_STEPPER_RK4, 0.7},
        {"table3", "table3 (impacting)", NULL, WG_STEPPER_RK4_EVENT, 0.7},
        {"table3", "table3 (chaotic band)", NULL, WG_STEPPER_RK4_EVENT, 1.45},
        {"lowfreq", "lowfreq", NULL, WG_STEPPER_RK4_EVENT, 0.5},
        {"realistic", "realistic", NULL, WG_STEPPER_RK4_EVENT, 0.5},
        {"torsional", "torsional", NULL, WG_STEPPER_RK4, 0.5},
        {"torsional", "torsional", NULL, WG_STEPPER_RK4_EVENT, 0.5},
    };
    printf("bench_step: N = %d steps per period, %ld steps x %d reps (median)\n\n", N, n, reps);
    printf("| scene | omega | stepper | kernel | ns/step | Msteps/s | splits/step |\n");
    printf("|---|---|---|---|---|---|---|\n");
    char why[600], kname[64];
    for (unsigned i = 0; i < sizeof rows / sizeof rows[0]; i++) {
        wg_scene sc;
        if (wg_scene_open(&sc, rows[i].scene, why, sizeof why)) {
            fprintf(stderr, "bench_step: %s\n", why);
            return 1;
        }
        sc.p.v[WG_P_OMEGA] = rows[i].omega;
        double sps, ns = time_steps(&sc.p, rows[i].stepper, N, n, reps, kname, &sps, 0);
        printf("| %s | %.2f | %s | %s | %.1f | %.2f | %.4f |\n", rows[i].label, rows[i].omega,
               wg_stepper_name(rows[i].stepper), kname, ns, 1e3 / ns, sps);
    }
    /* Specialisation speedups: same scene, dropped term forced back in. */
    static const struct {
        const char *scene, *what;
        int id[2];
        double omega;
    } sp[] = {
        {"torsional", "rigid bearings: torsional path", {WG_P_MU1, WG_P_MU2}, 0.5},
        {"table3", "b_j = 0: linear bearings", {WG_P_B_J, -1}, 0.5},
        {"table3", "k_a = 0: constant mesh stiffness", {WG_P_K_A, -1}, 0.5},
        {"table3", "e_m = 0: no transmission error", {WG_P_E_M, -1}, 0.5},
    };
    printf("\n| specialisation (plain rk4, no impacts) | specialised ns/step | general ns/step "
           "| speedup |\n|---|---|---|---|\n");
    for (unsigned i = 0; i < sizeof sp / sizeof sp[0]; i++) {
        wg_scene sc;
        wg_scene_open(&sc, sp[i].scene, why, sizeof why);
        sc.p.v[WG_P_OMEGA] = sp[i].omega;
        wg_params a = sc.p, b = sc.p;
        for (int k = 0; k < 2 && sp[i].id[k] >= 0; k++) {
            a.v[sp[i].id[k]] = 0.0;
            b.v[sp[i].id[k]] = 1e-300;
        }
        char ka[64], kb[64];
        double s1, s2;
        double tb = time_steps(&b, WG_STEPPER_RK4, N, n, reps, kb, &s2, 0);
        double ta = time_steps(&a, WG_STEPPER_RK4, N, n, reps, ka, &s1, 0);
        printf("| %s (%s vs %s) | %.1f | %.1f | %.2fx |\n", sp[i].what, ka, kb, ta, tb, tb / ta);
    }
    wg_scene sc;
    wg_scene_open(&sc, "table3", why, sizeof why);
    sc.p.v[WG_P_OMEGA] = 2.5;
    double sps, ns = time_steps(&sc.p, WG_STEPPER_RK4_EVENT, N, n, reps, kname, &sps, 1);
    printf("\n| the daemon's stream: every step general (an on_step sink, runs of 500 steps) "
           "| ns/step |\n|---|---|\n| table3, omega 2.50, %s | %.1f |\n", kname, ns);
    return 0;
}

/* bench_long - 1e9 RK4 steps in fast mode (unpaced, sections only): table3
 * at omega = 2.5, N = 128, rk4-event -- the daemon's real-time operating
 * point. Prints ns/step per 1e8-step chunk, the multiple of physical real
 * time (1.62 M steps/s at this omega and N, MODEL.md s3), and the same
 * health figures the 1e8-step stress test asserts: phase wrapped, state
 * bounded, mean x_n of the first and last 10^4 periods, tau against
 * steps * h, resident-set high-water mark before and after.
 * usage: bench_long [STEPS] [SCENE] (--help: what they allow) */
#include "bench_args.h"
#include "proc_status.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_sim.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>

enum { N = 128, WINDOW = 10000 };

typedef struct acc {
    uint64_t sections, bad;
    double sum_xn, maxabs;
} acc;

static void on_sec(void *ctx, const wg_section *s)
{
    acc *a = ctx;
    double m = 0;
    for (int i = 0; i < 14; i++)
        m = fmax(m, fabs(s->y[i]));
    a->bad += !(m < 1e3) || !isfinite(s->out.xn);
    a->maxabs = fmax(a->maxabs, m);
    a->sum_xn += s->out.xn;
    a->sections++;
}

static double cpu_s(long *maxrss)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    *maxrss = ru.ru_maxrss;
    return (double)ru.ru_utime.tv_sec + 1e-6 * (double)ru.ru_utime.tv_usec +
           (double)ru.ru_stime.tv_sec + 1e-6 * (double)ru.ru_stime.tv_usec;
}

int main(int argc, char **argv)
{
    double steps = 1e9;
    const char *scene = "table3";
    bench_arg args[] = {
        {"STEPS", "steps timed, in chunks of 1e8, a whole number from 128 to 1e12 (default 1e9)",
         N, 1e12, &steps, NULL, 0},
        {"SCENE", "the scene, a name on WG_SCENE_PATH or a file (default table3)", 0, 0, NULL,
         &scene, 0}};
    int rc0 = bench_args("bench_long", "The 10^9-step run in fast mode at omega 2.5, N 128, "
                         "rk4-event: ns a step, the multiple of physical real time, and the "
                         "run's health.", "", argc, argv, args, 2, NULL);
    if (rc0 >= 0)
        return rc0;
    uint64_t total = (uint64_t)steps;
    char why[600];
    wg_scene sc;
    if (wg_scene_open(&sc, scene, why, sizeof why))
        return cli_usage_error("bench_long", "SCENE: %s", why);
    sc.p.v[WG_P_OMEGA] = 2.5;
    wg_sim s;
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, N};
    if (wg_sim_init(&s, &sc.p, &cfg, why, sizeof why)) {
        fprintf(stderr, "bench_long: %s\n", why);
        return 1;
    }
    acc a = {0, 0, 0, 0};
    wg_sink sink = {&a, NULL, on_sec, NULL};
    wg_sim_run(&s, (uint64_t)N * 1000, &sink, NULL); /* transient */
    a.sum_xn = 0;
    wg_sim_run(&s, (uint64_t)N * WINDOW, &sink, NULL);
    double mean0 = a.sum_xn / WINDOW;
    const uint64_t chunk = 100000000ull;
    uint64_t left = total - total % N, done_all = 0;
    printf("bench_long: %s, omega 2.5, N %d, rk4-event, %.3g steps in chunks of %.0e\n", scene, N,
           (double)left, (double)chunk);
    printf("| chunk | ns/step | x physical real time |\n|---|---|---|\n");
    fflush(stdout); /* stdio's buffer and printf's code in memory before the first reading */
    /* the anonymous resident memory (RssAnon: heap, stack; what a leak grows,
     * unlike code pages the kernel maps in as they run) */
    long rss0, rss1, anon0 = proc_status_kb(0, "RssAnon");
    double c0 = cpu_s(&rss0), t0 = cli_mono_s();
    for (int c = 1; left > 0; c++) {
        uint64_t n = left < chunk ? left : chunk, done = 0;
        double tc = cli_mono_s();
        int rc = wg_sim_run(&s, n, &sink, &done);
        double ns = (cli_mono_s() - tc) * 1e9 / (double)done;
        done_all += done;
        printf("| %d | %.1f | %.1fx |\n", c, ns, 1e9 / ns / 1.62e6);
        fflush(stdout);
        if (rc) {
            fprintf(stderr, "bench_long: %s after %llu steps\n", wg_status_name(rc),
                    (unsigned long long)done_all);
            return 1;
        }
        left -= n;
    }
    double wall = cli_mono_s() - t0, cpu = cpu_s(&rss1) - c0;
    long anon1 = proc_status_kb(0, "RssAnon");
    a.sum_xn = 0;
    wg_sim_run(&s, (uint64_t)N * WINDOW, &sink, NULL);
    double mean1 = a.sum_xn / WINDOW;
    long double exact = (long double)s.steps * (long double)s.h;
    printf("\n%llu steps in %.1f s wall, %.1f s CPU: %.1f ns/step (wall), %.2f M steps/s, "
           "%.1fx physical real time; 1x needs %.3f of one core by CPU time (%.3f by wall)\n",
           (unsigned long long)done_all, wall, cpu, wall * 1e9 / (double)done_all,
           (double)done_all / wall / 1e6, (double)done_all / wall / 1.62e6,
           1.62e6 * cpu / (double)done_all, 1.62e6 * wall / (double)done_all);
    printf("phase index k = %u (< %d), %llu periods, sections with a bad state: %llu, "
           "max |y| %.3f\n", s.k, N, (unsigned long long)s.period, (unsigned long long)a.bad,
           a.maxabs);
    printf("mean x_n over %d periods: before %.15f, after %.15f (diff %.2e)\n", WINDOW, mean0,
           mean1, fabs(mean1 - mean0));
    printf("tau %.9e, relative error vs steps * h %.2e; maxrss %ld kB before, %ld kB after\n",
           s.tau, (double)(fabsl((long double)s.tau - exact) / exact), rss0, rss1);
    printf("anonymous memory (RssAnon) %ld kB before, %ld kB after\n", anon0, anon1);
    wg_sim_fini(&s);
    return 0;
}

/* Long run: WG_LONGRUN_STEPS steps (1e8 in an optimised build, fewer under
 * the sanitizers; overridable with the environment variable of that name)
 * on table3 at omega = 2.5, N = 128, rk4-event: the daemon's real-time
 * operating point. Checks, every step, that the phase index stays wrapped
 * (k < N, psi in [0, 2 pi)); that the state stays bounded; that the mean of
 * x_n over the last 10^4 periods and the last Poincare point equal those of
 * a short run (no drift); that tau, accumulated with Kahan compensation,
 * equals steps * h; and that the resident-set high-water mark does not grow
 * (nothing is allocated per step). */
#include "stress.h"

#include <sys/resource.h>

#ifndef WG_LONGRUN_STEPS
#define WG_LONGRUN_STEPS 100000000
#endif

enum { N = 128, WINDOW = 10000 /* periods averaged */ };

typedef struct acc {
    uint64_t steps, bad_phase, sections, bad_state;
    long double sum_xn; /* over the averaging window */
    int averaging;
    double maxabs;
    double last[14];
} acc;

static void on_step(void *ctx, const wg_sim *s)
{
    acc *a = ctx;
    double psi = wg_sim_psi(s);
    a->bad_phase += !(s->k < N && psi >= 0.0 && psi < 2 * M_PI);
    if (a->averaging)
        a->sum_xn += wg_sim_xn(s); /* x_n at the end of the step */
    a->steps++;
}

static void on_sec(void *ctx, const wg_section *sec)
{
    acc *a = ctx;
    double m = stress_maxabs(sec->y, 14);
    a->bad_state += !(m < 10.0) || !isfinite(sec->out.xn);
    a->maxabs = fmax(a->maxabs, m);
    memcpy(a->last, sec->y, sizeof a->last);
    a->sections++;
}

static long maxrss_kb(void)
{
    struct rusage ru;
    getrusage(RUSAGE_SELF, &ru);
    return ru.ru_maxrss;
}

/* Mean x_n over the next WINDOW periods and the Poincare point at its end. */
static double window_mean(wg_sim *s, acc *a, const wg_sink *sink, double *pt)
{
    a->sum_xn = 0;
    a->averaging = 1;
    ASSERT_EQ_INT(wg_sim_run(s, (uint64_t)N * WINDOW, sink, NULL), WG_OK);
    a->averaging = 0;
    memcpy(pt, a->last, 14 * sizeof *pt);
    return (double)(a->sum_xn / ((long double)N * WINDOW));
}

static void test_long_run(void)
{
    uint64_t total = WG_LONGRUN_STEPS;
    const char *env = getenv("WG_LONGRUN_STEPS");
    if (env && atof(env) >= 1e6)
        total = (uint64_t)atof(env);
    wg_params p = stress_scene("table3");
    p.v[WG_P_OMEGA] = 2.5;
    wg_sim s;
    ASSERT_EQ_INT(test_sim_init(&s, &p, WG_STEPPER_RK4_EVENT, N), WG_OK);
    acc a;
    memset(&a, 0, sizeof a);
    wg_sink sink = {&a, on_step, on_sec, NULL};
    /* transient, then the short run's window */
    ASSERT_EQ_INT(wg_sim_run(&s, (uint64_t)N * 2000, &sink, NULL), WG_OK);
    double p0[14], p1[14];
    double m0 = window_mean(&s, &a, &sink, p0);
    uint64_t used = s.steps;
    long rss0 = maxrss_kb();
    /* the long middle, then the same window again */
    uint64_t mid = total > used + (uint64_t)N * WINDOW ? total - used - (uint64_t)N * WINDOW : 0;
    mid -= mid % N;
    ASSERT_EQ_INT(wg_sim_run(&s, mid, &sink, NULL), WG_OK);
    double m1 = window_mean(&s, &a, &sink, p1);
    long rss1 = maxrss_kb();
    double dp = 0;
    for (int i = 0; i < 14; i++)
        dp = fmax(dp, fabs(p1[i] - p0[i]));
    long double exact = (long double)s.steps * (long double)s.h;
    double tau_err = (double)fabsl((long double)s.tau - exact) / (double)exact;
    printf("  %llu steps (%s): %llu periods, k wrapped at every step (%llu violations), "
           "max|y| %.3f\n", (unsigned long long)s.steps,
           total >= 100000000 ? "the full 1e8" : "reduced count for this build",
           (unsigned long long)s.period, (unsigned long long)a.bad_phase, a.maxabs);
    printf("  mean x_n over %d periods: short run %.15f, after the long run %.15f (diff %.2e)\n",
           WINDOW, m0, m1, fabs(m1 - m0));
    printf("  Poincare point: max diff %.2e; tau %.6e, relative error vs steps*h %.2e\n", dp,
           s.tau, tau_err);
    printf("  maxrss %ld kB before, %ld kB after (+%ld kB)\n", rss0, rss1, rss1 - rss0);
    ASSERT_EQ_INT(s.steps, a.steps);
    ASSERT_TRUE(s.steps >= total - N);
    ASSERT_EQ_INT(a.bad_phase, 0);
    ASSERT_EQ_INT(a.bad_state, 0);
    ASSERT_EQ_INT(s.period, s.steps / N);
    ASSERT_EQ_INT(a.sections, s.period);
    ASSERT_EQ_INT(s.k, 0);
    ASSERT_TRUE(fabs(m1 - m0) < 1e-9);
    ASSERT_TRUE(dp < 1e-9);
    ASSERT_TRUE(tau_err < 1e-14);
    ASSERT_TRUE(rss1 - rss0 < 1024);
    wg_sim_fini(&s);
}

TEST_MAIN(TEST(test_long_run))

/* Early transient stop (wg_sweep_opts.settle) against the full transient on
 * the Table-3 study (table3, xi_p = 0.08, 0.10, 0.12, omega 0.1 .. 2.5 step
 * 0.01, up and down: 1,446 points; one group on a coarser grid under the
 * sanitizers). $WG_SETTLE_SCENE=NAME runs another scene the same way, at
 * its own xi_p.
 *
 * Per point: the full-transient study is run as chains; each point is then
 * analysed again from the very state its chain handed it, with early
 * stopping, and its regime, period and motion compared. The comparison
 * counts on the points where the full run is robust: analysed again from
 * its own final state (about twice as late) it has the same regime and
 * period. Every robust point must agree; the test prints the fraction.
 *
 * Per chain (printed, not asserted): the early-stopping study run as chains
 * of its own. Where two attractors coexist (hysteresis) or an orbit has
 * just lost stability, a chain follows whichever its seed leads to, and
 * seeds that differ in the last digits (a record that starts earlier ends
 * elsewhere on the same orbit) can pick the other one; the test prints how
 * many points that touches, and the wall time of both studies. */
#include "test.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_status.h"
#include "wormgear/wg_sweep.h"

#include <stdlib.h>
#include <time.h>
#include <unistd.h>

#ifdef WG_TEST_SLOW
static const double xis[] = {0.10};
#define OM_STEP 0.05
#else
static const double xis[] = {0.08, 0.10, 0.12};
#define OM_STEP 0.01
#endif
enum { NXI = sizeof xis / sizeof xis[0], NCH = 2 * NXI };

/* $WG_SETTLE_SCENE: another scene, at its own xi_p (one group) */
static const char *scene_name(void)
{
    const char *s = getenv("WG_SETTLE_SCENE");
    return s && *s ? s : "table3";
}

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int nthreads(void)
{
    long n = sysconf(_SC_NPROCESSORS_ONLN);
    return n < 1 ? 1 : n > 16 ? 16 : (int)n;
}

static wg_params scene(void)
{
    wg_scene sc;
    char why[256];
    int rc = wg_scene_open(&sc, scene_name(), why, sizeof why);
    if (rc)
        fprintf(stderr, "%s\n", why);
    ASSERT_EQ_INT(rc, WG_OK);
    return sc.p;
}

/* A chain of np points of omega over [0.1, 2.5] (or one point at v from
 * y0 when y0 is given). */
static wg_chain chain(const wg_params *p, int np, int dir, double v, const double *y0,
                      wg_point *pts)
{
    wg_chain c;
    memset(&c, 0, sizeof c);
    c.base = *p;
    c.param = WG_P_OMEGA;
    c.v0 = y0 ? v : 0.1;
    c.v1 = y0 ? v : 2.5;
    c.npts = np;
    c.dir = dir;
    c.param2 = -1;
    c.pts = pts;
    if (y0) {
        c.has_y0 = 1;
        memcpy(c.y0, y0, sizeof c.y0);
    }
    return c;
}

static int same(const wg_point *a, const wg_point *b, int motion)
{
    return a->regime == b->regime && a->period == b->period && (!motion || a->motion == b->motion);
}

/* Single-point chains over every point of the study cs: from the seed each
 * point had in its chain (prev = 1), or from its final state (prev = 0). */
static void points_again(const wg_chain *cs, int nch, int np, int prev, wg_chain *one,
                         wg_point *out)
{
    for (int k = 0; k < nch; k++) {
        for (int i = 0; i < np; i++) {
            const wg_point *pt = &cs[k].pts[i];
            double y[WG_NSTATE_MAX] = {0};
            wg_params p = cs[k].base;
            p.v[WG_P_OMEGA] = pt->value;
            if (!prev)
                memcpy(y, pt->y_end, sizeof y);
            else if (i == 0 || cs[k].pts[i - 1].regime == WG_REGIME_DIVERGED)
                wg_equilibrium(WG_MODEL_CONSISTENT, &p, y);
            else
                memcpy(y, cs[k].pts[i - 1].y_end, sizeof y);
            one[k * np + i] = chain(&p, 1, 1, pt->value, y, &out[k * np + i]);
        }
    }
}

static void test_early_stop_keeps_classification(void)
{
    const int ng = strcmp(scene_name(), "table3") == 0 ? NXI : 1, nch = 2 * ng;
    const int np = (int)floor(2.4 / OM_STEP + 0.5) + 1, n = nch * np;
    wg_params base = scene();
    wg_sweep_opts full, early;
    wg_sweep_opts_default(&early);
    ASSERT_EQ_INT(early.settle, 0); /* the whole transient is the default */
    early.settle = WG_SETTLE_WINDOW;
    full = early;
    full.settle = 0;
    wg_point *pf = calloc((size_t)n, sizeof *pf), *pe = calloc((size_t)n, sizeof *pe);
    wg_point *p1 = calloc((size_t)n, sizeof *p1), *pr = calloc((size_t)n, sizeof *pr);
    wg_chain cf[NCH], ce[NCH];
    wg_chain *one = calloc((size_t)n, sizeof *one), *rob = calloc((size_t)n, sizeof *rob);
    ASSERT_TRUE(pf && pe && p1 && pr && one && rob);
    for (int g = 0; g < ng; g++) {
        wg_params p = base;
        if (ng > 1)
            p.v[WG_P_XI_P] = xis[g];
        for (int d = 0; d < 2; d++) {
            cf[2 * g + d] = chain(&p, np, d ? -1 : 1, 0, NULL, &pf[(2 * g + d) * np]);
            ce[2 * g + d] = chain(&p, np, d ? -1 : 1, 0, NULL, &pe[(2 * g + d) * np]);
        }
    }
    double t0 = now_s();
    ASSERT_EQ_INT(wg_chains_run(cf, nch, &full, nthreads(), NULL, NULL, NULL), WG_OK);
    double t1 = now_s();
    ASSERT_EQ_INT(wg_chains_run(ce, nch, &early, nthreads(), NULL, NULL, NULL), WG_OK);
    double t2 = now_s();
    points_again(cf, nch, np, 1, one, p1);
    points_again(cf, nch, np, 0, rob, pr);
    ASSERT_EQ_INT(wg_chains_run(one, n, &early, nthreads(), NULL, NULL, NULL), WG_OK);
    ASSERT_EQ_INT(wg_chains_run(rob, n, &full, nthreads(), NULL, NULL, NULL), WG_OK);
    int robust = 0, agree = 0, chain_agree = 0, chain_robust = 0;
    for (int i = 0; i < n; i++) {
        if (!same(&pf[i], &pr[i], 0))
            continue;
        robust++;
        agree += same(&pf[i], &p1[i], 1);
        chain_robust++;
        chain_agree += same(&pf[i], &pe[i], 1);
        if (!same(&pf[i], &p1[i], 1))
            fprintf(stderr, "xi_p %.2f %s omega %.2f: full %s/%d/%s, early %s/%d/%s\n",
                    ng > 1 ? xis[i / (2 * np)] : base.v[WG_P_XI_P],
                    (i / np) % 2 ? "down" : "up", pf[i].value, wg_regime_name(pf[i].regime),
                    pf[i].period, wg_motion_name(pf[i].motion), wg_regime_name(p1[i].regime),
                    p1[i].period, wg_motion_name(p1[i].motion));
    }
    printf("scene %s: %d points; full run robust (same regime and period again ~2x later) on %d\n",
           scene_name(), n, robust);
    printf("per point, from the same seed: %d of %d robust points agree with early stopping "
           "(%.1f %%)\n", agree, robust, 100.0 * agree / (robust ? robust : 1));
    double mean = 0;
    for (int i = 0; i < n; i++)
        mean += (double)p1[i].transient / n;
    printf("mean transient with early stopping: %.0f periods (full: %d)\n", mean, full.transient);
    printf("per chain (continuation, informative): %d of %d agree (%.1f %%)\n", chain_agree,
           chain_robust, 100.0 * chain_agree / (chain_robust ? chain_robust : 1));
    printf("study wall time on %d thread(s): full transient %.2f s, early stop %.2f s\n",
           nthreads(), t1 - t0, t2 - t1);
    ASSERT_TRUE(robust > n * 9 / 10);
    ASSERT_EQ_INT(agree, robust);
    free(pf), free(pe), free(p1), free(pr), free(one), free(rob);
}

/* On a plain period-1 point early stopping runs a shorter transient and
 * ends on the full run's orbit (final states within the tolerance; the
 * times are printed, not tested), and a transient no longer than the
 * window runs whole. */
static void test_early_stop_saves_periods(void)
{
    wg_params p = scene();
    p.v[WG_P_OMEGA] = 0.5;
    wg_sweep_opts full, early;
    wg_sweep_opts_default(&early);
    early.settle = WG_SETTLE_WINDOW;
    full = early;
    full.settle = 0;
    double y0[WG_NSTATE_MAX] = {0}, yf[WG_NSTATE_MAX], ye[WG_NSTATE_MAX];
    wg_equilibrium(WG_MODEL_CONSISTENT, &p, y0);
    wg_point *a = malloc(sizeof *a), *b = malloc(sizeof *b);
    ASSERT_TRUE(a && b);
    char why[200];
    memcpy(yf, y0, sizeof yf);
    memcpy(ye, y0, sizeof ye);
    double t0 = now_s();
    ASSERT_EQ_INT(wg_point_run(&p, &full, yf, a, why, sizeof why), WG_OK);
    double t1 = now_s();
    ASSERT_EQ_INT(wg_point_run(&p, &early, ye, b, why, sizeof why), WG_OK);
    double t2 = now_s();
    ASSERT_TRUE(same(a, b, 1) && a->period == 1);
    /* the same orbit at the same phase: final states within the tolerance */
    double d = 0;
    for (int j = 0; j < 14; j++)
        d = fmax(d, fabs(yf[j] - ye[j]));
    ASSERT_TRUE(d <= a->tol);
    printf("omega 0.5 from equilibrium: transient %d -> %d periods, %.1f -> %.1f ms, final "
           "states %.2g apart (tol %.2g)\n", a->transient, b->transient, 1e3 * (t1 - t0),
           1e3 * (t2 - t1), d, a->tol);
    ASSERT_EQ_INT(a->transient, 300);
    ASSERT_TRUE(b->transient >= 64 && b->transient < 300);
    /* a transient no longer than the window runs whole: the same bits */
    full.transient = early.transient = 64;
    memcpy(yf, y0, sizeof yf);
    memcpy(ye, y0, sizeof ye);
    ASSERT_EQ_INT(wg_point_run(&p, &full, yf, a, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_point_run(&p, &early, ye, b, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(memcmp(yf, ye, sizeof yf), 0);
    free(a), free(b);
}

TEST_MAIN(TEST(test_early_stop_keeps_classification), TEST(test_early_stop_saves_periods))

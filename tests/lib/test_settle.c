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
 * many points that touches, and the wall time of both studies.
 *
 * Then two single points of table3 (whatever the scene): a plain period-1
 * point, and one seeded just past a period doubling on the period-1 orbit
 * being left, where the early-stopped record must see it go. */
#include "test.h"
#include "internal.h" /* la_solve */
#include "wormgear/wg_scene.h"
#include "wormgear/wg_shoot.h"
#include "wormgear/wg_status.h"
#include "wormgear/wg_sweep.h"

#include <math.h>
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

static wg_params scene_named(const char *name)
{
    wg_scene sc;
    char why[256];
    int rc = wg_scene_open(&sc, name, why, sizeof why);
    if (rc)
        fprintf(stderr, "%s\n", why);
    ASSERT_EQ_INT(rc, WG_OK);
    return sc.p;
}

/* The study's scene (table3, or $WG_SETTLE_SCENE). */
static wg_params scene(void) { return scene_named(scene_name()); }

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

/* On a plain period-1 point (table3) early stopping runs a shorter transient and
 * ends on the full run's orbit (final states within the tolerance; the
 * times are printed, not tested), and a transient no longer than the
 * window runs whole. */
static void test_early_stop_saves_periods(void)
{
    wg_params p = scene_named("table3");
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
    ASSERT_TRUE(b->transient >= WG_SETTLE_WINDOW && b->transient < 300);
    /* a transient no longer than the window runs whole: the same bits */
    full.transient = early.transient = WG_SETTLE_WINDOW;
    memcpy(yf, y0, sizeof yf);
    memcpy(ye, y0, sizeof ye);
    ASSERT_EQ_INT(wg_point_run(&p, &full, yf, a, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_point_run(&p, &early, ye, b, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(memcmp(yf, ye, sizeof yf), 0);
    free(a), free(b);
}

/* v <- the eigenvector of the n x n matrix A (row-major) whose eigenvalue
 * is nearest `shift`, by inverse iteration (la_solve on A - shift I),
 * max-norm 1. */
static void eigenvector_near(const double *A, int n, double shift, double *v)
{
    for (int i = 0; i < n; i++)
        v[i] = 1.0 + 0.1 * i;
    for (int it = 0; it < 40; it++) {
        double a[WG_NSTATE_MAX * WG_NSTATE_MAX], nrm = 0.0;
        for (int i = 0; i < n * n; i++)
            a[i] = A[i] - (i % (n + 1) == 0 ? shift : 0.0);
        ASSERT_EQ_INT(la_solve(n, a, v), WG_OK);
        for (int i = 0; i < n; i++)
            nrm = fmax(nrm, fabs(v[i]));
        for (int i = 0; i < n; i++)
            v[i] /= nrm;
    }
}

/* Just past a period doubling the period-1 orbit is left slowly: seeded on
 * it with a slowly decaying flip mode (multiplier -0.94) of 1e-7 and the
 * growing one (-1.053) of 1e-12, an early-stopped transient sees lag-1
 * residuals falling and settles on period 1, while the flip mode grows
 * through the record and by the full transient's record has made the
 * orbit period 2. Early stopping must say period 2 as well: the record
 * shows its residual growing, and the point is extended. (table3, xi_p
 * 0.12, omega 0.93, where a period-2 orbit coexists with two period-1
 * ones; the orbit is found by Newton from a state near the period-2 one.) */
static void test_early_stop_orbit_being_left(void)
{
    static const double near_p2[14] = {
        -0.99775106599114871, -0.99688905021092256, 0.99175390863420454,
        0.98816997306181953,  0.99688571995679631,  -0.8543783546311825,
        4.1853943909205586,   -0.043026838705395032, -0.059519014016541798,
        0.15776507525311415,  -0.00014312178751131079, 0.0062797248207628166,
        0.0084506132050081346, 0.35111178301356277};
    wg_params p = scene_named("table3");
    p.v[WG_P_XI_P] = 0.12;
    p.v[WG_P_OMEGA] = 0.93;
    wg_sim s;
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, 256};
    char why[200];
    ASSERT_EQ_INT(wg_sim_init(&s, &p, &cfg, why, sizeof why), WG_OK);
    double x[WG_NSTATE_MAX] = {0}, resid, wr[WG_NSTATE_MAX], wi[WG_NSTATE_MAX];
    memcpy(x, near_p2, sizeof near_p2);
    wg_orbit *o = malloc(sizeof *o);
    ASSERT_TRUE(o != NULL);
    ASSERT_EQ_INT(wg_orbit_refine(&s, 1, x, 1e-12, 30, &resid, o), WG_OK);
    ASSERT_EQ_INT(wg_orbit_floquet(o, wr, wi), WG_OK);
    printf("period-1 orbit at xi_p 0.12, omega 0.93: residual %.2g, multipliers %.4f, %.4f\n",
           resid, wr[0], wr[1]);
    /* the scenario: one flip multiplier just past -1, the next near it */
    ASSERT_TRUE(wr[0] < -1.02 && wr[0] > -1.1 && wi[0] == 0.0);
    ASSERT_TRUE(wr[1] < -0.9 && wr[1] > -0.98 && wi[1] == 0.0);
    double grow[WG_NSTATE_MAX], slow[WG_NSTATE_MAX], y[2][WG_NSTATE_MAX];
    eigenvector_near(o->M, o->dim, wr[0] + 1e-3, grow);
    eigenvector_near(o->M, o->dim, wr[1] + 1e-3, slow);
    wg_sweep_opts full, early;
    wg_sweep_opts_default(&full);
    early = full;
    early.settle = WG_SETTLE_WINDOW;
    wg_point *pt = calloc(2, sizeof *pt);
    ASSERT_TRUE(pt != NULL);
    for (int k = 0; k < 2; k++) {
        memcpy(y[k], x, sizeof y[k]);
        for (int i = 0; i < o->dim; i++)
            y[k][o->idx[i]] += 1e-12 * grow[i] + 1e-7 * slow[i];
        ASSERT_EQ_INT(wg_point_run(&p, k ? &early : &full, y[k], &pt[k], why, sizeof why), WG_OK);
    }
    printf("seeded on it: full transient period %d, early stop period %d (first transient %d)\n",
           pt[0].period, pt[1].period, pt[1].transient);
    ASSERT_EQ_INT(pt[0].period, 2);
    ASSERT_TRUE(same(&pt[0], &pt[1], 1));
    ASSERT_TRUE(pt[1].transient < 300); /* it did stop early: the record check saved it */
    free(pt);
    free(o);
    wg_sim_fini(&s);
}

TEST_MAIN(TEST(test_early_stop_keeps_classification), TEST(test_early_stop_saves_periods),
          TEST(test_early_stop_orbit_being_left))

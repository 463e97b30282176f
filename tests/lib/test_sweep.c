/* Real sweeps of the table3 scene: a known period-doubling cascade
 * (P1 -> P2 between omega 1.19 and 1.20, P2 -> P4 between 1.21 and 1.22)
 * found by the sweep and predicted by a Floquet multiplier crossing -1; the
 * LLE sign of a chaotic and a periodic point; the error estimate behind the
 * period tolerance; threads giving the same bytes as one thread, also when
 * a chain moves between them; Ctrl-C. */
#include "test.h"
#include "sweep.h" /* chains_run: the hand-offs counted */
#include "wormgear/wg_scene.h"
#include "wormgear/wg_status.h"
#include "wormgear/wg_shoot.h"
#include "wormgear/wg_sweep.h"

#include <pthread.h>
#include <stddef.h>
#include <string.h>

static wg_params table3(void)
{
    wg_scene sc;
    char why[256];
    int rc = wg_scene_open(&sc, "table3", why, sizeof why);
    if (rc)
        fprintf(stderr, "%s\n", why);
    ASSERT_EQ_INT(rc, WG_OK);
    return sc.p;
}

static wg_chain chain(const wg_params *p, double v0, double v1, int n, int dir, wg_point *pts)
{
    wg_chain c;
    memset(&c, 0, sizeof c);
    c.base = *p;
    c.param = WG_P_OMEGA;
    c.v0 = v0;
    c.v1 = v1;
    c.npts = n;
    c.dir = dir;
    c.param2 = -1;
    c.pts = pts;
    return c;
}

static const wg_transition *find_pd(const wg_transition *t, int n, int from)
{
    for (int i = 0; i < n; i++)
        if (t[i].kind == WG_TR_DOUBLING && t[i].dir == +1 && t[i].from == from)
            return &t[i];
    return NULL;
}

/* Real part of the dominant multiplier (largest modulus, real) of the
 * period-n orbit refined by Newton from y at omega (y becomes the orbit).
 * Near the P2 -> P4 doubling the dominant multiplier is an exact double
 * pair (the two bearing directions of a body normal to the line of action
 * are symmetric), so the QR may return it with a tiny imaginary part. */
static double neg_multiplier(wg_sim *sim, wg_params p, double omega, int n, double *y)
{
    char why[256];
    p.v[WG_P_OMEGA] = omega;
    ASSERT_EQ_INT(wg_sim_set_params(sim, &p, why, sizeof why), WG_OK);
    double res, wr[WG_NSTATE_MAX], wi[WG_NSTATE_MAX];
    wg_orbit *o = malloc(sizeof *o);
    ASSERT_EQ_INT(wg_orbit_refine(sim, n, y, 1e-10, 10, &res, o), WG_OK);
    ASSERT_EQ_INT(wg_orbit_floquet(o, wr, wi), WG_OK);
    free(o);
    ASSERT_TRUE(fabs(wi[0]) < 1e-3);
    return wr[0];
}

static void test_period_doubling_sweep_and_floquet(void)
{
    wg_params p = table3();
    static wg_point pts[6];
    wg_sweep_opts o;
    wg_sweep_opts_default(&o);
    o.floquet = 1;
    wg_chain c = chain(&p, 1.17, 1.22, 6, +1, pts);
    ASSERT_EQ_INT(wg_chains_run(&c, 1, &o, 1, NULL, NULL, NULL), WG_OK);
    ASSERT_EQ_INT(c.ndone, 6);
    wg_transition t[32];
    int nt = wg_transitions(pts, 6, NULL, 0, p.v[WG_P_B], t, 32);
    const wg_transition *pd[2] = {find_pd(t, nt, 1), find_pd(t, nt, 2)};
    ASSERT_TRUE(pd[0] && pd[1]);
    if (!pd[0] || !pd[1])
        return;
    ASSERT_NEAR(pd[0]->lo, 1.19, 1e-12);
    ASSERT_NEAR(pd[1]->lo, 1.21, 1e-12);
    /* the sweep's own multipliers just below each doubling: near -1, above */
    ASSERT_TRUE(pts[2].nfloq == 14 && pts[2].floq_re[0] < -0.7 && pts[2].floq_re[0] > -1.0);
    ASSERT_TRUE(pts[4].nfloq == 14 && pts[4].floq_re[0] < -0.9 && pts[4].floq_re[0] > -1.0);
    /* Floquet: follow the period-n orbit across the bracket (unstable past
     * it) and locate the multiplier crossing -1 inside the bracket */
    wg_sim sim;
    char why[256];
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, pts[0].steps};
    ASSERT_EQ_INT(wg_sim_init(&sim, &p, &cfg, why, sizeof why), WG_OK);
    for (int k = 0; k < 2; k++) {
        int i = k == 0 ? 2 : 4, n = k == 0 ? 1 : 2;
        double y[WG_NSTATE_MAX];
        memcpy(y, pts[i].y_end, sizeof y);
        double mlo = neg_multiplier(&sim, p, pd[k]->lo, n, y);
        double mhi = neg_multiplier(&sim, p, pd[k]->hi, n, y);
        ASSERT_TRUE(mlo > -1.0);
        ASSERT_TRUE(mhi < -1.0);
        double wstar = pd[k]->lo + (pd[k]->hi - pd[k]->lo) * (-1.0 - mlo) / (mhi - mlo);
        printf("  doubling P%d -> P%d: sweep bracket (%.3f, %.3f), Floquet -1 at %.4f "
               "(multipliers %.4f, %.4f)\n", n, 2 * n, pd[k]->lo, pd[k]->hi, wstar, mlo, mhi);
        ASSERT_TRUE(wstar > pd[k]->lo && wstar < pd[k]->hi);
    }
    wg_sim_fini(&sim);
}

static void test_lle_sign_on_the_model(void)
{
    wg_params p = table3();
    wg_sweep_opts o;
    wg_sweep_opts_default(&o);
    o.extend = 1;
    double y[WG_NSTATE_MAX];
    wg_point pt;
    char why[256];
    p.v[WG_P_OMEGA] = 0.70; /* chaotic from the equilibrium (single-sided impacts) */
    wg_equilibrium(WG_MODEL_CONSISTENT, &p, y);
    ASSERT_EQ_INT(wg_point_run(&p, &o, y, &pt, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(pt.regime, WG_REGIME_CHAOTIC);
    ASSERT_TRUE(pt.lle > 0.1);
    /* a stable period-1 orbit: the exponent is log |largest multiplier| */
    p.v[WG_P_OMEGA] = 0.85;
    wg_equilibrium(WG_MODEL_CONSISTENT, &p, y);
    o.floquet = 1;
    ASSERT_EQ_INT(wg_point_run(&p, &o, y, &pt, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(pt.regime, WG_REGIME_PERIODIC);
    ASSERT_EQ_INT(pt.period, 1);
    wg_sim a, b;
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, pt.steps};
    ASSERT_EQ_INT(wg_sim_init(&a, &p, &cfg, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_sim_init(&b, &p, &cfg, why, sizeof why), WG_OK);
    wg_simmap sa = {&a, 1, NULL, NULL}, sb = {&b, 1, NULL, NULL};
    wg_map ma = wg_simmap_map(&sa), mb = wg_simmap_map(&sb);
    double lle;
    ASSERT_EQ_INT(wg_lle_twin(&ma, &mb, y, 300, 1e-7, &lle), WG_OK);
    ASSERT_TRUE(lle < 0.0);
    ASSERT_NEAR(lle, log(hypot(pt.floq_re[0], pt.floq_im[0])), 0.02);
    wg_sim_fini(&a);
    wg_sim_fini(&b);
}

/* run2 of wg_lle_sims: each sim in turn by wg_sim_run, counted. */
static int run2_in_turn(void *ctx, wg_sim *a, wg_sim *b, uint64_t n)
{
    ++*(int *)ctx;
    int rc = wg_sim_run(a, n, NULL, NULL);
    int rb = wg_sim_run(b, n, NULL, NULL);
    return rc ? rc : rb;
}

/* wg_lle_sims (both trajectories advanced at once: paired, or by a run2)
 * gives wg_lle_twin's exponent and end state to the bit: on a chaotic
 * point and on a periodic one; a sim given twice, or two of different N,
 * is refused. */
static void test_lle_sims(void)
{
    wg_params p = table3();
    char why[256];
    for (int k = 0; k < 2; k++) {
        p.v[WG_P_OMEGA] = k ? 0.85 : 0.70;
        double y[3][WG_NSTATE_MAX], lle[3];
        wg_sim s[6];
        wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, 128};
        for (int j = 0; j < 6; j++)
            ASSERT_EQ_INT(wg_sim_init(&s[j], &p, &cfg, why, sizeof why), WG_OK);
        int calls = 0;
        for (int m = 0; m < 3; m++) { /* from the scene's state onto the attractor */
            wg_sim_run(&s[2 * m], 200 * 128, NULL, NULL);
            memcpy(y[m], s[2 * m].y, sizeof y[m]);
        }
        wg_simmap sa = {&s[0], 1, NULL, NULL}, sb = {&s[1], 1, NULL, NULL};
        wg_map ma = wg_simmap_map(&sa), mb = wg_simmap_map(&sb);
        ASSERT_EQ_INT(wg_lle_twin(&ma, &mb, y[0], 150, 1e-7, &lle[0]), WG_OK);
        ASSERT_EQ_INT(wg_lle_sims(&s[2], &s[3], y[1], 150, 1e-7, NULL, NULL, &lle[1]), WG_OK);
        ASSERT_EQ_INT(wg_lle_sims(&s[4], &s[5], y[2], 150, 1e-7, run2_in_turn, &calls, &lle[2]),
                      WG_OK);
        ASSERT_EQ_INT(calls, 150);
        for (int m = 1; m < 3; m++) {
            ASSERT_TRUE(memcmp(&lle[m], &lle[0], sizeof lle[0]) == 0);
            ASSERT_TRUE(memcmp(y[m], y[0], sizeof y[0]) == 0);
            ASSERT_TRUE(memcmp(s[2 * m + 1].y, s[1].y, sizeof s[1].y) == 0); /* the twins */
        }
        ASSERT_TRUE(k ? lle[0] < 0.0 : lle[0] > 0.1);
        printf("omega %.2f: LLE %.6f per period, the same bits three ways\n",
               p.v[WG_P_OMEGA], lle[0]);
        ASSERT_EQ_INT(wg_lle_sims(&s[0], &s[0], y[0], 10, 1e-7, NULL, NULL, &lle[0]), WG_EINVAL);
        for (int j = 0; j < 6; j++)
            wg_sim_fini(&s[j]);
        wg_sim_config c2 = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, 256};
        ASSERT_EQ_INT(wg_sim_init(&s[0], &p, &cfg, why, sizeof why), WG_OK);
        ASSERT_EQ_INT(wg_sim_init(&s[1], &p, &c2, why, sizeof why), WG_OK);
        ASSERT_EQ_INT(wg_lle_sims(&s[0], &s[1], y[0], 10, 1e-7, NULL, NULL, &lle[0]), WG_EINVAL);
        wg_sim_fini(&s[0]);
        wg_sim_fini(&s[1]);
    }
}

/* A blow-up in either trajectory: wg_lle_sims returns what wg_lle_twin
 * returns (the base's status first, then the twin's) and leaves x where
 * it leaves it, through the pair and through a run2. */
static void test_lle_sims_blowup(void)
{
    wg_params p = table3();
    char why[256];
    p.v[WG_P_OMEGA] = 0.70;
    for (int twin_fails = 0; twin_fails < 2; twin_fails++) {
        wg_sim s[6];
        wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, 128};
        for (int j = 0; j < 6; j++)
            ASSERT_EQ_INT(wg_sim_init(&s[j], &p, &cfg, why, sizeof why), WG_OK);
        double y[3][WG_NSTATE_MAX], lle[3] = {-1, -1, -1};
        int rc[3], calls = 0;
        for (int m = 0; m < 3; m++) {
            memcpy(y[m], s[0].y, sizeof y[m]);
            if (twin_fails) /* d0 so large the twin starts far out */
                continue;
            y[m][6] = 6e8; /* the mesh far past its clearance: NaN within a period */
        }
        const double d0 = twin_fails ? 6e8 : 1e-7;
        wg_simmap sa = {&s[0], 1, NULL, NULL}, sb = {&s[1], 1, NULL, NULL};
        wg_map ma = wg_simmap_map(&sa), mb = wg_simmap_map(&sb);
        rc[0] = wg_lle_twin(&ma, &mb, y[0], 50, d0, &lle[0]);
        rc[1] = wg_lle_sims(&s[2], &s[3], y[1], 50, d0, NULL, NULL, &lle[1]);
        rc[2] = wg_lle_sims(&s[4], &s[5], y[2], 50, d0, run2_in_turn, &calls, &lle[2]);
        ASSERT_EQ_INT(rc[0], WG_ENONFINITE);
        for (int m = 1; m < 3; m++) {
            ASSERT_EQ_INT(rc[m], rc[0]);
            ASSERT_TRUE(memcmp(y[m], y[0], sizeof y[0]) == 0);
            ASSERT_TRUE(lle[m] == -1); /* not written */
        }
        printf("%s blows up: %s from each, x the same\n", twin_fails ? "the twin" : "the base",
               wg_status_str(rc[0]));
        for (int j = 0; j < 6; j++)
            wg_sim_fini(&s[j]);
    }
}

static void test_error_estimate_order(void)
{
    /* the one-period error behind the tolerance falls ~16x per halving of h
     * on a non-impacting orbit (RK4, order 4) */
    wg_params p = table3();
    p.v[WG_P_OMEGA] = 2.0;
    wg_sweep_opts o;
    wg_sweep_opts_default(&o);
    double err[2];
    for (int k = 0; k < 2; k++) {
        double y[WG_NSTATE_MAX];
        wg_point pt;
        char why[256];
        o.steps = k ? 256 : 128;
        wg_equilibrium(WG_MODEL_CONSISTENT, &p, y);
        ASSERT_EQ_INT(wg_point_run(&p, &o, y, &pt, why, sizeof why), WG_OK);
        ASSERT_EQ_INT(pt.period, 1);
        ASSERT_NEAR(pt.tol, fmax(o.tol_floor, o.tol_factor * pt.err), 0.0);
        err[k] = pt.err;
    }
    printf("  one-period error: N=128 %.3e, N=256 %.3e, ratio %.1f\n", err[0], err[1],
           err[0] / err[1]);
    ASSERT_TRUE(err[0] / err[1] > 10.0 && err[0] / err[1] < 24.0);
}

static void test_threads_identical(void)
{
    wg_params p = table3();
    wg_sweep_opts o;
    wg_sweep_opts_default(&o);
    o.transient = 150;
    enum { NC = 4, NP = 4 };
    static wg_point a[NC][NP], b[NC][NP];
    wg_chain ca[NC], cb[NC];
    for (int i = 0; i < NC; i++) {
        wg_params q = p;
        q.v[WG_P_XI_P] = i < 2 ? 0.08 : 0.10;
        ca[i] = chain(&q, 1.18, 1.21, NP, i % 2 ? -1 : 1, a[i]);
        cb[i] = chain(&q, 1.18, 1.21, NP, i % 2 ? -1 : 1, b[i]);
    }
    ASSERT_EQ_INT(wg_chains_run(ca, NC, &o, 1, NULL, NULL, NULL), WG_OK);
    ASSERT_EQ_INT(wg_chains_run(cb, NC, &o, 2, NULL, NULL, NULL), WG_OK);
    for (int i = 0; i < NC; i++) {
        ASSERT_EQ_INT(ca[i].ndone, NP);
        ASSERT_EQ_INT(cb[i].ndone, NP);
        ASSERT_TRUE(memcmp(a[i], b[i], sizeof a[i]) == 0);
    }
}

/* A chain taken up by another thread between two of its points (its
 * workspace and seed moved with it) gives the same points, to the bit, as
 * one thread running each chain whole. The pool deals chains 0, 3, 4 to the
 * first thread and 1, 2, 5 to the second: these last have one point each,
 * so the second thread is soon without a chain while the first runs three,
 * and asks it for one (chains_run counts the moves). Through the period
 * doubling, the chaotic band (extensions, the LLE's twin) and impacts, with
 * and without the 2N checks as jobs (drained before a chain moves). A
 * thread slow to start may find no chain worth asking for: up to five
 * tries, and one must have moved a chain (the first did in 59 of 60 runs
 * here, the second in the other). */
static void test_handoff_identical(void)
{
    wg_params p = table3();
    wg_sweep_opts o;
    wg_sweep_opts_default(&o);
    o.transient = 100;
    o.settle = 32;
    o.extend = 1;
    o.lle_periods = 100;
    o.record = 64;
    enum { NC = 6, NP = 6 };
    /* xi_p, omega from, to, points: the chaotic chain's three points take
     * as long as the others' six, so all three run while the second thread
     * finishes its own (and, with the checks, helps with the first's) */
    static const double span[NC][4] = {{0.08, 1.19, 1.24, 6}, {0.10, 1.0, 1.0, 1},
                                       {0.12, 2.0, 2.0, 1},   {0.10, 1.46, 1.48, 3},
                                       {0.10, 0.70, 0.75, 6}, {0.12, 0.5, 0.5, 1}};
    static wg_point ref[NC][NP], pts[NC][NP];
    for (int verify = 0; verify <= 1; verify++) {
        o.verify = verify;
        wg_chain c[NC];
        for (int run = 0; run < 6; run++) {
            for (int i = 0; i < NC; i++) {
                wg_params q = p;
                q.v[WG_P_XI_P] = span[i][0];
                c[i] = chain(&q, span[i][1], span[i][2], (int)span[i][3], 1,
                             run ? pts[i] : ref[i]);
            }
            int moves = 0;
            ASSERT_EQ_INT(chains_run(c, NC, &o, run ? 2 : 1, NULL, NULL, NULL, &moves),
                          WG_OK);
            if (!run) {
                ASSERT_EQ_INT(moves, 0); /* one thread: none to move to */
                continue;
            }
            for (int i = 0; i < NC; i++) {
                ASSERT_EQ_INT(c[i].ndone, c[i].npts);
                ASSERT_TRUE(memcmp(pts[i], ref[i], sizeof(wg_point) * (size_t)c[i].npts) == 0);
            }
            int aperiodic = 0, impacting = 0;
            for (int j = 0; j < c[3].npts; j++)
                aperiodic += pts[3][j].regime != WG_REGIME_PERIODIC;
            for (int j = 0; j < c[4].npts; j++)
                impacting += pts[4][j].motion != WG_MOTION_NO_IMPACT;
            printf("  hand-off: verify %d, try %d: %d chain(s) moved, points compared bitwise "
                   "(%d aperiodic, %d impacting)\n", verify, run, moves, aperiodic, impacting);
            ASSERT_TRUE(aperiodic > 0 && impacting > 0);
            if (moves > 0)
                break;
            ASSERT_TRUE(run < 5);
        }
    }
}

/* Chains advanced o.pair at a time on a thread (their runs paired by
 * wg_sim_run_pair, or, three or more on AVX2 or AVX-512, batched by
 * wg_sim_run_batch) give the same points, to the bit, as one at a time: on
 * one thread (five runs batched), and on two with more tasks than chains
 * (up to three a thread, batched or paired), through early-stopped
 * transients, extensions, the LLE of aperiodic points, N raised at low
 * omega (runs of different N paired), impacts, and the 2N check. */
static void test_pairs_identical(void)
{
    wg_params p = table3();
    wg_sweep_opts o;
    wg_sweep_opts_default(&o);
    ASSERT_EQ_INT(o.pair, 8);
    o.transient = 150;
    o.settle = 32;
    o.verify = 1;
    enum { NC = 5, NP = 2, NK = 4 };
    static const double span[NC][3] = {{0.08, 1.18, 1.21}, {0.10, 1.21, 1.18}, {0.10, 0.70, 0.72},
                                       {0.12, 0.03, 0.04}, {0.10, 1.45, 1.47}};
    static const int pair[NK] = {1, 2, 8, 8}, threads[NK] = {1, 1, 2, 1};
    static wg_point pts[NK][NC][NP];
    int steps[NC] = {0}, aperiodic = 0;
    for (int k = 0; k < NK; k++) {
        wg_chain c[NC];
        for (int i = 0; i < NC; i++) {
            wg_params q = p;
            q.v[WG_P_XI_P] = span[i][0];
            c[i] = chain(&q, span[i][1], span[i][2], NP, 1, pts[k][i]);
        }
        o.pair = pair[k];
        ASSERT_EQ_INT(wg_chains_run(c, NC, &o, threads[k], NULL, NULL, NULL), WG_OK);
        for (int i = 0; i < NC; i++) {
            ASSERT_EQ_INT(c[i].ndone, NP);
            ASSERT_TRUE(memcmp(pts[k][i], pts[0][i], sizeof pts[0][i]) == 0);
            steps[i] = pts[k][i][0].steps;
            for (int j = 0; j < NP && k == 0; j++)
                aperiodic += pts[0][i][j].regime != WG_REGIME_PERIODIC;
        }
    }
    printf("  pairs: %d chains x %d points, pair 1/2/8 (2 threads)/8, N %d and %d, %d aperiodic, "
           "compared bitwise\n", NC, NP, steps[0], steps[3], aperiodic);
    ASSERT_TRUE(steps[3] > steps[0]); /* a low-omega chain ran with a raised N */
    ASSERT_TRUE(aperiodic > 0);
}

/* Progress seen by test_checks_in_flight: per chain, the counts in the
 * order they came; a stop asked once chain 0 has `halt_at` points. */
enum { CF_NC = 3, CF_NP = 8 };
typedef struct cflog {
    pthread_mutex_t lock;
    int n[CF_NC], seq[CF_NC][CF_NP + 1];
    int halt_at;
    volatile sig_atomic_t *stop;
    wg_point *pts[CF_NC];
    int unchecked; /* points whose progress came before their check */
} cflog;

static void cf_progress(void *ctx, int chain, int ndone)
{
    cflog *l = ctx;
    pthread_mutex_lock(&l->lock);
    if (chain >= 0 && chain < CF_NC && l->n[chain] <= CF_NP) {
        l->seq[chain][l->n[chain]++] = ndone;
        l->unchecked += ndone >= 1 && ndone <= CF_NP && !l->pts[chain][ndone - 1].checked;
    }
    if (l->halt_at && chain == 0 && ndone == l->halt_at)
        *l->stop = 1;
    pthread_mutex_unlock(&l->lock);
}

/* The step-halving checks (o->verify) run as jobs beside their chains, on
 * any task of any thread: the points are those of one point at a time, to
 * the bit, and each chain's progress comes once a point, in order, only
 * once the point is checked. A stop asked mid-sweep leaves every chain a
 * prefix of checked points (the analyses and checks running then end
 * early, as one point at a time does: the points before are the
 * reference's). */
static void test_checks_in_flight(void)
{
    wg_params p = table3();
    wg_sweep_opts o;
    wg_sweep_opts_default(&o);
    o.transient = 120;
    o.settle = WG_SETTLE_WINDOW;
    o.verify = 1;
    static const double xi[CF_NC] = {0.08, 0.10, 0.12};
    static wg_point ref[CF_NC][CF_NP], pts[CF_NC][CF_NP];
    for (int run = 0; run < 3; run++) {
        volatile sig_atomic_t stop = 0;
        cflog l = {PTHREAD_MUTEX_INITIALIZER, {0}, {{0}}, run == 2 ? 2 : 0, &stop, {NULL}, 0};
        wg_chain c[CF_NC];
        for (int i = 0; i < CF_NC; i++) {
            wg_params q = p;
            q.v[WG_P_XI_P] = xi[i];
            c[i] = chain(&q, 1.16, 1.30, CF_NP, i == 1 ? -1 : 1, run ? pts[i] : ref[i]);
            l.pts[i] = c[i].pts;
        }
        o.pair = run ? 8 : 1;
        memset(pts, 0, sizeof pts);
        ASSERT_EQ_INT(wg_chains_run(c, CF_NC, &o, run ? 2 : 1, &stop, cf_progress, &l), WG_OK);
        int done = 0;
        ASSERT_EQ_INT(l.unchecked, 0);
        for (int i = 0; i < CF_NC; i++) {
            /* stopped: chain 0 has at most the 2 points that asked the stop,
             * SLOTS = 4 checks in flight and the point it was analysing;
             * the others stop short too unless a loaded machine ran them
             * to their end first */
            if (run != 2)
                ASSERT_EQ_INT(c[i].ndone, CF_NP);
            else
                ASSERT_TRUE(i == 0 ? c[i].ndone >= 2 && c[i].ndone <= 7 : c[i].ndone <= CF_NP);
            ASSERT_EQ_INT(l.n[i], c[i].ndone);
            for (int j = 0; j < c[i].ndone; j++) {
                ASSERT_EQ_INT(l.seq[i][j], j + 1);
                ASSERT_EQ_INT(c[i].pts[j].checked, 1);
                if (run == 1)
                    ASSERT_TRUE(memcmp(&pts[i][j], &ref[i][j], sizeof ref[i][j]) == 0);
                else if (run == 2 && j < c[i].ndone - 1) /* the last was cut short */
                    ASSERT_TRUE(memcmp(&pts[i][j], &ref[i][j], offsetof(wg_point, checked)) == 0);
            }
            done += c[i].ndone;
        }
        printf("  checks in flight: %s, %d points committed, in order and checked%s\n",
               run == 0 ? "one chain at a time (the reference)" : run == 1 ? "2 threads x 8 tasks"
                                                                  : "stopped mid-sweep",
               done, run == 1 ? ", equal to the reference" : run ? ", all but each chain's last equal to the reference" : "");
    }
}

static void test_stop_flag(void)
{
    wg_params p = table3();
    wg_sweep_opts o;
    wg_sweep_opts_default(&o);
    static wg_point pts[3];
    wg_chain c = chain(&p, 1.0, 1.1, 3, 1, pts);
    volatile sig_atomic_t stop = 1;
    ASSERT_EQ_INT(wg_chains_run(&c, 1, &o, 1, &stop, NULL, NULL), WG_OK);
    ASSERT_EQ_INT(c.ndone, 0); /* nothing started after the request */
    ASSERT_EQ_INT(c.rc, WG_OK);
}

/* No chains (an MPI rank that more ranks than chains left with none): WG_OK
 * and nothing run, on any number of threads and tasks; a negative count is
 * refused. Before, the pool's thread count fell to 0 and the caller ran as
 * an unset thread (a segmentation fault under `mpirun -np 3` on two chains). */
static void test_no_chains(void)
{
    wg_params p = table3();
    wg_sweep_opts o;
    wg_sweep_opts_default(&o);
    static wg_point pts[2];
    wg_chain c = chain(&p, 1.0, 1.1, 2, 1, pts);
    for (int threads = 1; threads <= 3; threads++)
        for (int pair = 1; pair <= 2; pair++) {
            o.pair = pair;
            ASSERT_EQ_INT(wg_chains_run(&c, 0, &o, threads, NULL, NULL, NULL), WG_OK);
            ASSERT_EQ_INT(c.ndone, 0);
        }
    ASSERT_EQ_INT(wg_chains_run(&c, -1, &o, 2, NULL, NULL, NULL), WG_EINVAL);
    ASSERT_EQ_INT(c.ndone, 0);
}

/* Tolerances out of their ranges are refused by the check and by every
 * entry point, before a point runs (a floor of 1e300 made the period-2
 * points of 1.0-1.4 period 1, exit 0); the ranges' ends are taken. */
static void test_tolerances_refused(void)
{
    wg_params p = table3();
    wg_sweep_opts o;
    static wg_point pts[2];
    char why[256];
    const char *field = NULL;
    static const struct {
        const char *field;
        double bad[4], ok[2];
    } cases[3] = {{"tol_floor", {1e300, 1e-3, 1e-300, 0.0}, {WG_TOL_MIN, WG_TOL_FLOOR_MAX}},
                  {"tol_factor", {1e300, 1001, 0.5, NAN}, {1.0, 1000.0}},
                  {"lle_tol", {1e300, 0.2, 1e-5, -0.01}, {1e-4, 0.1}}};
    for (int k = 0; k < 3; k++) {
        for (int i = 0; i < 6; i++) {
            wg_sweep_opts_default(&o);
            double v = i < 4 ? cases[k].bad[i] : cases[k].ok[i - 4];
            *(k == 0 ? &o.tol_floor : k == 1 ? &o.tol_factor : &o.lle_tol) = v;
            field = NULL;
            ASSERT_EQ_INT(wg_sweep_opts_check(&o, &field, why, sizeof why),
                          i < 4 ? WG_ERANGE : WG_OK);
            if (i < 4)
                ASSERT_STR(field, cases[k].field);
        }
    }
    wg_sweep_opts_default(&o);
    o.tol_floor = 1e300;
    ASSERT_EQ_INT(wg_sweep_opts_check(&o, &field, why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "need a period tolerance floor (states in b_c) in [1e-13, 0.0001], "
                         "got 1e+300");
    wg_chain c = chain(&p, 1.0, 1.1, 2, 1, pts);
    ASSERT_EQ_INT(wg_chains_run(&c, 1, &o, 1, NULL, NULL, NULL), WG_ERANGE);
    ASSERT_EQ_INT(c.ndone, 0);
    ASSERT_CONTAINS(c.why, "option tol_floor: need a period tolerance floor");
    double y[WG_NSTATE_MAX];
    wg_equilibrium(WG_MODEL_CONSISTENT, &p, y);
    ASSERT_EQ_INT(wg_point_run(&p, &o, y, &pts[0], why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "option tol_floor: ");
}

/* Bearing impacts counted by an independent run from the point's final
 * state (a section of its periodic orbit). */
typedef struct bcount {
    long n[WG_NBEARING];
    double vmax[WG_NBEARING];
} bcount;

static void count_bearing(void *ctx, const wg_event *ev)
{
    bcount *b = ctx;
    int j = ev->contact - WG_C_X1;
    if (j >= 0 && j < WG_NBEARING &&
        (ev->kind == WG_EV_DRIVE_IMPACT || ev->kind == WG_EV_BACK_IMPACT)) {
        b->n[j]++;
        b->vmax[j] = fmax(b->vmax[j], fabs(ev->velocity));
    }
}

/* Each bearing's impacts per period and largest impact speed: at
 * xi_p = 1.0 (the printed value) the mesh never separates, yet at omega 1.2
 * the wheel bearing z2 rattles once a period; at xi_p = 0.08 all six
 * impact once a period. Whether the others touch at xi_p = 1.0 depends on
 * where their journals float within the clearance, where no force holds
 * them: on the last bits of the history (a start state moved by 1e-12
 * turns x1, y1, z1 and x2 on or off), so they are held to the count of
 * the events only. */
static void test_bearing_impacts(void)
{
    const double xi[2] = {1.0, 0.08};
    for (int c = 0; c < 2; c++) {
        wg_params p = table3();
        p.v[WG_P_XI_P] = xi[c];
        p.v[WG_P_OMEGA] = 1.2;
        wg_sweep_opts o;
        wg_sweep_opts_default(&o);
        double y[WG_NSTATE_MAX];
        wg_point pt;
        char why[256];
        wg_equilibrium(WG_MODEL_CONSISTENT, &p, y);
        ASSERT_EQ_INT(wg_point_run(&p, &o, y, &pt, why, sizeof why), WG_OK);
        ASSERT_EQ_INT(pt.regime, WG_REGIME_PERIODIC);
        bcount b = {{0}, {0}};
        wg_sim s;
        wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, pt.steps};
        ASSERT_EQ_INT(wg_sim_init(&s, &p, &cfg, why, sizeof why), WG_OK);
        wg_sim_set_state(&s, pt.y_end, 0, 0.0);
        wg_sink sink = {&b, NULL, NULL, count_bearing};
        ASSERT_EQ_INT(wg_sim_run(&s, (uint64_t)o.record * (uint64_t)pt.steps, &sink, NULL), WG_OK);
        wg_sim_fini(&s);
        int rattling = 0;
        for (int j = 0; j < WG_NBEARING; j++) {
            ASSERT_NEAR(pt.bimpacts[j], (double)b.n[j] / o.record, 1e-12);
            ASSERT_NEAR(pt.bvmax[j], b.vmax[j], 1e-6 * (1 + b.vmax[j]));
            rattling += pt.bimpacts[j] > 0;
        }
        printf("xi_p %.2f: bearing impacts per period x1..z2 %g %g %g %g %g %g\n", xi[c],
               pt.bimpacts[0], pt.bimpacts[1], pt.bimpacts[2], pt.bimpacts[3], pt.bimpacts[4],
               pt.bimpacts[5]);
        if (c == 0) {
            ASSERT_EQ_INT(pt.motion, WG_MOTION_NO_IMPACT);
            ASSERT_NEAR(pt.bimpacts[WG_C_Z2 - WG_C_X1], 1, 0);
        } else {
            ASSERT_EQ_INT(rattling, WG_NBEARING);
        }
    }
}

TEST_MAIN(TEST(test_bearing_impacts), TEST(test_period_doubling_sweep_and_floquet),
          TEST(test_lle_sign_on_the_model), TEST(test_lle_sims), TEST(test_lle_sims_blowup),
          TEST(test_error_estimate_order), TEST(test_threads_identical), TEST(test_handoff_identical),
          TEST(test_pairs_identical),
          TEST(test_checks_in_flight), TEST(test_stop_flag), TEST(test_no_chains),
          TEST(test_tolerances_refused))

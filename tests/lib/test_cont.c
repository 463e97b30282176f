/* Continuation of periodic orbits (wg_cont.h), against what the sweep sees
 * and against exact answers:
 *   - linear case: every point of the branch is the exact frequency
 *     response, nothing is detected;
 *   - table3 at xi_p = 0.08: the located period doubling lies where a fine
 *     sweep (long transients) goes from P1 to P2; the switched period-2
 *     branch starts there and folds back (the doubling is subcritical);
 *     the located grazing lies where a fine sweep's min x_n crosses b; the
 *     fold right after it lies in the up sweep's jump bracket and the
 *     branch's folds bracket the hysteresis interval;
 *   - torsional scene: two folds, each inside the sweep's jump bracket;
 *   - every point is a fixed point of wg_sim_run; halving the step and the
 *     tolerances moves each located value by less than 1e-6;
 *   - options refused, and a raised stop flag. */
#include "test_sim.h"
#include "wormgear/wg_cont.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_sweep.h"
#include "test_linear.h"

/* Sanitizer builds run 10-30x slower: shorter sweeps there. */
#ifdef WG_TEST_SLOW
#define SLOW 1
#else
#define SLOW 0
#endif

enum { MAXPT = 4000, MAXBIF = 128 };

typedef struct run {
    wg_cont_point *pt;
    int npt;
    wg_bif bif[MAXBIF];
    int nbif, notes;
    volatile sig_atomic_t *stop_at_first; /* raised by the first point (NULL: not) */
} run;

static void on_point(void *ctx, const wg_cont_point *p)
{
    run *r = ctx;
    if (r->npt < MAXPT)
        r->pt[r->npt++] = *p;
    if (r->stop_at_first)
        *r->stop_at_first = 1;
}

static void on_bif(void *ctx, const wg_bif *b)
{
    run *r = ctx;
    if (r->nbif < MAXBIF)
        r->bif[r->nbif++] = *b;
}

static void on_note(void *ctx, int code, int branch, double v, const char *msg)
{
    run *r = ctx;
    r->notes++;
    (void)code, (void)branch, (void)v, (void)msg;
}

static wg_params scene(const char *name)
{
    wg_scene sc;
    char why[256];
    ASSERT_EQ_INT(wg_scene_open(&sc, name, why, sizeof why), WG_OK);
    return sc.p;
}

/* Continue from the equilibrium's attractor at `from` over [from, to]. */
static run *cont(const wg_params *p, double from, double to, int N, double tol_scale,
                 int depth)
{
    run *r = calloc(1, sizeof *r);
    r->pt = malloc(sizeof *r->pt * MAXPT);
    wg_cont_opts o;
    wg_cont_opts_default(&o);
    o.from = o.start = from;
    o.to = to;
    o.steps = N;
    o.depth = depth;
    o.tol *= tol_scale;
    o.loc_tol *= tol_scale;
    double y[WG_NSTATE_MAX];
    wg_equilibrium(WG_MODEL_CONSISTENT, p, y);
    wg_cont_sink sink = {r, on_point, on_bif, on_note};
    char why[512];
    int rc = wg_cont_run(p, y, &o, &sink, NULL, why, sizeof why);
    if (rc)
        fprintf(stderr, "wg_cont_run: %s\n", why);
    ASSERT_EQ_INT(rc, WG_OK);
    return r;
}

static void run_free(run *r)
{
    free(r->pt);
    free(r);
}

/* The k-th bifurcation of a kind (and, for grazing, contact) on a branch. */
static const wg_bif *find(const run *r, int kind, int branch, int contact, int k)
{
    for (int i = 0; i < r->nbif; i++) {
        const wg_bif *b = &r->bif[i];
        if (b->kind == kind && b->branch == branch && (kind != WG_BIF_GRAZING || b->contact == contact) &&
            k-- == 0)
            return b;
    }
    return NULL;
}

/* Every point of r is a fixed point of P^n as wg_sim_run computes it. */
static void fixed_points(const wg_params *p0, const run *r, int N)
{
    wg_params p = *p0;
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, N);
    double worst = 0.0;
    for (int i = 0; i < r->npt; i += SLOW ? 7 : 1) {
        p.v[WG_P_OMEGA] = r->pt[i].value;
        char why[256];
        ASSERT_EQ_INT(wg_sim_set_params(&s, &p, why, sizeof why), WG_OK);
        wg_sim_set_state(&s, r->pt[i].y, 0, 0.0);
        ASSERT_EQ_INT(wg_sim_run(&s, (uint64_t)r->pt[i].period * N, NULL, NULL), WG_OK);
        for (int j = 0; j < s.nstate; j++)
            worst = fmax(worst, fabs(s.y[j] - r->pt[i].y[j]));
    }
    printf("  %d points: largest |P^n(x) - x| under wg_sim_run %.1e\n", r->npt, worst);
    ASSERT_TRUE(worst <= 1e-9);
    wg_sim_fini(&s);
}

/* The state of the stable branch-0 point of r nearest to value v. */
static const double *seed(const run *r, double v)
{
    const wg_cont_point *best = NULL;
    for (int i = 0; i < r->npt; i++)
        if (r->pt[i].branch == 0 && r->pt[i].stable &&
            (!best || fabs(r->pt[i].value - v) < fabs(best->value - v)))
            best = &r->pt[i];
    ASSERT_TRUE(best != NULL);
    return best ? best->y : NULL;
}

/* An up or down sweep chain over [v0, v1], from y0 (NULL: the equilibrium). */
static wg_point *sweep(const wg_params *p, double v0, double v1, int n, int dir, int transient,
                       const double *y0)
{
    wg_point *pts = calloc((size_t)n, sizeof *pts);
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
    if ((c.has_y0 = y0 != NULL))
        memcpy(c.y0, y0, sizeof c.y0);
    wg_sweep_opts o;
    wg_sweep_opts_default(&o);
    o.transient = transient;
    o.extend = 1;
    ASSERT_EQ_INT(wg_chain_run(&c, &o, NULL, NULL, NULL), WG_OK);
    return pts;
}

/* ---- linear ---------------------------------------------------------------------- */

static void test_linear_branch_is_the_frequency_response(void)
{
    wg_params p = scene("table3");
    p.v[WG_P_B] = p.v[WG_P_B_J] = p.v[WG_P_K_A] = 0.0;
    double hi = SLOW ? 0.7 : 1.5, worst = 0.0, y[LIN_NS];
    run *r = cont(&p, 0.5, hi, 256, 1.0, 1);
    ASSERT_EQ_INT(r->nbif, 0);
    ASSERT_TRUE(r->npt > 10 && fabs(r->pt[r->npt - 1].value - hi) < 1e-12);
    for (int i = 0; i < r->npt; i++) {
        wg_params q = p;
        q.v[WG_P_OMEGA] = r->pt[i].value;
        exact_response(&q, y);
        for (int k = 0; k < LIN_NS; k++)
            worst = fmax(worst, fabs(r->pt[i].y[k] - y[k]));
        ASSERT_TRUE(r->pt[i].stable);
    }
    printf("  %d points over [0.5, %g]: largest |branch - exact response| %.1e\n", r->npt, hi,
           worst);
    ASSERT_TRUE(worst < 1e-6);
    run_free(r);
}

/* ---- table3 at xi_p = 0.08 --------------------------------------------------------- */

/* The period doubling of the cascade, its switched branch, and where a fine
 * sweep with long transients sees P1 -> P2. */
static void test_table3_period_doubling(void)
{
    wg_params p = scene("table3");
    run *r = cont(&p, 1.15, 1.25, 256, 1.0, 1);
    fixed_points(&p, r, 256);
    const wg_bif *pd = find(r, WG_BIF_PD, 0, -1, 0);
    ASSERT_TRUE(pd != NULL);
    if (!pd)
        return;
    printf("  period doubling at %.9f (multiplier %+.9f, bracket %.1e)\n", pd->value, pd->mu_re,
           pd->bracket);
    ASSERT_NEAR(pd->mu_re, -1.0, 1e-6);
    ASSERT_TRUE(pd->bracket < 1e-8);
    /* the sweep: P1 on the grid point below, P2 on the one above */
    double lo = floor(pd->value / 5e-4) * 5e-4, hi = lo + 5e-4;
    wg_point *pts = sweep(&p, lo, hi, 2, +1, 6000, seed(r, lo));
    printf("  fine up sweep (6000-period transients): %.4f P%d, %.4f P%d\n", pts[0].value,
           pts[0].period, pts[1].value, pts[1].period);
    ASSERT_TRUE(pts[0].regime == WG_REGIME_PERIODIC && pts[0].period == 1);
    ASSERT_TRUE(pts[1].regime == WG_REGIME_PERIODIC && pts[1].period == 2);
    free(pts);
    /* branch 1: period 2 from the doubling point, back to a fold (subcritical) */
    const wg_bif *f2 = find(r, WG_BIF_FOLD, 1, -1, 0);
    ASSERT_TRUE(f2 != NULL && f2->period == 2 && f2->value < pd->value);
    if (f2)
        printf("  period-2 branch: fold at %.9f (multiplier %+.9f)\n", f2->value, f2->mu_re);
    int n2 = 0;
    for (int i = 0; i < r->npt; i++)
        if (r->pt[i].branch == 1) {
            n2++;
            ASSERT_EQ_INT(r->pt[i].period, 2);
            if (r->pt[i].index > 0) /* genuinely period 2 */
                ASSERT_TRUE(fabs(r->pt[i].xnsec[1] - r->pt[i].xnsec[0]) > 1e-6);
        }
    ASSERT_TRUE(n2 > 5);
    run_free(r);
}

/* Grazing, the fold after it and the hysteresis of the jump near 0.7. */
static void test_table3_grazing_and_folds(void)
{
    wg_params p = scene("table3");
    run *r = cont(&p, 0.60, 0.70, 256, 1.0, 0);
    const wg_bif *g = find(r, WG_BIF_GRAZING, 0, WG_C_MESH, 0);
    ASSERT_TRUE(g != NULL);
    if (!g)
        return;
    ASSERT_TRUE(g->side == 1 && g->extreme == -1);
    /* a fine sweep's min x_n crosses b between the grid points around it */
    double lo = floor(g->value / 5e-4) * 5e-4;
    wg_point *pts = sweep(&p, lo, lo + 5e-4, 2, +1, SLOW ? 300 : 1000, seed(r, lo));
    double b = p.v[WG_P_B];
    printf("  grazing at %.9f; sweep min x_n - b: %.2e at %.4f, %.2e at %.4f\n", g->value,
           pts[0].min_xn - b, pts[0].value, pts[1].min_xn - b, pts[1].value);
    ASSERT_TRUE(pts[0].min_xn > b && pts[1].min_xn < b);
    double at = pts[0].value + 5e-4 * (pts[0].min_xn - b) / (pts[0].min_xn - pts[1].min_xn);
    ASSERT_NEAR(at, g->value, 2e-5); /* linear interpolation of a smooth min */
    free(pts);
    /* the folds: the first one right after the grazing, in the up sweep's
     * jump bracket (0.6975, 0.7000) of docs/study; all of them bracket its
     * hysteresis interval [0.6900, 0.6975] */
    const wg_bif *f0 = find(r, WG_BIF_FOLD, 0, -1, 0);
    double flo = INFINITY, fhi = -INFINITY;
    for (int k = 0; find(r, WG_BIF_FOLD, 0, -1, k); k++) {
        flo = fmin(flo, find(r, WG_BIF_FOLD, 0, -1, k)->value);
        fhi = fmax(fhi, find(r, WG_BIF_FOLD, 0, -1, k)->value);
    }
    ASSERT_TRUE(f0 != NULL && f0->value > g->value && f0->value > 0.6975 && f0->value < 0.7);
    ASSERT_TRUE(flo < 0.6900 && fhi > 0.6975);
    printf("  folds span [%.9f, %.9f]; the first %.9f (multiplier %+.9f)\n", flo, fhi,
           f0 ? f0->value : NAN, f0 ? f0->mu_re : NAN);
    run_free(r);
}

/* ---- torsional: the single-DOF impact oscillator's jump --------------------------- */

static void test_torsional_folds_bound_the_jump(void)
{
    wg_params p = scene("torsional");
    run *r = cont(&p, 0.6, 0.9, 256, 1.0, 0);
    const wg_bif *a = find(r, WG_BIF_FOLD, 0, -1, 0), *b = find(r, WG_BIF_FOLD, 0, -1, 1);
    ASSERT_TRUE(a != NULL && b != NULL && !find(r, WG_BIF_FOLD, 0, -1, 2));
    if (!a || !b)
        return;
    printf("  folds at %.9f and %.9f\n", a->value, b->value);
    ASSERT_NEAR(a->mu_re, 1.0, 1e-6);
    ASSERT_NEAR(b->mu_re, 1.0, 1e-6);
    /* the sweep jumps up just above the upper fold, down just below the lower */
    int n = SLOW ? 9 : 21;
    double lo = 0.70, hi = 0.80, st = (hi - lo) / (n - 1);
    wg_point *up = sweep(&p, lo, hi, n, +1, 300, NULL), *dn = sweep(&p, lo, hi, n, -1, 300, NULL);
    int ju = -1, jd = -1;
    for (int i = 0; i + 1 < n; i++) {
        if (fabs(up[i + 1].max_xn - up[i].max_xn) > 0.1)
            ju = i; /* up: between value i and i + 1 */
        if (fabs(dn[i + 1].max_xn - dn[i].max_xn) > 0.1)
            jd = n - 2 - i; /* down runs in reverse */
    }
    ASSERT_TRUE(ju >= 0 && jd >= 0);
    printf("  up sweep jumps in (%.4f, %.4f), down sweep in (%.4f, %.4f)\n", lo + ju * st,
           lo + (ju + 1) * st, lo + jd * st, lo + (jd + 1) * st);
    ASSERT_TRUE(a->value > lo + ju * st && a->value < lo + (ju + 1) * st);
    ASSERT_TRUE(b->value > lo + jd * st && b->value < lo + (jd + 1) * st);
    free(up);
    free(dn);
    run_free(r);
}

/* ---- accuracy: halving the step and the tolerances --------------------------------- */

static double located(const wg_params *p, double from, double to, int N, double ts, int kind,
                      int k)
{
    run *r = cont(p, from, to, N, ts, 0);
    const wg_bif *b = find(r, kind, 0, WG_C_MESH, k);
    double v = b ? b->value : NAN;
    ASSERT_TRUE(b != NULL);
    run_free(r);
    return v;
}

static void test_step_halving(void)
{
    static const struct {
        const char *scene;
        double from, to;
        int kind, k;
    } cases[] = {{"table3", 1.15, 1.22, WG_BIF_PD, 0},
                 {"table3", 0.69, 0.70, WG_BIF_GRAZING, 0},
                 {"table3", 0.69, 0.70, WG_BIF_FOLD, 0},
                 {"torsional", 0.6, 0.9, WG_BIF_FOLD, 1}};
    for (unsigned i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        if (SLOW && i > 0)
            break;
        wg_params p = scene(cases[i].scene);
        double a = located(&p, cases[i].from, cases[i].to, 256, 1.0, cases[i].kind, cases[i].k);
        double b = located(&p, cases[i].from, cases[i].to, 512, 0.5, cases[i].kind, cases[i].k);
        printf("  %s %s: N = 256 %.9f, N = 512 and tolerances / 2 %.9f, |diff| %.1e\n",
               cases[i].scene, wg_bif_name(cases[i].kind), a, b, fabs(a - b));
        ASSERT_TRUE(fabs(a - b) <= 1e-6);
    }
}

/* ---- the API ---------------------------------------------------------------------- */

static void test_refused_and_stopped(void)
{
    wg_params p = scene("table3");
    wg_cont_opts o;
    wg_cont_opts_default(&o);
    double y[WG_NSTATE_MAX];
    char why[512];
    wg_equilibrium(WG_MODEL_CONSISTENT, &p, y);
    o.start = 3.0;
    ASSERT_EQ_INT(wg_cont_run(&p, y, &o, NULL, NULL, why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "option start: need a value in [0.1, 2.5] (the range), got 3");
    wg_cont_opts_default(&o);
    o.period = 0;
    ASSERT_EQ_INT(wg_cont_run(&p, y, &o, NULL, NULL, why, sizeof why), WG_EINVAL);
    /* the check alone names the member at fault, for a program's own words */
    const char *field = NULL;
    ASSERT_EQ_INT(wg_cont_check(&o, &field, why, sizeof why), WG_EINVAL);
    ASSERT_STR(field, "period");
    wg_cont_opts_default(&o);
    o.to = o.from;
    ASSERT_EQ_INT(wg_cont_check(&o, &field, why, sizeof why), WG_ERANGE);
    ASSERT_STR(field, "range");
    wg_cont_opts_default(&o);
    o.ds_max = o.ds_min / 2;
    ASSERT_EQ_INT(wg_cont_check(&o, &field, why, sizeof why), WG_EINVAL);
    ASSERT_STR(field, "ds_max");
    wg_cont_opts_default(&o);
    ASSERT_EQ_INT(wg_cont_check(&o, &field, why, sizeof why), WG_OK);
    /* tolerances in their ranges (1e300 took the first guess as the orbit;
     * 1e-300 is never met: "no orbit found"), the ends taken */
    static const double tols[][2] = {{1e300, 1e-5}, {1e-300, 1e-300}, {1e-6, 1e-14},
                                     {WG_TOL_MIN, 1e-3}, {0.0, NAN}, {WG_CONT_TOL_MAX, 1e-5}};
    static const char *const fields[] = {"tol", "tol", "loc_tol", "loc_tol", "tol", ""};
    for (int i = 0; i < 6; i++) {
        wg_cont_opts_default(&o);
        o.tol = tols[i][0], o.loc_tol = tols[i][1];
        field = "";
        ASSERT_EQ_INT(wg_cont_check(&o, &field, why, sizeof why), i < 5 ? WG_ERANGE : WG_OK);
        ASSERT_STR(field, fields[i]);
    }
    o.tol = 1e300;
    ASSERT_EQ_INT(wg_cont_check(&o, &field, why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "need a residual (states in b_c) in [1e-13, 1e-06], got 1e+300");
    wg_cont_opts_default(&o);
    o.model = WG_MODEL_PRINTED;
    ASSERT_EQ_INT(wg_cont_run(&p, y, &o, NULL, NULL, why, sizeof why), WG_EUNSUPPORTED);
    /* period 3 asked where the attractor is period 1: Newton finds that */
    wg_cont_opts_default(&o);
    o.from = o.start = 0.5;
    o.to = 0.6;
    o.period = 3;
    o.transient = 50;
    ASSERT_EQ_INT(wg_cont_run(&p, y, &o, NULL, NULL, why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "has period 1, not 3");
    /* a stop flag raised before the run: it ends in the first point's
     * transient, nothing reported; raised by the first point: that one */
    run *r = calloc(1, sizeof *r);
    r->pt = malloc(sizeof *r->pt * MAXPT);
    wg_cont_sink sink = {r, on_point, on_bif, on_note};
    volatile sig_atomic_t stop = 1;
    wg_cont_opts_default(&o);
    o.from = o.start = 0.5;
    o.to = 0.6;
    ASSERT_EQ_INT(wg_cont_run(&p, y, &o, &sink, &stop, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(r->npt, 0);
    stop = 0;
    r->stop_at_first = &stop;
    ASSERT_EQ_INT(wg_cont_run(&p, y, &o, &sink, &stop, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(r->npt, 1);
    run_free(r);
}

TEST_MAIN(TEST(test_linear_branch_is_the_frequency_response), TEST(test_table3_period_doubling),
          TEST(test_table3_grazing_and_folds), TEST(test_torsional_folds_bound_the_jump),
          TEST(test_step_halving), TEST(test_refused_and_stopped))

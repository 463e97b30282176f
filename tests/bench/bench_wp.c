/* bench_wp - work-precision: error against run time, SciMLBenchmarks style,
 * for our fixed-step rk4 and rk4-event (N = 16 ... 4096 steps per mesh
 * period), GSL odeiv2 rk4 / rkf45 / rk8pd and CVODE Adams / BDF (SUNDIALS
 * 6, Debian 12) at a range of tolerances (atol = rtol = tol), on
 *   (i)   a smooth linear case (b = b_j = k_a = e_m = 0, omega 1.3),
 *   (ii)  table3 at omega 0.7 (single-sided impacts, bearings rattling;
 *         30 periods: beyond ~45 the trajectory itself is sensitive --
 *         rk4-event at N = 16384 and 32768 part from 1e-11 to 1e-2),
 *   (iii) table3 at omega 1.45 (chaotic band; short horizon).
 * Error = max over the run's Poincare samples (psi = 0, once per mesh
 * period, from equilibrium) of |x_n - x_n,ref|. The reference is rk4-event
 * at N = 32768, validated against GSL rk8pd at 1e-14 (local time restarted
 * every mesh period; it integrates through the kinks) -- their agreement is
 * printed. GSL and CVODE call wg_exc_eval at the stage time and wg_rhs.
 * Times: the integration only (set-up excluded for every method), median of
 * REPS repetitions interleaved over all methods. Prints Markdown tables and
 * writes DIR/wp_<case>.png.
 * usage: bench_wp [DIR] [REPS] (--help: what they allow) */
#include "bench_args.h"
#include "bench_common.h"
#include "bench_plot.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_sim.h"
#include "wormgear/wg_status.h"

#include <cvode/cvode.h>
#include <errno.h>
#include <gsl/gsl_errno.h>
#include <gsl/gsl_odeiv2.h>
#include <math.h>
#include <nvector/nvector_serial.h>
#include <sunlinsol/sunlinsol_dense.h>
#include <sunmatrix/sunmatrix_dense.h>
#include <sunnonlinsol/sunnonlinsol_fixedpoint.h>
#include <sys/stat.h>
#include <unistd.h>

enum { PMAX = 200, NPAR = 16, MAXREP = 15, NREF = 32768 };

enum kind { OURS_RK4, OURS_EV, GSL_RK4, GSL_RKF45, GSL_RK8PD, M_ADAMS, M_BDF, NKIND };

static const char *const kind_label[NKIND] = {"wg rk4", "wg rk4-event", "GSL rk4", "GSL rkf45",
                                              "GSL rk8pd", "CVODE Adams", "CVODE BDF"};
static const double kind_rgb[NKIND][3] = {{0.55, 0.55, 0.55}, {0.85, 0.1, 0.1}, {0.1, 0.6, 0.1},
                                          {0.1, 0.3, 0.9},    {0.5, 0.1, 0.7},  {0.9, 0.6, 0.0},
                                          {0.0, 0.6, 0.7}};

typedef struct wpcase {
    const char *key, *title;
    wg_params p;
    int P; /* mesh periods (= Poincare samples) */
} wpcase;

typedef struct result {
    int n;
    double par[NPAR], err[NPAR], work[NPAR];
    double t[NPAR][MAXREP]; /* us per mesh period */
    double tmed[NPAR];
} result;

static double xn_at_section(const wpcase *c, const double *y)
{
    wg_exc e;
    wg_outputs o;
    wg_exc_eval(&c->p, 0.0, c->p.v[WG_P_OMEGA], &e);
    wg_outputs_eval(WG_MODEL_CONSISTENT, &c->p, &e, y, &o);
    return o.xn;
}

/* ---- our integrator ----------------------------------------------------- */

typedef struct secrec {
    int n;
    double *xn;
} secrec;

static void on_sec(void *ctx, const wg_section *s)
{
    secrec *r = ctx;
    if (r->n < PMAX)
        r->xn[r->n] = s->out.xn;
    r->n++;
}

static double run_ours(const wpcase *c, int stepper, int N, double *xn, double *work)
{
    wg_sim s;
    char why[400];
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, stepper, N};
    if (wg_sim_init(&s, &c->p, &cfg, why, sizeof why)) {
        fprintf(stderr, "bench_wp: %s\n", why);
        return NAN;
    }
    secrec r = {0, xn};
    wg_sink sink = {&r, NULL, on_sec, NULL};
    double t0 = bench_now_ns();
    int rc = wg_sim_run(&s, (uint64_t)N * (uint64_t)c->P, &sink, NULL);
    double dt = bench_now_ns() - t0;
    *work = (double)(s.steps + s.nsplit) / c->P; /* RK4 steps incl. split sub-steps */
    wg_sim_fini(&s);
    return rc == WG_OK && r.n == c->P ? dt : NAN;
}

/* ---- GSL odeiv2, adaptive, local time restarted every mesh period ------- */

static double run_gsl(const wpcase *c, int kind, double tol, double *xn, double *work)
{
    const gsl_odeiv2_step_type *T = kind == GSL_RK4     ? gsl_odeiv2_step_rk4
                                    : kind == GSL_RKF45 ? gsl_odeiv2_step_rkf45
                                                        : gsl_odeiv2_step_rk8pd;
    double om = c->p.v[WG_P_OMEGA], Tp = 2 * M_PI / om, y[14];
    bench_ode o = {&c->p, om, 0.0, 0};
    gsl_odeiv2_system sys = {bench_gsl_rhs, NULL, 14, &o};
    gsl_odeiv2_driver *d = gsl_odeiv2_driver_alloc_y_new(&sys, T, Tp / 64, tol, tol);
    wg_equilibrium(WG_MODEL_CONSISTENT, &c->p, y);
    int rc = 0;
    double t0 = bench_now_ns();
    for (int k = 0; k < c->P && !rc; k++) {
        double t = 0.0; /* the RHS is Tp-periodic: restart the local time */
        rc = gsl_odeiv2_driver_apply(d, &t, Tp, y);
        xn[k] = xn_at_section(c, y);
    }
    double dt = bench_now_ns() - t0;
    gsl_odeiv2_driver_free(d);
    *work = (double)o.nrhs / c->P;
    return rc ? NAN : dt;
}

/* ---- CVODE (SUNDIALS 6: every object needs a SUNContext) ---------------- */

static int cv_rhs(sunrealtype t, N_Vector y, N_Vector ydot, void *ud)
{
    bench_rhs(ud, t, N_VGetArrayPointer(y), N_VGetArrayPointer(ydot));
    return 0;
}

static void cv_quiet(int code, const char *module, const char *fn, char *msg, void *ud)
{
    (void)code, (void)module, (void)fn, (void)msg, (void)ud;
}

/* Global time (a restart every period would throw away CVODE's multistep
 * history); tau stays below ~1e3 here, which floors the error near 1e-12. */
static double run_cvode(const wpcase *c, int kind, double tol, double *xn, double *work)
{
    double om = c->p.v[WG_P_OMEGA], Tp = 2 * M_PI / om;
    bench_ode o = {&c->p, om, 0.0, 0};
    SUNContext ctx;
    if (SUNContext_Create(NULL, &ctx))
        return NAN;
    N_Vector y = N_VNew_Serial(14, ctx);
    wg_equilibrium(WG_MODEL_CONSISTENT, &c->p, N_VGetArrayPointer(y));
    void *mem = CVodeCreate(kind == M_ADAMS ? CV_ADAMS : CV_BDF, ctx);
    SUNMatrix A = NULL;
    SUNLinearSolver LS = NULL;
    SUNNonlinearSolver NLS = NULL;
    int rc = CVodeInit(mem, cv_rhs, 0.0, y);
    rc |= CVodeSStolerances(mem, tol, tol);
    rc |= CVodeSetUserData(mem, &o);
    rc |= CVodeSetMaxNumSteps(mem, 100000000L);
    rc |= CVodeSetErrHandlerFn(mem, cv_quiet, NULL);
    if (kind == M_BDF) { /* Newton, dense, difference-quotient Jacobian */
        A = SUNDenseMatrix(14, 14, ctx);
        LS = SUNLinSol_Dense(y, A, ctx);
        rc |= CVodeSetLinearSolver(mem, LS, A);
    } else { /* Adams with functional (fixed-point) iteration */
        NLS = SUNNonlinSol_FixedPoint(y, 0, ctx);
        rc |= CVodeSetNonlinearSolver(mem, NLS);
    }
    double t0 = bench_now_ns();
    for (int k = 0; k < c->P && rc >= 0; k++) {
        sunrealtype t;
        rc = CVode(mem, (k + 1) * Tp, y, &t, CV_NORMAL);
        xn[k] = xn_at_section(c, N_VGetArrayPointer(y));
    }
    double dt = bench_now_ns() - t0;
    *work = (double)o.nrhs / c->P;
    CVodeFree(&mem);
    if (LS)
        SUNLinSolFree(LS);
    if (A)
        SUNMatDestroy(A);
    if (NLS)
        SUNNonlinSolFree(NLS);
    N_VDestroy(y);
    SUNContext_Free(&ctx);
    return rc < 0 ? NAN : dt;
}

static double run_method(const wpcase *c, int kind, double par, double *xn, double *work)
{
    if (kind == OURS_RK4 || kind == OURS_EV)
        return run_ours(c, kind == OURS_EV ? WG_STEPPER_RK4_EVENT : WG_STEPPER_RK4, (int)par, xn,
                        work);
    if (kind <= GSL_RK8PD)
        return run_gsl(c, kind, par, xn, work);
    return run_cvode(c, kind, par, xn, work);
}

static double maxdiff(const double *a, const double *b, int n)
{
    double e = 0;
    for (int i = 0; i < n; i++)
        e = isfinite(a[i]) && isfinite(b[i]) ? fmax(e, fabs(a[i] - b[i])) : INFINITY;
    return e;
}

/* Run time (us/period) at which a method's curve reaches `target`, by
 * log-log interpolation between the bracketing settings; NAN if never. */
static double time_at(const result *r, int rep, double target)
{
    for (int i = 0; i < r->n; i++) {
        double ti = rep < 0 ? r->tmed[i] : r->t[i][rep];
        if (!(r->err[i] <= target))
            continue;
        if (i == 0 || !(r->err[i - 1] > target))
            return ti; /* the cheapest setting already meets it: an upper bound */
        double tp = rep < 0 ? r->tmed[i - 1] : r->t[i - 1][rep];
        double f = (log(target) - log(r->err[i - 1])) / (log(r->err[i]) - log(r->err[i - 1]));
        return exp(log(tp) + f * (log(ti) - log(tp)));
    }
    return NAN;
}

static void settings(int kind, const wpcase *c, result *r)
{
    r->n = 0;
    if (kind == OURS_RK4 || kind == OURS_EV) {
        int nmin = wg_min_steps(wg_rk4_hmax(WG_MODEL_CONSISTENT, &c->p), c->p.v[WG_P_OMEGA]);
        for (int N = 16; N <= 4096; N *= 2)
            if (N >= nmin)
                r->par[r->n++] = N;
        return;
    }
    double tmax = kind == GSL_RK4 ? 1e-10 : kind == GSL_RK8PD ? 1e-14 : 1e-12;
    for (double tol = 1e-3; tol >= tmax * 0.99; tol *= 0.1)
        r->par[r->n++] = tol;
}

static void run_case(wpcase *c, const char *dir, int reps)
{
    static double ref[PMAX], refB[PMAX], half[PMAX], xn[PMAX];
    double w;
    printf("\n## %s: %d mesh periods from equilibrium\n\n", c->title, c->P);
    /* the reference, and its validation */
    run_ours(c, WG_STEPPER_RK4_EVENT, NREF, ref, &w);
    run_ours(c, WG_STEPPER_RK4_EVENT, NREF / 2, half, &w);
    double tB = run_gsl(c, GSL_RK8PD, 1e-14, refB, &w), agree = maxdiff(ref, refB, c->P);
    printf("reference: rk4-event N = %d. Against GSL rk8pd at 1e-14 (%.0f RHS calls/period, "
           "%.0f us/period): max |dx_n| = %.2e; against rk4-event N = %d: %.2e\n\n", NREF, w,
           tB / 1e3 / c->P, agree, NREF / 2, maxdiff(ref, half, c->P));
    static result res[NKIND];
    for (int k = 0; k < NKIND; k++)
        settings(k, c, &res[k]);
    for (int rep = 0; rep < reps; rep++)
        for (int k = 0; k < NKIND; k++)
            for (int i = 0; i < res[k].n; i++) {
                double t = run_method(c, k, res[k].par[i], xn, &res[k].work[i]);
                res[k].t[i][rep] = t / 1e3 / c->P;
                if (rep == 0)
                    res[k].err[i] = isfinite(t) ? maxdiff(xn, ref, c->P) : NAN;
            }
    printf("| method | setting | max \\|dx_n\\| | us / period | work / period |\n"
           "|---|---|---|---|---|\n");
    for (int k = 0; k < NKIND; k++)
        for (int i = 0; i < res[k].n; i++) {
            res[k].tmed[i] = bench_median(res[k].t[i], reps);
            if (k <= OURS_EV)
                printf("| %s | N = %.0f | %.2e | %.1f | %.0f steps |\n", kind_label[k],
                       res[k].par[i], res[k].err[i], res[k].tmed[i], res[k].work[i]);
            else
                printf("| %s | tol = %.0e | %.2e | %.1f | %.0f RHS |\n", kind_label[k],
                       res[k].par[i], res[k].err[i], res[k].tmed[i], res[k].work[i]);
        }
    /* time to reach given errors, and the ratios against rk8pd */
    static const double targets[] = {1e-3, 1e-6, 1e-9};
    printf("\nus per mesh period to reach max |dx_n| (log-log interpolation; - = not reached):\n\n"
           "| method | 1e-3 | 1e-6 | 1e-9 |\n|---|---|---|---|\n");
    for (int k = 0; k < NKIND; k++) {
        printf("| %s |", kind_label[k]);
        for (int j = 0; j < 3; j++) {
            double t = time_at(&res[k], -1, targets[j]);
            if (isfinite(t))
                printf(" %.1f |", t);
            else
                printf(" - |");
        }
        printf("\n");
    }
    printf("\nrk4-event / GSL rk8pd time at equal error (ratio per repetition, median of %d):", reps);
    for (int j = 1; j < 3; j++) {
        double ratio[MAXREP];
        for (int rep = 0; rep < reps; rep++)
            ratio[rep] = time_at(&res[OURS_EV], rep, targets[j]) /
                         time_at(&res[GSL_RK8PD], rep, targets[j]);
        printf(" %.0e: **%.3f**;", targets[j], bench_median(ratio, reps));
    }
    printf("\n");
    /* the plot */
    plot_series s[NKIND];
    for (int k = 0; k < NKIND; k++)
        s[k] = (plot_series){kind_label[k], res[k].n, res[k].err, res[k].tmed,
                             {kind_rgb[k][0], kind_rgb[k][1], kind_rgb[k][2]}, k >= M_ADAMS};
    char path[600], title[200], cap[3][240];
    snprintf(path, sizeof path, "%s/wp_%s.png", dir, c->key);
    snprintf(title, sizeof title, "work-precision: %s, %d periods", c->title, c->P);
    snprintf(cap[0], sizeof cap[0],
             "error: max |x_n - x_n,ref| over the %d Poincaré samples (ψ = 0, from equilibrium); "
             "reference: rk4-event at N = %d (%.1e from GSL rk8pd at 1e-14)",
             c->P, NREF, agree);
    snprintf(cap[1], sizeof cap[1],
             "time: CPU of the integration alone, the median of %d repetition%s; wg: N = %.0f … "
             "4096 steps a period, doubling (from the RK4 limit's minimum)",
             reps, reps == 1 ? "" : "s", res[OURS_EV].par[0]);
    snprintf(cap[2], sizeof cap[2],
             "GSL odeiv2 and CVODE: atol = rtol = 1e-3 down to 1e-10 (rk4), 1e-12 (rkf45, CVODE), "
             "1e-14 (rk8pd); dashed: CVODE (multistep)");
    const char *const caption[] = {cap[0], cap[1], cap[2], NULL};
    if (plot_wp(path, title, caption, "max |Δx_n| at the Poincaré samples  (units of b_c)",
                "run time  (µs of CPU per mesh period)", s, NKIND, 1000, 640))
        fprintf(stderr, "bench_wp: could not write %s\n", path);
    else
        printf("\nplot: %s\n", path);
    fflush(stdout);
}

int main(int argc, char **argv)
{
    const char *dir = ".";
    double nrep = 3;
    bench_arg args[] = {
        {"DIR", "the directory the plots go to (wp_<case>.png), which must exist (default .)", 0,
         0, NULL, &dir, 0},
        {"REPS", "repetitions, interleaved, each time the median, 1 to 15 (default 3)", 1, MAXREP,
         &nrep, NULL, 0}};
    int rc = bench_args("bench_wp", "Work-precision: error against run time for our rk4 and "
                        "rk4-event, GSL's rk4, rkf45, rk8pd and CVODE's Adams and BDF, on three "
                        "cases.", "", argc, argv, args, 2, NULL);
    if (rc >= 0)
        return rc;
    struct stat st;
    const char *bad = stat(dir, &st) != 0       ? strerror(errno)
                      : !S_ISDIR(st.st_mode)    ? "not a directory"
                      : access(dir, W_OK) != 0  ? strerror(errno)
                                                : NULL;
    if (bad)
        return cli_usage_error("bench_wp", "DIR '%s': %s (the plots' directory must exist and "
                               "be writable)", dir, bad);
    int reps = (int)nrep;
    gsl_set_error_handler_off();
    wpcase cases[3];
    wg_params p;
    wg_params_default(&p);
    cases[0] = (wpcase){"linear", "(i) linear case (b = b_j = k_a = e_m = 0, xi_g = 0.02), omega 1.3",
                        p, 100};
    cases[0].p.v[WG_P_B] = cases[0].p.v[WG_P_B_J] = 0;
    cases[0].p.v[WG_P_K_A] = cases[0].p.v[WG_P_E_M] = 0;
    cases[0].p.v[WG_P_XI_G] = 0.02;
    cases[0].p.v[WG_P_OMEGA] = 1.3;
    cases[1] = (wpcase){"impact", "(ii) table3, omega 0.7 (single-sided impacts)", p, 30};
    cases[1].p.v[WG_P_OMEGA] = 0.7;
    cases[2] = (wpcase){"chaos", "(iii) table3, omega 1.45 (chaotic band)", p, 20};
    cases[2].p.v[WG_P_OMEGA] = 1.45;
    printf("# bench_wp: work-precision, %d repetitions (median times)\n", reps);
    for (int i = 0; i < 3; i++)
        run_case(&cases[i], dir, reps);
    return 0;
}

/* sweep_at.c - single-point views for wgsweep --at (see sweep_at.h). */
#include "sweep_at.h"
#include "plot.h"
#include "sweep_out.h"
#include "wormgear/wg_shoot.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* Buffers filled while the orbit is replayed. */
typedef struct views {
    double *sx, *sy;   /* Poincare x_n, x_n' */
    int ns, nsmax;
    double *t, *x, *v; /* trace: tau, x_n, x_n' of every step */
    int nt, ntmax;
    uint64_t trace_from; /* first period traced */
} views;

static void on_sec(void *ctx, const wg_section *sec)
{
    views *w = ctx;
    if (w->ns < w->nsmax) {
        w->sx[w->ns] = sec->out.xn;
        w->sy[w->ns++] = sec->out.dxn;
    }
}

static void on_step(void *ctx, const wg_sim *s)
{
    views *w = ctx;
    if (s->period < w->trace_from || w->nt >= w->ntmax)
        return;
    wg_outputs o;
    wg_sim_outputs(s, &o);
    w->t[w->nt] = s->tau;
    w->x[w->nt] = o.xn;
    w->v[w->nt++] = o.dxn;
}

static int views_alloc(views *w, int periods, int tperiods, int n)
{
    memset(w, 0, sizeof *w);
    w->nsmax = periods;
    w->ntmax = tperiods * n + 1;
    w->sx = malloc(sizeof(double) * (size_t)periods);
    w->sy = malloc(sizeof(double) * (size_t)periods);
    w->t = malloc(sizeof(double) * (size_t)w->ntmax);
    w->x = malloc(sizeof(double) * (size_t)w->ntmax);
    w->v = malloc(sizeof(double) * (size_t)w->ntmax);
    return w->sx && w->sy && w->t && w->x && w->v ? 0 : -1;
}

static void views_free(views *w)
{
    free(w->sx), free(w->sy), free(w->t), free(w->x), free(w->v);
}

/* Replay `periods` periods from y, the last trace_periods traced. */
static int replay(const wg_params *p, const double *y, const wg_sweep_opts *o, int n,
                  const at_opts *ao, views *w)
{
    wg_sim sim;
    char why[256];
    wg_sim_config cfg = {o->model, o->stepper, n};
    if (wg_sim_init(&sim, p, &cfg, why, sizeof why)) {
        fprintf(stderr, "wgsweep: %s\n", why);
        return 1;
    }
    wg_sim_set_state(&sim, y, 0, 0.0);
    int tp = ao->trace_periods < ao->periods ? ao->trace_periods : ao->periods;
    w->trace_from = (uint64_t)(ao->periods - tp);
    wg_sink sink = {w, on_step, on_sec, NULL};
    int rc = wg_sim_run(&sim, (uint64_t)ao->periods * (uint64_t)n, &sink, NULL);
    wg_sim_fini(&sim);
    if (rc)
        fprintf(stderr, "wgsweep: replay: %s\n", wg_status_str(rc));
    return rc ? 1 : 0;
}

static int write_trace(const char *path, const views *w)
{
    char why[1200];
    FILE *f = out_open(path, why, sizeof why);
    if (f) {
        fprintf(f, "tau,x_n,dx_n\n");
        for (int i = 0; i < w->nt; i++)
            fprintf(f, "%.12g,%.12g,%.12g\n", w->t[i], w->x[i], w->v[i]);
    }
    if (!f || out_close(f, path, why, sizeof why)) {
        fprintf(stderr, "wgsweep: %s\n", why);
        return 1;
    }
    return 0;
}

static int write_pngs(const char *base, const char *title, const views *w, double b)
{
    char path[1100], why[256], t[300];
    int rc = 0;
    snprintf(t, sizeof t, "%s: phase portrait", title);
    plot_xy ph = {t, "x_n", "x_n'", w->x, w->v, w->nt, 0, b, 1};
    snprintf(path, sizeof path, "%s-phase.png", base);
    rc |= plot_xy_png(path, &ph, why, sizeof why);
    char t2[300];
    snprintf(t2, sizeof t2, "%s: Poincare map (psi = 0), %d periods", title, w->ns);
    plot_xy pm = {t2, "x_n", "x_n'", w->sx, w->sy, w->ns, 1, b, 1};
    snprintf(path, sizeof path, "%s-poincare.png", base);
    rc |= plot_xy_png(path, &pm, why, sizeof why);
    char t3[300];
    snprintf(t3, sizeof t3, "%s: time trace", title);
    plot_xy tr = {t3, "tau", "x_n", w->t, w->x, w->nt, 0, b, 0};
    snprintf(path, sizeof path, "%s-trace.png", base);
    rc |= plot_xy_png(path, &tr, why, sizeof why);
    if (rc)
        fprintf(stderr, "wgsweep: %s\n", why);
    return rc ? 1 : 0;
}

/* Floquet multipliers of the Newton-refined orbit through y (period n). */
static void print_floquet(FILE *out, const wg_params *p, const double *y, const wg_sweep_opts *o,
                          int N, int n)
{
    wg_sim sim;
    char why[256];
    wg_sim_config cfg = {o->model, o->stepper, N};
    if (wg_sim_init(&sim, p, &cfg, why, sizeof why))
        return;
    wg_orbit *orb = malloc(sizeof *orb);
    double x[WG_NSTATE_MAX], res = INFINITY, wr[WG_NSTATE_MAX], wi[WG_NSTATE_MAX];
    memcpy(x, y, sizeof x);
    int rc = orb ? wg_orbit_refine(&sim, n, x, 1e-10, 8, &res, orb) : WG_ENOMEM;
    fprintf(out, "orbit       Newton refinement: %s, residual %.2e\n",
            rc ? wg_status_name(rc) : "ok", res);
    if (rc != WG_ENOMEM && rc != WG_EUNSUPPORTED && wg_orbit_floquet(orb, wr, wi) == WG_OK) {
        fprintf(out, "floquet     multipliers of the period-%d map (largest |mu| first):\n", n);
        for (int i = 0; i < orb->dim; i++)
            fprintf(out, "            %+.6f %+.6fi   |mu| = %.6f\n", wr[i], wi[i],
                    hypot(wr[i], wi[i]));
    }
    free(orb);
    wg_sim_fini(&sim);
}

static void summary(FILE *out, const wg_point *pt, double v, const at_opts *ao)
{
    char lab[32];
    fprintf(out, "point       %s = %g\n", ao->pname, v);
    fprintf(out, "regime      %s (%s%s)\n", out_label(pt, lab, sizeof lab),
            wg_regime_name(pt->regime),
            pt->regime == WG_REGIME_PERIODIC && !pt->converged ? ", period from LLE < 0" : "");
    fprintf(out, "motion      %s, %.3g mesh impacts per period\n", wg_motion_name(pt->motion),
            pt->impacts);
    fprintf(out, "x_n         min %.6f, max %.6f\n", pt->min_xn, pt->max_xn);
    fprintf(out, "numerics    N = %d, one-period error %.2e, period tolerance %.2e, residual "
                 "%.2e\n",
            pt->steps, pt->err, pt->tol, pt->resid);
}

/* The largest Lyapunov exponent from y, for every point here, periodic or
 * not (printed only when it could be computed). */
static void print_lle(FILE *out, const wg_params *p, const double *y, const wg_sweep_opts *o,
                      int N)
{
    wg_sim sim, twin;
    char why[256];
    wg_sim_config cfg = {o->model, o->stepper, N};
    if (wg_sim_init(&sim, p, &cfg, why, sizeof why) != WG_OK)
        return;
    if (wg_sim_init(&twin, p, &cfg, why, sizeof why) == WG_OK) {
        wg_sim_set_state(&sim, y, 0, 0.0);
        wg_simmap sb = {&sim, 1}, st = {&twin, 1};
        wg_map mb = wg_simmap_map(&sb), mt = wg_simmap_map(&st);
        double x[WG_NSTATE_MAX], lle;
        memcpy(x, y, sizeof x);
        if (wg_lle_twin(&mb, &mt, x, o->lle_periods, o->lle_d0, &lle) == WG_OK)
            fprintf(out, "lyapunov    %.5f per mesh period (%d periods, d0 = %g)\n", lle,
                    o->lle_periods, o->lle_d0);
        wg_sim_fini(&twin);
    }
    wg_sim_fini(&sim);
}

/* Replay the orbit and write its trace CSV and (ao->png) PNGs: 0, or 1. */
static int write_views(FILE *out, const wg_params *p, const double *y, const wg_sweep_opts *o,
                       const at_opts *ao, int N)
{
    views w;
    int rc = 1;
    if (views_alloc(&w, ao->periods, ao->trace_periods, N) == 0 &&
        replay(p, y, o, N, ao, &w) == 0) {
        char base[1024], path[1100], title[200], tag[96];
        snprintf(base, sizeof base, "%s-at-%s", ao->prefix,
                 out_tag(tag, sizeof tag, ao->pname, ao->value));
        snprintf(path, sizeof path, "%s-trace.csv", base);
        rc = write_trace(path, &w);
        snprintf(title, sizeof title, "%s = %g", ao->pname, ao->value);
        if (ao->png)
            rc |= write_pngs(base, title, &w, p->v[WG_P_B]);
        fprintf(out, "files       %s-trace.csv", base);
        if (ao->png)
            fprintf(out, ", %s-phase.png, %s-poincare.png, %s-trace.png", base, base, base);
        fputc('\n', out);
    }
    views_free(&w);
    return rc;
}

int at_view(const wg_params *p, const double *y0, const wg_sweep_opts *o, const at_opts *ao,
            FILE *out)
{
    wg_point *pt = calloc(1, sizeof *pt);
    double y[WG_NSTATE_MAX];
    char why[256];
    memcpy(y, y0, sizeof y);
    if (!pt || wg_point_run(p, o, y, pt, why, sizeof why)) {
        fprintf(stderr, "wgsweep: --at: %s\n", pt ? why : "out of memory");
        free(pt);
        return 1;
    }
    summary(out, pt, ao->value, ao);
    print_lle(out, p, y, o, pt->steps);
    if (pt->regime == WG_REGIME_PERIODIC && pt->period > 0)
        print_floquet(out, p, y, o, pt->steps, pt->period);
    int rc = write_views(out, p, y, o, ao, pt->steps);
    free(pt);
    return rc;
}

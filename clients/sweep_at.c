/* sweep_at.c - single-point views for wgsweep --at (see sweep_at.h). */
#include "sweep_at.h"
#include "plot.h"
#include "plot_text.h"
#include "sweep_out.h"
#include "wormgear/wg_model.h"
#include "wormgear/wg_shoot.h"
#include "wormgear/wg_snapshot.h"
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

int at_state_load(const char *path, const char *scene, int model, wg_params *p, double *y,
                  char *why, size_t whylen)
{
    char sname[WG_SNAPSHOT_SCENE_MAX], w[320];
    wg_snapshot snap;
    if (wg_snapshot_load(path, &snap, sname, sizeof sname, why, whylen))
        return 1;
    if (strcmp(sname, scene) || snap.model != model) {
        snprintf(why, whylen, "%s: a snapshot of scene %s (%s model); this run is scene %s (%s "
                 "model): pass --scene %s", path, sname, wg_model_name(snap.model), scene,
                 wg_model_name(model), sname);
        return 1;
    }
    wg_sim sim;
    wg_sim_config cfg = {snap.model, snap.stepper, snap.steps_per_period};
    if (wg_sim_init(&sim, &snap.p, &cfg, w, sizeof w)) {
        snprintf(why, whylen, "%s: %s", path, w);
        return 1;
    }
    if (wg_sim_restore(&sim, &snap, w, sizeof w)) {
        snprintf(why, whylen, "%s: %s", path, w);
        wg_sim_fini(&sim);
        return 1;
    }
    uint32_t N = (uint32_t)snap.steps_per_period;
    int rc = wg_sim_run(&sim, (N - snap.k) % N, NULL, NULL); /* on to psi = 0 */
    if (rc)
        snprintf(why, whylen, "%s: running to the next section: %s", path, wg_status_str(rc));
    else
        wg_sim_snapshot(&sim, &snap), *p = snap.p, memcpy(y, snap.y, sizeof snap.y);
    wg_sim_fini(&sim);
    return rc ? 1 : 0;
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

/* What the figures of one point share. */
typedef struct fig {
    const at_opts *ao;
    const char *base, *title;      /* file base; "table3, omega = 1.2" */
    const char *note;              /* regime and Lyapunov exponent */
    plot_page pg;
    double b, omega;
    out_files *files;              /* each figure written is added */
} fig;

static int fig_write(const fig *g, const char *what, plot_xy *p)
{
    char path[1100], why[256];
    snprintf(path, sizeof path, "%s-%s.%s", g->base, what, plot_text_ext(g->ao->format));
    if (plot_xy_write(path, p, why, sizeof why)) {
        fprintf(stderr, "wgsweep: %s\n", why);
        return 1;
    }
    out_files_add(g->files, path);
    return 0;
}

/* The time trace: t in ms from the trace's first period (tau when the
 * scene has no usable scale), mesh periods on top. */
static int trace_fig(const fig *g, const views *w, plot_xy *p, char *t)
{
    const units_scale *us = &g->ao->us;
    double *ms = malloc(sizeof(double) * (size_t)(w->nt ? w->nt : 1));
    if (!ms)
        return 1;
    double T = 6.283185307179586 / g->omega, t0 = (double)w->trace_from * T;
    double k = units_scale_ok(us) ? 1e3 * units_s_per_tau(us) : 1.0;
    for (int i = 0; i < w->nt; i++)
        ms[i] = (w->t[i] - t0) * k;
    snprintf(t, 300, "%s: time trace, %d mesh periods (T = %.4g %s)", g->title,
             g->ao->trace_periods, T * k, units_scale_ok(us) ? "ms" : "in τ");
    p->title = t, p->x = ms, p->y = w->x, p->n = w->nt, p->b = g->b, p->b_on_x = 0;
    p->xlabel = units_scale_ok(us) ? "t from the first traced period  (ms)" : "τ = ω_n t  (-)";
    p->ylabel = PLOT_XN_LABEL;
    int tp = g->ao->trace_periods;
    p->x2 = (plot_scale2){1.0 / (T * k), "mesh periods", tp <= 40 ? 1 : tp <= 100 ? 5 : 0};
    p->y2 = (plot_scale2){units_scale_ok(us) ? units_um_per_x(us) : 0, PLOT_XN_UM, 0};
    p->pg = g->pg;
    int rc = fig_write(g, "trace", p);
    free(ms);
    return rc;
}

static int write_figs(const fig *g, const views *w)
{
    const units_scale *us = &g->ao->us;
    int ok = units_scale_ok(us), rc = 0;
    char t[300];
    static const char vlab[] = "x_n' = dx_n/dτ  (b_c ω_n)";
    plot_scale2 xum = {ok ? units_um_per_x(us) : 0, PLOT_XN_UM, 0};
    plot_scale2 vms = {ok ? units_m_s_per_v(us) : 0, "x_n'  (m/s)", 0};
    snprintf(t, sizeof t, "%s: phase portrait, the last %d mesh periods", g->title,
             g->ao->trace_periods);
    plot_xy ph = {.title = t, .xlabel = PLOT_XN_LABEL, .ylabel = vlab, .x = w->x, .y = w->v,
                  .n = w->nt, .b = g->b, .b_on_x = 1, .x2 = xum, .y2 = vms, .note = g->note,
                  .pg = g->pg};
    rc |= fig_write(g, "phase", &ph);
    snprintf(t, sizeof t, "%s: Poincaré map at ψ = 0, %d periods", g->title, w->ns);
    plot_xy pm = ph;
    pm.x = w->sx, pm.y = w->sy, pm.n = w->ns, pm.dots = 1;
    rc |= fig_write(g, "poincare", &pm);
    plot_xy tr = {0};
    rc |= trace_fig(g, w, &tr, t);
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
    fprintf(out, "point       %s = %.15g\n", ao->pname, v);
    fprintf(out, "regime      %s (%s%s)\n", out_label(pt, lab, sizeof lab),
            wg_regime_name(pt->regime),
            pt->regime == WG_REGIME_PERIODIC && !pt->converged ? ", period from LLE < 0" : "");
    fprintf(out, "motion      %s, %.3g mesh impacts per period\n", wg_motion_name(pt->motion),
            pt->impacts);
    fprintf(out, "bearings    impacts per period (largest |velocity|):");
    for (int j = 0; j < WG_NBEARING; j++)
        fprintf(out, " %s %.3g (%.3g)", wg_contact_name(WG_C_X1 + j), pt->bimpacts[j],
                pt->bvmax[j]);
    fprintf(out, "\n");
    fprintf(out, "x_n         min %.6f, max %.6f\n", pt->min_xn, pt->max_xn);
    fprintf(out, "numerics    N = %d, one-period error %.2e, period tolerance %.2e, residual "
                 "%.2e\n",
            pt->steps, pt->err, pt->tol, pt->resid);
}

/* The largest Lyapunov exponent from y, for every point here, periodic or
 * not (printed only when it could be computed). */
static double print_lle(FILE *out, const wg_params *p, const double *y, const wg_sweep_opts *o,
                        int N)
{
    double lle = NAN;
    wg_sim sim, twin;
    char why[256];
    wg_sim_config cfg = {o->model, o->stepper, N};
    if (wg_sim_init(&sim, p, &cfg, why, sizeof why) != WG_OK)
        return lle;
    if (wg_sim_init(&twin, p, &cfg, why, sizeof why) == WG_OK) {
        wg_sim_set_state(&sim, y, 0, 0.0);
        double x[WG_NSTATE_MAX], v;
        memcpy(x, y, sizeof x);
        if (wg_lle_sims(&sim, &twin, x, o->lle_periods, o->lle_d0, NULL, NULL, &v) == WG_OK) {
            lle = v;
            fprintf(out, "lyapunov    %.5f per mesh period (%d periods, d0 = %g)\n", lle,
                    o->lle_periods, o->lle_d0);
        }
        wg_sim_fini(&twin);
    }
    wg_sim_fini(&sim);
    return lle;
}

/* Replay the orbit and write its trace CSV and (ao->png) figures, which
 * carry the point's regime and Lyapunov exponent lle: 0, or 1. */
static int write_views(FILE *out, const wg_params *p, const double *y, const wg_sweep_opts *o,
                       const at_opts *ao, const wg_point *pt, double lle)
{
    views w;
    int rc = 1, N = pt->steps;
    if (views_alloc(&w, ao->periods, ao->trace_periods, N) == 0 &&
        replay(p, y, o, N, ao, &w) == 0) {
        char base[1024], path[1100], title[200], tag[96], note[200], lab[32], cap[2][400];
        snprintf(base, sizeof base, "%s-at-%s", ao->prefix,
                 out_tag(tag, sizeof tag, ao->pname, ao->value));
        snprintf(path, sizeof path, "%s-trace.csv", base);
        out_files files = {"", 0};
        rc = write_trace(path, &w);
        if (!rc)
            out_files_add(&files, path);
        snprintf(title, sizeof title, "%s, %s = %.15g", ao->scene ? ao->scene : "",
                 plot_text_psym(wg_param_lookup(ao->pname)), ao->value);
        int n = pt->regime == WG_REGIME_PERIODIC /* "P2 (periodic)"; "chaotic", once */
                    ? snprintf(note, sizeof note, "%s (periodic), %s", out_label(pt, lab, sizeof lab),
                               wg_motion_name(pt->motion))
                    : snprintf(note, sizeof note, "%s, %s", wg_regime_name(pt->regime),
                               wg_motion_name(pt->motion));
        snprintf(note + n, sizeof note - (size_t)n, isfinite(lle) ? ", λ = %.4f per mesh period"
                 : ", λ not computed", lle);
        if (ao->scene_p)
            plot_text_caption(cap, ao->scene, p, ao->scene_p, -1, -1, o, N, N);
        char run[160]; /* the record classifies; the figures are the periods after it */
        snprintf(run, sizeof run, "class and λ from the periods recorded; then %d periods run "
                 "for these figures", ao->periods);
        fig g = {ao, base, title, note, {ao->format, {ao->scene_p ? cap[0] : run,
                 ao->scene_p ? cap[1] : NULL, ao->scene_p ? run : NULL, NULL}}, p->v[WG_P_B],
                 p->v[WG_P_OMEGA], &files};
        if (ao->png)
            rc |= write_figs(&g, &w);
        fprintf(out, "files       %s\n", files.n ? files.list : "none written");
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
    double lle = print_lle(out, p, y, o, pt->steps);
    if (pt->regime == WG_REGIME_PERIODIC && pt->period > 0)
        print_floquet(out, p, y, o, pt->steps, pt->period);
    else if (o->floquet) /* asked for, and silent at a chaotic point */
        fprintf(out, "floquet     none: no periodic orbit here (%s); multipliers belong to a "
                "periodic point\n", wg_regime_name(pt->regime));
    int rc = write_views(out, p, y, o, ao, pt, lle);
    free(pt);
    return rc;
}

/* sweep_out.c - writers of a sweep study (see sweep_out.h). */
#include "sweep_out.h"
#include "cli.h"
#include "plot.h"
#include "plot_text.h"
#include "sweep_md.h"

#include <math.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>

const char *out_pname(int id)
{
    const wg_param_info *r = wg_param_info_get(id);
    return r ? r->name : "?";
}

double out_group_b(const sweep_study *st, const sweep_group *g)
{
    return st->param == WG_P_B ? NAN : st->gparam == WG_P_B ? g->gval : st->b;
}

FILE *out_open(const char *path, char *why, size_t whylen)
{
    FILE *f = fopen(path, "w");
    if (!f)
        snprintf(why, whylen, "cannot write %s: %m", path);
    return f;
}

int out_close(FILE *f, const char *path, char *why, size_t whylen)
{
    int bad = ferror(f);
    if (fclose(f) || bad) {
        snprintf(why, whylen, "error writing %s", path);
        return -1;
    }
    return 0;
}

const char *out_label(const wg_point *p, char *buf, size_t len)
{
    switch (p->regime) {
    case WG_REGIME_PERIODIC:
        if (p->period)
            snprintf(buf, len, "P%d", p->period);
        else
            snprintf(buf, len, "P? (n>32)");
        break;
    case WG_REGIME_QUASIPERIODIC: snprintf(buf, len, "quasi"); break;
    case WG_REGIME_CHAOTIC: snprintf(buf, len, "chaos"); break;
    case WG_REGIME_DIVERGED: snprintf(buf, len, "diverged"); break;
    default: snprintf(buf, len, "-"); break;
    }
    return buf;
}

/* Chains of a group in a fixed order: up then down. */
static int group_chains(const sweep_group *g, const wg_chain *c[2], const char *dir[2])
{
    int n = 0;
    if (g->up)
        c[n] = g->up, dir[n++] = "up";
    if (g->down)
        c[n] = g->down, dir[n++] = "down";
    return n;
}

/* ---- CSV --------------------------------------------------------------- */

const char *const out_point_cols[OUT_POINT_NCOLS] = {
    "regime", "period", "converged", "motion", "impacts_per_period", "min_xn", "max_xn",
    "lle_per_period", "err", "tol", "resid", "steps_per_period", "floquet1_re", "floquet1_im",
    "floquet1_abs", "check2n_regime", "check2n_period", "check2n_motion",
    "x1_impacts_per_period", "y1_impacts_per_period", "z1_impacts_per_period",
    "x2_impacts_per_period", "y2_impacts_per_period", "z2_impacts_per_period",
    "x1_impact_vmax", "y1_impact_vmax", "z1_impact_vmax", "x2_impact_vmax", "y2_impact_vmax",
    "z2_impact_vmax"};

static void csv_point(FILE *f, const sweep_study *st, const sweep_group *g, const char *dir,
                      int i, const wg_point *p)
{
    if (st->gparam >= 0)
        fprintf(f, "%.10g,", g->gval);
    if (!wg_point_measured(p)) { /* its value and regime (none, diverged), the rest empty */
        fprintf(f, "%s,%d,%.10g,%s", dir, i, p->value, wg_regime_name(p->regime));
        for (int c = 1; c < OUT_POINT_NCOLS; c++)
            fputc(',', f);
        fputc('\n', f);
        return;
    }
    fprintf(f, "%s,%d,%.10g,%s,%d,%d,%s,%.6g,%.12g,%.12g,%.6g,%.3e,%.3e,%.3e,%d", dir, i,
            p->value, wg_regime_name(p->regime), p->period, p->converged,
            wg_motion_name(p->motion), p->impacts, p->min_xn, p->max_xn, p->lle, p->err, p->tol,
            p->resid, p->steps);
    if (p->nfloq)
        fprintf(f, ",%.9g,%.9g,%.9g", p->floq_re[0], p->floq_im[0],
                hypot(p->floq_re[0], p->floq_im[0]));
    else
        fprintf(f, ",,,");
    if (p->checked)
        fprintf(f, ",%s,%d,%s", wg_regime_name(p->check_regime), p->check_period,
                wg_motion_name(p->check_motion));
    else
        fprintf(f, ",,,");
    for (int j = 0; j < WG_NBEARING; j++)
        fprintf(f, ",%.6g", p->bimpacts[j]);
    for (int j = 0; j < WG_NBEARING; j++)
        fprintf(f, ",%.6g", p->bvmax[j]);
    fputc('\n', f);
}

int out_points_csv(const char *path, const sweep_study *st, char *why, size_t whylen)
{
    FILE *f = out_open(path, why, whylen);
    if (!f)
        return -1;
    if (st->gparam >= 0)
        fprintf(f, "%s,", out_pname(st->gparam));
    fprintf(f, "dir,index,%s", out_pname(st->param));
    for (int i = 0; i < OUT_POINT_NCOLS; i++)
        fprintf(f, ",%s", out_point_cols[i]);
    fputc('\n', f);
    for (int k = 0; k < st->ngroups; k++) {
        const wg_chain *c[2];
        const char *dir[2];
        int nc = group_chains(&st->g[k], c, dir);
        for (int j = 0; j < nc; j++)
            for (int i = 0; i < c[j]->ndone; i++)
                csv_point(f, st, &st->g[k], dir[j], i, &c[j]->pts[i]);
    }
    return out_close(f, path, why, whylen);
}

int out_poincare_csv(const char *path, const sweep_study *st, char *why, size_t whylen)
{
    FILE *f = out_open(path, why, whylen);
    if (!f)
        return -1;
    if (st->gparam >= 0)
        fprintf(f, "%s,", out_pname(st->gparam));
    fprintf(f, "dir,index,%s,k,x_n,dx_n\n", out_pname(st->param));
    for (int k = 0; k < st->ngroups; k++) {
        const wg_chain *c[2];
        const char *dir[2];
        int nc = group_chains(&st->g[k], c, dir);
        for (int j = 0; j < nc; j++)
            for (int i = 0; i < c[j]->ndone; i++) {
                const wg_point *p = &c[j]->pts[i];
                char pre[160]; /* the point's columns, formatted once for its rows */
                int np = st->gparam >= 0 ? snprintf(pre, sizeof pre, "%.10g,", st->g[k].gval) : 0;
                snprintf(pre + np, sizeof pre - (size_t)np, "%s,%d,%.10g,", dir[j], i, p->value);
                for (int s = 0; s < p->nsec; s++)
                    fprintf(f, "%s%d,%.12g,%.12g\n", pre, s, p->xn[s], p->dxn[s]);
            }
    }
    return out_close(f, path, why, whylen);
}

int out_map_csv(const char *path, const wg_chain *rows, int nrows, char *why, size_t whylen)
{
    FILE *f = out_open(path, why, whylen);
    if (!f)
        return -1;
    if (nrows)
        fprintf(f, "%s,%s,regime,period,motion,impacts_per_period,min_xn,max_xn,lle_per_period\n",
                out_pname(rows[0].param2), out_pname(rows[0].param));
    for (int r = 0; r < nrows; r++)
        for (int i = 0; i < rows[r].ndone; i++) {
            const wg_point *p = &rows[r].pts[i];
            if (!wg_point_measured(p)) { /* its values and regime, the rest empty */
                fprintf(f, "%.10g,%.10g,%s,,,,,,\n", p->value2, p->value,
                        wg_regime_name(p->regime));
                continue;
            }
            fprintf(f, "%.10g,%.10g,%s,%d,%s,%.6g,%.12g,%.12g,%.6g\n", p->value2, p->value,
                    wg_regime_name(p->regime), p->period, wg_motion_name(p->motion), p->impacts,
                    p->min_xn, p->max_xn, p->lle);
        }
    return out_close(f, path, why, whylen);
}

/* ---- JSON ---------------------------------------------------------------- */

/* A number, or null when not finite (JSON has no NaN). */
static void jnum(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.12g", v);
    else
        fputs("null", f);
}

static void json_point(FILE *f, const wg_point *p)
{
    if (!wg_point_measured(p)) { /* the same keys, null where nothing was measured */
        fprintf(f, "{\"value\":%.12g,\"regime\":\"%s\",\"period\":null,\"converged\":null,"
                   "\"motion\":null,\"impacts_per_period\":null,\"min_xn\":null,\"max_xn\":null,"
                   "\"lle_per_period\":null,\"err\":null,\"tol\":null,\"resid\":null,"
                   "\"steps_per_period\":null,\"poincare_xn\":[],\"poincare_dxn\":[]}",
                p->value, wg_regime_name(p->regime));
        return;
    }
    fprintf(f, "{\"value\":%.12g,\"regime\":\"%s\",\"period\":%d,\"converged\":%s,"
               "\"motion\":\"%s\",\"impacts_per_period\":%.6g,\"min_xn\":",
            p->value, wg_regime_name(p->regime), p->period, p->converged ? "true" : "false",
            wg_motion_name(p->motion), p->impacts);
    jnum(f, p->min_xn);
    fputs(",\"max_xn\":", f);
    jnum(f, p->max_xn);
    fputs(",\"lle_per_period\":", f);
    jnum(f, p->lle);
    fprintf(f, ",\"err\":%.3e,\"tol\":%.3e,\"resid\":", p->err, p->tol);
    jnum(f, p->resid);
    fprintf(f, ",\"steps_per_period\":%d,\"poincare_xn\":[", p->steps);
    for (int s = 0; s < p->nsec; s++)
        fprintf(f, "%s%.10g", s ? "," : "", p->xn[s]);
    fputs("],\"poincare_dxn\":[", f);
    for (int s = 0; s < p->nsec; s++)
        fprintf(f, "%s%.10g", s ? "," : "", p->dxn[s]);
    fputs("]", f);
    if (p->checked)
        fprintf(f, ",\"check2n\":{\"regime\":\"%s\",\"period\":%d,\"motion\":\"%s\"}",
                wg_regime_name(p->check_regime), p->check_period, wg_motion_name(p->check_motion));
    if (p->nfloq) {
        fputs(",\"floquet\":[", f);
        for (int s = 0; s < p->nfloq; s++)
            fprintf(f, "%s[%.9g,%.9g]", s ? "," : "", p->floq_re[s], p->floq_im[s]);
        fputs("]", f);
    }
    fputs("}", f);
}

static void json_chain(FILE *f, const char *name, const wg_chain *c)
{
    fprintf(f, ",\"%s\":{\"status\":\"%s\",\"points\":[", name,
            c->rc ? c->why : "ok");
    for (int i = 0; i < c->ndone; i++) {
        fputs(i ? ",\n" : "\n", f);
        json_point(f, &c->pts[i]);
    }
    fprintf(f, "],\"complete\":%s}", c->ndone == c->npts ? "true" : "false");
}

static void json_transitions(FILE *f, const sweep_study *st, const sweep_group *g)
{
    wg_transition *t = malloc(sizeof *t * STUDY_MAX_TRANS);
    int n = t ? wg_transitions(g->up ? g->up->pts : NULL, g->up ? g->up->ndone : 0,
                               g->down ? g->down->pts : NULL, g->down ? g->down->ndone : 0,
                               out_group_b(st, g), t, STUDY_MAX_TRANS)
              : 0;
    fputs(",\"transitions\":[", f);
    for (int i = 0; i < n; i++) {
        fprintf(f, "%s\n{\"kind\":\"%s\",\"dir\":%d,\"lo\":%.10g,\"hi\":%.10g,\"at\":%.10g,"
                   "\"from\":%d,\"to\":%d,\"lo2\":",
                i ? "," : "", wg_trans_name(t[i].kind), t[i].dir, t[i].lo, t[i].hi, t[i].at,
                t[i].from, t[i].to);
        jnum(f, t[i].lo2);
        fputs(",\"hi2\":", f);
        jnum(f, t[i].hi2);
        fputs("}", f);
    }
    fputs("]", f);
    free(t);
}

/* The analysis options; run (a ramp's words, sweep_study) in their place:
 * a ramp runs no per-point transient, record or extension. */
static void json_opts(FILE *f, const wg_sweep_opts *o, const char *run)
{
    fprintf(f, "\"options\":{\"model\":\"%s\",\"stepper\":\"%s\",\"steps_per_period\":%d,",
            wg_model_name(o->model), wg_stepper_name(o->stepper), o->steps);
    if (run) {
        fputs("\"run\":", f);
        cli_json_str(f, run);
    } else {
        fprintf(f, "\"transient\":%d,\"settle\":%d,\"record\":%d,\"extend\":%d,\"lle_periods\":%d,"
                   "\"lle_d0\":%g", o->transient, o->settle, o->record, o->extend,
                o->lle_periods, o->lle_d0);
    }
    fprintf(f, ",\"lle_tol\":%g,\"tol_factor\":%g,\"tol_floor\":%g,\"floquet\":%s,"
               "\"verify_2n\":%s}", o->lle_tol, o->tol_factor, o->tol_floor,
            o->floquet ? "true" : "false", o->verify ? "true" : "false");
}

int out_json(const char *path, const sweep_study *st, char *why, size_t whylen)
{
    FILE *f = out_open(path, why, whylen);
    if (!f)
        return -1;
    fputs("{\"scene\":", f);
    cli_json_str(f, st->scene); /* a loader's rule, escaped here all the same */
    fprintf(f, ",\"param\":\"%s\",\"group_param\":", out_pname(st->param));
    if (st->gparam >= 0)
        fprintf(f, "\"%s\"", out_pname(st->gparam));
    else
        fputs("null", f);
    fprintf(f,
            ",\"b\":%g,\"partial\":%s,\"wall_s\":%.3f,\"threads\":%d,\"pair\":%d,\"ranks\":%d,\n",
            st->b, st->partial ? "true" : "false", st->wall_s, st->threads, st->pair, st->ranks);
    json_opts(f, st->o, st->run);
    fputs(",\n\"groups\":[", f);
    for (int k = 0; k < st->ngroups; k++) {
        const sweep_group *g = &st->g[k];
        fprintf(f, "%s\n{\"value\":", k ? "," : "");
        jnum(f, st->gparam >= 0 ? g->gval : NAN);
        if (g->up)
            json_chain(f, "up", g->up);
        if (g->down)
            json_chain(f, "down", g->down);
        json_transitions(f, st, g);
        fputs("}", f);
    }
    fputs("]}\n", f);
    return out_close(f, path, why, whylen);
}

/* ---- PNG ------------------------------------------------------------------- */

void out_files_add(out_files *files, const char *path)
{
    if (!files)
        return;
    size_t len = strlen(files->list);
    snprintf(files->list + len, sizeof files->list - len, "%s%s", files->n++ ? ", " : "", path);
}

const char *out_tag(char *buf, size_t len, const char *name, double v)
{
    snprintf(buf, len, "%s-%.15g", name, v); /* 1.37880005 and 1.37880006 apart */
    return buf;
}

/* The N range of a group's points (0, 0: none). */
static void steps_range(const sweep_group *g, int *lo, int *hi)
{
    const wg_chain *cs[2] = {g->up, g->down};
    *lo = 0, *hi = 0;
    for (int c = 0; c < 2; c++)
        for (int i = 0; cs[c] && i < cs[c]->ndone; i++) {
            int n = cs[c]->pts[i].steps;
            *lo = !*lo || n < *lo ? n : *lo;
            *hi = n > *hi ? n : *hi;
        }
}

/* Group k's bifurcation diagram: its path into path (len), then drawn. */
static int out_png_group(const char *prefix, const sweep_study *st, int k, char *path,
                         size_t len, char *why, size_t whylen)
{
    const char *ext = plot_text_ext(st->format);
    const sweep_group *g = &st->g[k];
    const wg_chain *c = g->up ? g->up : g->down;
    char title[256], tag[96], xl[96], x2l[96], cap[2][400] = {"", ""};
    if (st->gparam >= 0) {
        snprintf(path, len, "%s-%s.%s", prefix,
                 out_tag(tag, sizeof tag, out_pname(st->gparam), g->gval), ext);
        snprintf(title, sizeof title, "%s: bifurcation diagram in %s, %s = %.15g%s", st->scene,
                 plot_text_psym(st->param), plot_text_psym(st->gparam), g->gval,
                 st->partial ? " (partial)" : "");
    } else {
        snprintf(path, len, "%s.%s", prefix, ext);
        snprintf(title, sizeof title, "%s: bifurcation diagram in %s%s", st->scene,
                 plot_text_psym(st->param), st->partial ? " (partial)" : "");
    }
    int nlo, nhi;
    steps_range(g, &nlo, &nhi);
    if (c && st->scene_p)
        plot_text_caption_run(cap, st->scene, &c->base, st->scene_p, st->param, -1, st->o, nlo,
                              nhi, st->run);
    plot_bif pb = {title, plot_text_plabel(st->param, xl, sizeof xl), g->up ? g->up->pts : NULL,
                   g->down ? g->down->pts : NULL, g->up ? g->up->ndone : 0,
                   g->down ? g->down->ndone : 0, out_group_b(st, g), NULL, 0,
                   c ? plot_text_pscale(st->param, &c->base, &st->us, x2l, sizeof x2l)
                     : (plot_scale2){0, NULL, 0},
                   {units_scale_ok(&st->us) ? units_um_per_x(&st->us) : 0, PLOT_XN_UM, 0},
                   {st->format, {c && st->scene_p ? cap[0] : NULL, cap[1], NULL, NULL}}};
    return plot_bifurcation(path, &pb, why, whylen);
}

int out_pngs(const char *prefix, const sweep_study *st, out_files *files, char *why,
             size_t whylen)
{
    int rc = 0;
    for (int k = 0; k < st->ngroups && !rc; k++) {
        char path[1024];
        rc = out_png_group(prefix, st, k, path, sizeof path, why, whylen);
        if (!rc)
            out_files_add(files, path);
    }
    return rc;
}

/* ---- a study's files, written by threads at once ------------------------------ */

enum { JOB_CSV, JOB_POINCARE, JOB_MD, JOB_JSON, JOB_FIG };

typedef struct out_job {
    int kind, group; /* group: JOB_FIG's */
    int lane;        /* out_study's: 1 on the other thread */
    int rc;
    char path[1024], why[512];
} out_job;

/* One thread's share: the jobs of one lane, in order. */
typedef struct out_lane {
    const char *prefix;
    const sweep_study *st;
    out_job *jobs;
    int n, lane; /* 1: the other thread's */
} out_lane;

static void run_job(const out_lane *w, out_job *j)
{
    static const char *const suffix[] = {".csv", "-poincare.csv", ".md", ".json"};
    const sweep_study *st = w->st;
    if (j->kind == JOB_FIG) {
        j->rc = out_png_group(w->prefix, st, j->group, j->path, sizeof j->path, j->why,
                              sizeof j->why);
        return;
    }
    snprintf(j->path, sizeof j->path, "%s%s", w->prefix, suffix[j->kind]);
    j->rc = j->kind == JOB_CSV        ? out_points_csv(j->path, st, j->why, sizeof j->why)
            : j->kind == JOB_POINCARE ? out_poincare_csv(j->path, st, j->why, sizeof j->why)
            : j->kind == JOB_MD       ? md_write(j->path, st, j->why, sizeof j->why)
                                      : out_json(j->path, st, j->why, sizeof j->why);
}

static void *out_lane_run(void *arg)
{
    out_lane *w = arg;
    for (int i = 0; i < w->n; i++)
        if (w->jobs[i].lane == w->lane)
            run_job(w, &w->jobs[i]);
    return NULL;
}

int out_study(const char *prefix, const sweep_study *st, int json, int figures, int threads,
              out_files *files, char *why, size_t whylen)
{
    out_job jobs[4 + STUDY_MAX_GROUPS];
    int n = 0;
    static const int files_kind[] = {JOB_CSV, JOB_POINCARE, JOB_MD, JOB_JSON};
    for (int i = 0; i < 4; i++)
        if (files_kind[i] != JOB_JSON || json)
            jobs[n++] = (out_job){.kind = files_kind[i]};
    for (int k = 0; figures && k < st->ngroups && k < STUDY_MAX_GROUPS; k++)
        jobs[n++] = (out_job){.kind = JOB_FIG, .group = k};
    /* Two lanes: the figures on the other thread, the data files on this
     * one; without figures the JSON goes there (measured on the Table-3
     * study: the three figures 0.14 s, the Poincare CSV 0.085 s, the JSON
     * 0.045 s, the rest 0.005 s). cairo draws on one thread at a time: run
     * beside itself, ThreadSanitizer reported races inside fontconfig and
     * FreeType under it. */
    int other = 0;
    for (int i = 0; i < n; i++) {
        jobs[i].lane = jobs[i].kind == JOB_FIG || (jobs[i].kind == JOB_JSON && !figures);
        other |= jobs[i].lane;
    }
    out_lane there = {prefix, st, jobs, n, 1}, here = {prefix, st, jobs, n, 0};
    pthread_t tid;
    int apart = other && threads > 1 && pthread_create(&tid, NULL, out_lane_run, &there) == 0;
    out_lane_run(&here);
    if (apart)
        pthread_join(tid, NULL);
    else
        out_lane_run(&there);
    int rc = 0;
    size_t len = 0;
    for (int i = 0; i < n; i++) {
        if (jobs[i].rc) {
            if (len < whylen)
                len += (size_t)snprintf(why + len, whylen - len, "%s%s", rc ? "; " : "",
                                        jobs[i].why);
            rc = -1;
        } else {
            out_files_add(files, jobs[i].path);
        }
    }
    return rc;
}

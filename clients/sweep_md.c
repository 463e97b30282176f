/* sweep_md.c - the Markdown transitions table of a study (see sweep_md.h):
 * the up and down sweeps' transitions matched by kind, periods and
 * proximity, and the continuation's exact points beside them (--exact). */
#include "sweep_md.h"
#include "sweep_exact.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

static double grid_step(const wg_chain *c)
{
    return c && c->npts > 1 ? fabs(c->v1 - c->v0) / (c->npts - 1) : 0.0;
}

/* Decimals that show grid step h: 4 (the study's 0.0025 and coarser),
 * more for finer grids (a zoom with step 5e-8 read [1.3788, 1.3788]),
 * at most 12. */
static int decimals(double h)
{
    if (!(h > 0) || !isfinite(h))
        return 4;
    int d = (int)ceil(-log10(h) - 1e-9) + 1;
    return d < 4 ? 4 : d > 12 ? 12 : d;
}

static const char *per_name(int n, char *buf, size_t len)
{
    if (n)
        snprintf(buf, len, "P%d", n);
    else
        snprintf(buf, len, "aperiodic");
    return buf;
}

/* Text of one sweep's side of a row. */
static void cell(const wg_transition *t, int dg, char *buf, size_t len)
{
    if (!t) {
        snprintf(buf, len, "-");
        return;
    }
    switch (t->kind) {
    case WG_TR_CHAOS:
    case WG_TR_QUASI:
        snprintf(buf, len, "[%.*f, %.*f] (%d pts%s%d other)", dg, t->lo, dg, t->hi, t->from,
                 t->to ? ", " : "", t->to);
        if (!t->to) /* drop the ", 0 other" */
            snprintf(buf, len, "[%.*f, %.*f] (%d pts)", dg, t->lo, dg, t->hi, t->from);
        break;
    default:
        snprintf(buf, len, "%.*f (%.*f-%.*f)", dg, t->at, dg, t->lo, dg, t->hi);
    }
}

/* Description column. */
static void detail(const wg_transition *t, char *buf, size_t len)
{
    char a[24], b[24];
    switch (t->kind) {
    case WG_TR_GRAZING:
    case WG_TR_BACKSIDE:
        snprintf(buf, len, "%s -> %s", wg_motion_name(t->from), wg_motion_name(t->to));
        break;
    case WG_TR_CHAOS:
        snprintf(buf, len, "largest Lyapunov exponent > 0");
        break;
    case WG_TR_QUASI:
        snprintf(buf, len, "no period <= 32, |LLE| small");
        break;
    default:
        snprintf(buf, len, "%s -> %s", per_name(t->from, a, sizeof a), per_name(t->to, b, sizeof b));
    }
}

static const char *row_name(const wg_transition *t)
{
    if (t->kind == WG_TR_GRAZING)
        return t->to > t->from ? "grazing: impacts begin" : "grazing: impacts end";
    if (t->kind == WG_TR_BACKSIDE)
        return t->to > t->from ? "back-side impacts begin" : "back-side impacts end";
    if (t->kind == WG_TR_CHAOS)
        return "chaotic interval";
    if (t->kind == WG_TR_QUASI)
        return "quasi-periodic interval";
    return wg_trans_name(t->kind);
}

/* Same transition seen by the other sweep? */
static int same(const wg_transition *a, const wg_transition *b, double win)
{
    if (a->kind != b->kind)
        return 0;
    if (a->kind == WG_TR_CHAOS || a->kind == WG_TR_QUASI)
        return a->lo <= b->hi + win && b->lo <= a->hi + win;
    return a->from == b->from && a->to == b->to && fabs(a->at - b->at) <= win;
}

/* The "exact (continuation)" cell, when the group has wgcont's results. */
static void exact_col(FILE *f, const cont_bifs *ex, const wg_transition *up,
                      const wg_transition *dn, double win)
{
    char buf[256];
    if (!ex)
        return;
    exact_cell(ex, up, dn, win / 4.0, win, buf, sizeof buf); /* win: 4 grid steps at most */
    fprintf(f, " %s |", buf);
}

static void jump_row(FILE *f, const wg_transition *t, const cont_bifs *ex, double win, int dg)
{
    fprintf(f, "| jump (hysteresis) | %.*f (%.*f-%.*f) | %.*f (%.*f-%.*f) | up and down "
               "attractors differ over [%.*f, %.*f]; up: %s -> %s |",
            dg, 0.5 * (t->lo + t->hi), dg, t->lo, dg, t->hi, dg, 0.5 * (t->lo2 + t->hi2), dg,
            t->lo2, dg, t->hi2, dg, t->hi2, dg, t->lo, t->from ? "periodic" : "aperiodic",
            t->to ? "periodic" : "aperiodic");
    exact_col(f, ex, t, NULL, win);
    fputc('\n', f);
}

static void rows(FILE *f, wg_transition *t, int n, double win, const cont_bifs *ex, int dg)
{
    char *used = calloc((size_t)n + 1, 1);
    if (!used)
        return;
    for (int i = 0; i < n; i++) {
        if (used[i])
            continue;
        used[i] = 1;
        if (t[i].kind == WG_TR_JUMP) {
            jump_row(f, &t[i], ex, win, dg);
            continue;
        }
        const wg_transition *up = t[i].dir > 0 ? &t[i] : NULL, *dn = up ? NULL : &t[i];
        double best = INFINITY;
        int bj = -1;
        for (int j = i + 1; j < n; j++) /* the nearest partner from the other sweep */
            if (!used[j] && t[j].dir == -t[i].dir && same(&t[i], &t[j], win) &&
                fabs(t[j].at - t[i].at) < best)
                best = fabs(t[j].at - t[i].at), bj = j;
        if (bj >= 0) {
            used[bj] = 1;
            if (up)
                dn = &t[bj];
            else
                up = &t[bj];
        }
        char cu[96], cd[96], de[96];
        cell(up, dg, cu, sizeof cu);
        cell(dn, dg, cd, sizeof cd);
        detail(&t[i], de, sizeof de);
        fprintf(f, "| %s | %s | %s | %s |", row_name(&t[i]), cu, cd, de);
        exact_col(f, ex, up, dn, win);
        fputc('\n', f);
    }
    free(used);
}

/* A doubling, or several between two grid points (P4 -> P16). */
static int doubling(const wg_transition *t)
{
    if (t->kind == WG_TR_DOUBLING)
        return 1;
    return t->kind == WG_TR_PERIOD && t->from > 0 && t->to > t->from && t->to % t->from == 0 &&
           ((t->to / t->from) & (t->to / t->from - 1)) == 0;
}

/* Period-doubling cascades of one sweep: the doublings since the last
 * return to period-1 before each chaotic interval (t sorted by value). */
static void cascades(FILE *f, const wg_transition *t, int n, int dir, int dg)
{
    for (int i = 0; i < n; i++) {
        if (t[i].kind != WG_TR_CHAOS || t[i].dir != dir)
            continue;
        int first = i;
        for (int j = i - 1; j >= 0; j--) {
            if (t[j].dir != dir)
                continue;
            if (t[j].kind == WG_TR_RETURN_P1 || (t[j].kind == WG_TR_CHAOS && t[j].hi < t[i].lo))
                break;
            if (doubling(&t[j]))
                first = j;
        }
        fprintf(f, "- %s sweep: ", dir > 0 ? "up" : "down");
        for (int j = first; j < i; j++)
            if (t[j].dir == dir && doubling(&t[j]))
                fprintf(f, "P%d->P%d at %.*f, ", t[j].from, t[j].to, dg, t[j].at);
        fprintf(f, "chaos from %.*f to %.*f\n", dg, t[i].lo, dg, t[i].hi);
    }
}

/* The up sweep as a sequence of regime segments. */
static void route(FILE *f, const wg_chain *c, int dg)
{
    char a[24], b[24];
    fputs("Route of the up sweep: ", f);
    for (int i = 0; i < c->ndone;) {
        int j = i;
        out_label(&c->pts[i], a, sizeof a);
        while (j + 1 < c->ndone && strcmp(out_label(&c->pts[j + 1], b, sizeof b), a) == 0)
            j++;
        if (j > i)
            fprintf(f, "%s%s %.*f-%.*f", i ? " | " : "", a, dg, c->pts[i].value, dg,
                    c->pts[j].value);
        else
            fprintf(f, "%s%s %.*f", i ? " | " : "", a, dg, c->pts[i].value);
        i = j + 1;
    }
    fputs("\n\n", f);
}

/* The points of chain c (dir) not measured and with no regime (wg_point_measured). */
static void not_measured(FILE *f, const char *dir, const wg_chain *c, const char *p, int dg)
{
    int n = 0;
    for (int i = 0; c && i < c->ndone; i++) {
        if (wg_point_measured(&c->pts[i]) || c->pts[i].regime != WG_REGIME_NONE)
            continue; /* a diverged point: its route says so */
        if (!n++)
            fprintf(f, "Not measured in the %s sweep (refused by the daemon; the run's messages "
                       "say why; their rows have regime none and no other value): %s = ", dir, p);
        else
            fputs(", ", f);
        fprintf(f, "%.*f", dg, c->pts[i].value);
    }
    if (n)
        fputs("\n\n", f);
}

/* Step-halving check of one chain: how many points keep their
 * classification (regime, period, motion class) with 2N steps. */
static void halving(FILE *f, const char *dir, const wg_chain *c, int dg)
{
    int n = 0, same = 0, shown = 0;
    for (int i = 0; c && i < c->ndone; i++) {
        const wg_point *p = &c->pts[i];
        if (!p->checked)
            continue;
        n++;
        same += p->check_regime == p->regime && p->check_period == p->period &&
                p->check_motion == p->motion;
    }
    if (!n)
        return;
    fprintf(f, "- %s sweep: %d of %d attractors keep regime, period and motion class with 2N "
               "steps per period",
            dir, same, n);
    for (int i = 0; c && i < c->ndone; i++) {
        const wg_point *p = &c->pts[i];
        if (!p->checked || (p->check_regime == p->regime && p->check_period == p->period &&
                            p->check_motion == p->motion))
            continue;
        wg_point q = *p;
        q.regime = p->check_regime, q.period = p->check_period;
        char a[24], b[24];
        fprintf(f, "%s%.*f %s/%s -> %s/%s", shown++ ? "; " : "; differ: ", dg, p->value,
                out_label(p, a, sizeof a), wg_motion_name(p->motion), out_label(&q, b, sizeof b),
                wg_motion_name(p->check_motion));
    }
    fputs("\n", f);
}

/* The table and notes of one group. */
static void group_table(FILE *f, const sweep_study *st, const sweep_group *g)
{
    wg_transition *t = malloc(sizeof *t * STUDY_MAX_TRANS);
    if (!t)
        return;
    int n = wg_transitions(g->up ? g->up->pts : NULL, g->up ? g->up->ndone : 0,
                           g->down ? g->down->pts : NULL, g->down ? g->down->ndone : 0,
                           out_group_b(st, g), t,
                           STUDY_MAX_TRANS);
    const wg_chain *c = g->up ? g->up : g->down;
    double h = grid_step(c);
    int dg = decimals(h);
    const char *p = out_pname(st->param);
    const cont_bifs *ex = st->exact[g - st->g];
    fprintf(f, "| transition | up sweep: %s | down sweep: %s | detail |%s\n|---|---|---|---|%s\n",
            p, p, ex ? " exact (continuation) |" : "", ex ? "---|" : "");
    rows(f, t, n, fmax(4.0 * h, 0.01 * (c ? fabs(c->v1 - c->v0) : 0.0)), ex, dg);
    if (!n)
        fprintf(f, "| (none found) | - | - | - |%s\n", ex ? " - |" : "");
    fprintf(f, "\nLocations are brackets between neighbouring grid points (step %.4g); grazing "
               "is interpolated on min x_n = b.%s\n\n",
            h, ex ? " The exact column: the same events located on the orbits' branches by "
                    "wgcont (docs/analysis.md, \"From a sweep to exact points\")." : "");
    fputs("Routes into chaos (doublings since the last period-1):\n\n", f);
    cascades(f, t, n, +1, dg);
    cascades(f, t, n, -1, dg);
    fputs("\n", f);
    if ((g->up && g->up->ndone && g->up->pts[0].checked) ||
        (g->down && g->down->ndone && g->down->pts[0].checked)) {
        fputs("Step-halving check (each point's final state re-analysed with twice the steps "
              "per period):\n\n", f);
        halving(f, "up", g->up, dg);
        halving(f, "down", g->down, dg);
        fputs("\n", f);
    }
    if (g->up)
        route(f, g->up, dg);
    not_measured(f, "up", g->up, p, dg);
    not_measured(f, "down", g->down, p, dg);
    free(t);
}

/* Where the points came from: a CSV read back, or this run's settings. */
static void provenance(FILE *f, const sweep_study *st)
{
    const wg_sweep_opts *o = st->o;
    if (st->source) {
        fprintf(f, "Transitions recomputed from the points in `%s` (the run's settings are in "
                   "its JSON/Markdown).\n\n",
                st->source);
        return;
    }
    if (st->run) {
        fprintf(f, "Model %s, stepper %s, N = %d steps per mesh period, %s. Wall time %.1f s.\n\n",
                wg_model_name(o->model), wg_stepper_name(o->stepper), o->steps, st->run,
                st->wall_s);
        return;
    }
    char early[80] = "";
    if (o->settle > 0)
        snprintf(early, sizeof early, " (ending once settled over %d periods)", o->settle);
    char where[80] = "", chains[64] = "one chain at a time on each thread";
    if (st->pair > 1)
        snprintf(chains, sizeof chains, "up to %d chains at once on each thread", st->pair);
    if (st->ranks > 1)
        snprintf(where, sizeof where, " in each of %d MPI ranks", st->ranks);
    fprintf(f, "Model %s, stepper %s, N = %d steps per mesh period (raised where RK4 needs "
               "more), transient %d%s + record %d periods per point (up to %d extensions), LLE "
               "over %d periods (chaotic above %g per period), period tolerance max(%g, %g x "
               "one-period error). Wall time %.1f s on %d %s%s, %s.\n\n",
            wg_model_name(o->model), wg_stepper_name(o->stepper), o->steps, o->transient,
            early, o->record, o->extend, o->lle_periods, o->lle_tol, o->tol_floor, o->tol_factor,
            st->wall_s, st->threads, st->threads == 1 ? "thread" : "threads", where, chains);
}

int md_write(const char *path, const sweep_study *st, char *why, size_t whylen)
{
    FILE *f = out_open(path, why, whylen);
    if (!f)
        return -1;
    fprintf(f, "# Transitions: scene %s, sweep of %s%s\n\n", st->scene, out_pname(st->param),
            st->partial ? " (PARTIAL: interrupted)" : "");
    if (st->command)
        fprintf(f, "Command: `%s`\n\n", st->command);
    provenance(f, st);
    for (int k = 0; k < st->ngroups; k++) {
        if (st->gparam >= 0)
            fprintf(f, "## %s = %g\n\n", out_pname(st->gparam), st->g[k].gval);
        group_table(f, st, &st->g[k]);
    }
    return out_close(f, path, why, whylen);
}

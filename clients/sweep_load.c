/* sweep_load.c - read a points CSV written by out_points_csv back into a
 * study, so the transitions table can be recomputed without re-integrating
 * (wgsweep --table-from). Poincare values are not in that file: the loaded
 * points have nsec = 0. */
#include "sweep_load.h"
#include "cli.h"
#include "wormgear/wg_file.h"

#include <errno.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* The i in [0, n) whose name(i) is s, or -1: the library's names read back. */
static int lookup(const char *(*name)(int), int n, const char *s)
{
    for (int i = 0; i < n; i++)
        if (strcmp(name(i), s) == 0)
            return i;
    return -1;
}

/* Split a CSV line in place into at most max fields. */
static int split(char *line, char **f, int max)
{
    int n = 0;
    line[strcspn(line, "\r\n")] = 0;
    for (char *p = line; n < max;) {
        f[n++] = p;
        char *c = strchr(p, ',');
        if (!c)
            break;
        *c = 0;
        p = c + 1;
    }
    return n;
}

/* Column i (of out_point_cols) of a row, text t, into pt: 0, or -1 with
 * *need saying what wgsweep writes there. */
static int put(int i, const char *t, wg_point *pt, const char **need)
{
    double v = 0.0;
    int opt = i >= 12 && i < 18, empty = !*t; /* Floquet, 2N check: empty when not run */
    if (opt && empty)
        return 0;
    if (i == 0 || i == 3 || i == 15 || i == 17) {
        int reg = i == 0 || i == 15;
        int k = reg ? lookup(wg_regime_name, WG_REGIME_DIVERGED + 1, t)
                    : lookup(wg_motion_name, WG_MOTION_DOUBLE + 1, t);
        *need = reg ? "a regime name (periodic, quasiperiodic, chaotic, ...)"
                    : "a motion class (no_impact, single_sided, double_sided)";
        *(i == 0 ? &pt->regime : i == 3 ? &pt->motion : i == 15 ? &pt->check_regime
                                                                 : &pt->check_motion) = k;
        pt->checked |= i == 15;
        return k < 0 ? -1 : 0;
    }
    if (i == 1 || i == 16) {
        *need = "a whole number 0..32 (0: no period found)";
        return cli_csv_int(t, 0, WG_PERIOD_MAX, i == 1 ? &pt->period : &pt->check_period);
    }
    if (i == 2 || i == 11) {
        *need = i == 2 ? "0 or 1" : "a whole number 8..65536";
        return i == 2 ? cli_csv_int(t, 0, 1, &pt->converged)
                      : cli_csv_int(t, WG_STEPS_MIN, WG_STEPS_MAX, &pt->steps);
    }
    int ok = !cli_csv_num(t, &v);
    if (i == 7) { /* the LLE: nan where it was not run */
        *need = "a finite number, or nan (not computed)";
        ok = ok && !isinf(v);
    } else if (i == 10) { /* the period residual: inf where no lag was tried */
        *need = "a number >= 0 (inf: none tried)";
        ok = ok && v >= 0;
    } else {
        *need = i == 5 || i == 6 || i == 12 || i == 13 ? "a finite number" : "a finite number >= 0";
        ok = ok && isfinite(v) && (i == 5 || i == 6 || i == 12 || i == 13 || v >= 0);
    }
    if (opt)
        *need = i == 14 ? "a finite number >= 0, or empty (no Floquet multipliers)"
                        : "a finite number, or empty (no Floquet multipliers)";
    double *at[] = {&pt->impacts, &pt->min_xn, &pt->max_xn, &pt->lle, &pt->err, &pt->tol,
                    &pt->resid};
    if (i >= 4 && i <= 10)
        *at[i - 4] = v;
    else if (i >= 18 && i < 24)
        pt->bimpacts[i - 18] = v;
    else if (i >= 24)
        pt->bvmax[i - 24] = v;
    return ok ? 0 : -1;
}

/* The columns after PARAM of one row (ncol of them) into pt; -1 with why
 * (the column, its text, what wgsweep writes there) if one is not what
 * out_points_csv writes. */
static int parse_point(char **f, int ncol, wg_point *pt, char *why, size_t whylen)
{
    const char *need = "";
    memset(pt, 0, sizeof *pt);
    pt->value2 = NAN;
    if (ncol > 0 && (!strcmp(f[0], "none") || !strcmp(f[0], "diverged"))) {
        int blank = 1; /* not measured (wg_point_measured): every other column empty */
        for (int i = 1; i < ncol; i++)
            blank &= !f[i][0];
        if (blank) {
            pt->regime = !strcmp(f[0], "none") ? WG_REGIME_NONE : WG_REGIME_DIVERGED;
            pt->min_xn = pt->max_xn = pt->lle = NAN;
            return 0;
        }
    }
    for (int i = 0; i < ncol; i++)
        if (put(i, f[i], pt, &need)) {
            snprintf(why, whylen, "%s '%s' is not what wgsweep writes there: need %s",
                     out_point_cols[i], f[i], need);
            return -1;
        }
    for (int g = 12; g + 3 <= ncol && g <= 15; g += 3) /* Floquet, 2N check: 3 or none */
        if (!f[g][0] != !f[g + 1][0] || !f[g][0] != !f[g + 2][0]) {
            snprintf(why, whylen, "%s..%s: all three given or all three empty, as wgsweep "
                     "writes them", out_point_cols[g], out_point_cols[g + 2]);
            return -1;
        }
    if (!(pt->min_xn <= pt->max_xn)) {
        snprintf(why, whylen, "min_xn %s over max_xn %s: not what wgsweep writes", f[5], f[6]);
        return -1;
    }
    return 0;
}

/* The group of value gval (created on first use); NAN, a file without a
 * group column, is one group (NAN == NAN is false: every row of a plain
 * sweep's CSV was once a group of its own). */
static sweep_group *group_of(sweep_study *st, double gval)
{
    for (int k = 0; k < st->ngroups; k++)
        if (st->g[k].gval == gval || (isnan(gval) && isnan(st->g[k].gval)))
            return &st->g[k];
    if (st->ngroups == STUDY_MAX_GROUPS)
        return NULL;
    sweep_group *g = &st->g[st->ngroups++];
    g->gval = gval;
    return g;
}

/* Append pt to the group's chain of direction dir (grown as needed). */
static int append(sweep_group *g, int dir, const wg_point *pt)
{
    wg_chain **cp = dir > 0 ? &g->up : &g->down;
    if (!*cp) {
        *cp = calloc(1, sizeof **cp);
        if (!*cp)
            return -1;
        (*cp)->dir = dir;
        (*cp)->param2 = -1;
    }
    wg_chain *c = *cp;
    if (c->ndone == c->npts) {
        int cap = c->npts ? 2 * c->npts : 256;
        wg_point *np = realloc(c->pts, sizeof *np * (size_t)cap);
        if (!np)
            return -1;
        c->pts = np;
        c->npts = cap;
    }
    c->pts[c->ndone++] = *pt;
    return 0;
}

/* Chains read back: the grid ends from the data, complete as read. */
static void finish_chains(sweep_study *st)
{
    for (int k = 0; k < st->ngroups; k++) {
        wg_chain *cs[2] = {st->g[k].up, st->g[k].down};
        for (int j = 0; j < 2; j++) {
            wg_chain *c = cs[j];
            if (!c || !c->ndone)
                continue;
            c->npts = c->ndone;
            c->v0 = fmin(c->pts[0].value, c->pts[c->ndone - 1].value);
            c->v1 = fmax(c->pts[0].value, c->pts[c->ndone - 1].value);
        }
    }
}

/* Header: [group,]dir,index,PARAM, then out_point_cols or its first
 * NEED_COLS or more (older runs wrote fewer): the group column's offset
 * (0, 1), or -1. *nf: its field count, which every row must have. */
enum { NEED_COLS = 12 }; /* regime .. steps_per_period: what the table reads */
static int parse_header(char *line, sweep_study *st, int *nf)
{
    char *f[64];
    int n = *nf = split(line, f, 64);
    int off = n > 0 && strcmp(f[0], "dir") != 0;
    if (n < 3 + off + NEED_COLS || n > 3 + off + OUT_POINT_NCOLS || strcmp(f[off], "dir") ||
        strcmp(f[off + 1], "index"))
        return -1;
    for (int i = 0; i < n - 3 - off; i++)
        if (strcmp(f[off + 3 + i], out_point_cols[i]))
            return -1;
    st->gparam = off ? wg_param_lookup(f[0]) : -1;
    st->param = wg_param_lookup(f[2 + off]);
    if (off && st->gparam == st->param) /* --values of the swept parameter: wgsweep refuses it */
        return -1;
    return (off && st->gparam < 0) || st->param < 0 ? -1 : off;
}

/* The row's group value, direction, index and parameter value, checked
 * against what wgsweep writes (a finite group value in its parameter's
 * range; up or down; a direction's rows numbered 0, 1, 2, ... with values
 * strictly increasing up, decreasing down, in the parameter's range):
 * its chain's group in *gp, direction in *dir, or NULL with why. */
static sweep_group *row_place(sweep_study *st, char **f, int off, int *dir, double *v,
                              char *why, size_t whylen)
{
    char w[160];
    double gv = NAN;
    if (off && (cli_csv_num(f[0], &gv) ? snprintf(w, sizeof w, "not a number as wgsweep writes one")
                                       : wg_param_check(st->gparam, gv, w, sizeof w))) {
        snprintf(why, whylen, "group value '%s': need a finite value of %s in its range (%s)",
                 f[0], out_pname(st->gparam), w);
        return NULL;
    }
    if (strcmp(f[off], "up") && strcmp(f[off], "down")) {
        snprintf(why, whylen, "dir '%s': need up or down", f[off]);
        return NULL;
    }
    *dir = strcmp(f[off], "down") == 0 ? -1 : 1;
    sweep_group *g = group_of(st, gv);
    if (!g) {
        snprintf(why, whylen, "too many groups: at most %d values of %s (as --values takes)",
                 STUDY_MAX_GROUPS, out_pname(st->gparam));
        return NULL;
    }
    const wg_chain *c = *dir > 0 ? g->up : g->down;
    int k = c ? c->ndone : 0, idx;
    if (cli_csv_int(f[off + 1], 0, 1000000000, &idx) || idx != k) {
        snprintf(why, whylen, "index '%s': need %d (each direction's rows numbered 0, 1, 2, "
                 "... in the order wgsweep writes them)", f[off + 1], k);
        return NULL;
    }
    if (cli_csv_num(f[off + 2], v) ? snprintf(w, sizeof w, "not a number as wgsweep writes one")
                                   : wg_param_check(st->param, *v, w, sizeof w)) {
        snprintf(why, whylen, "%s '%s': need a finite value in its range (%s)",
                 out_pname(st->param), f[off + 2], w);
        return NULL;
    }
    double prev = k ? c->pts[k - 1].value : NAN;
    if (k && !(*dir > 0 ? *v > prev : *v < prev)) {
        snprintf(why, whylen, "%s %s after %.10g in the %s sweep: need values strictly %s, as "
                 "wgsweep writes them", out_pname(st->param), f[off + 2], prev,
                 *dir > 0 ? "up" : "down", *dir > 0 ? "increasing" : "decreasing");
        return NULL;
    }
    return g;
}

/* The file is verified as it is read: a header naming out_points_csv's
 * columns, rows of as many fields, each field what wgsweep writes there
 * (row_place, parse_point), every line whole, at least one row. A torn or
 * foreign file is refused with the line at fault (it once gave an empty
 * table and exit 0; nan groups, a grid out of order, omega = 1e308 and
 * garbage in the index or Floquet columns gave tables of nonsense). */
int load_points_csv(const char *path, sweep_study *st, char *why, size_t whylen)
{
    FILE *fp = wg_file_fopen(path, "points file", 0, -1, NULL, why, whylen);
    char line[4096], w[320];
    if (!fp)
        return -1;
    int nf = 0, lineno = 1, rc = 0, rows = 0;
    int got = cli_read_line(fp, line, sizeof line, path, 1, why, whylen);
    int off = got == 1 ? parse_header(line, st, &nf) : -1;
    if (got < 0) {
        rc = -1; /* why says it */
    } else if (off < 0) {
        snprintf(why, whylen, "%s:1: not a wgsweep points CSV header ([group,]dir,index,PARAM,"
                 "regime,period,... as wgsweep writes PREFIX.csv)", path);
        rc = -1;
    }
    while (!rc && (got = cli_read_line(fp, line, sizeof line, path, ++lineno, why, whylen))) {
        char *f[64];
        wg_point pt;
        rows++;
        if (got < 0) {
            rc = -1;
            break;
        }
        int dir, n = split(line, f, 64);
        double v;
        sweep_group *g = NULL;
        if (n != nf)
            snprintf(w, sizeof w, "%d fields, the header has %d", n, nf);
        else if ((g = row_place(st, f, off, &dir, &v, w, sizeof w)) &&
                 parse_point(f + off + 3, n - off - 3, &pt, w, sizeof w) == 0) {
            pt.value = v;
            if (append(g, dir, &pt) == 0)
                continue;
            snprintf(why, whylen, "%s:%d: out of memory", path, lineno);
            rc = -2; /* not the file's fault */
            break;
        }
        snprintf(why, whylen, "%s:%d: %s", path, lineno, w);
        rc = -1;
    }
    if (!rc && !rows) {
        snprintf(why, whylen, "%s: no points after the header", path);
        rc = -1;
    }
    fclose(fp);
    finish_chains(st);
    return rc;
}

int load_exact(const char *const *paths, int n, sweep_study *st, cont_bifs *ex, char *why,
               size_t whylen)
{
    const char *pname = out_pname(st->param);
    char w[512];
    if (n && n != st->ngroups) {
        snprintf(why, whylen, "--exact: %d file(s) for %d group(s): give one per group", n,
                 st->ngroups);
        return -1;
    }
    for (int k = 0; k < n; k++) {
        int bad = cont_read_bifs(paths[k], &ex[k], w, sizeof w);
        if (bad)
            snprintf(why, whylen, "--exact: %s", w);
        else if ((bad = strcmp(ex[k].param, pname) != 0))
            snprintf(why, whylen, "--exact %s: continued in %s, the sweep is in %s", paths[k],
                     ex[k].param, pname);
        if (bad) {
            load_exact_free(ex, k + 1);
            return -1;
        }
        st->exact[k] = &ex[k];
    }
    return 0;
}

void load_exact_free(cont_bifs *ex, int n)
{
    for (int k = 0; k < n; k++)
        cont_bifs_free(&ex[k]);
}

void load_free(sweep_study *st)
{
    for (int k = 0; k < st->ngroups; k++) {
        wg_chain *cs[2] = {st->g[k].up, st->g[k].down};
        for (int j = 0; j < 2; j++)
            if (cs[j]) {
                free(cs[j]->pts);
                free(cs[j]);
            }
    }
    st->ngroups = 0;
}

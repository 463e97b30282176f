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

/* f as a whole number (nan, inf included), or -1. */
static int fnum(const char *f, double *v)
{
    char *end;
    *v = strtod(f, &end);
    return end == f || *end ? -1 : 0;
}

static int fint(const char *f, int *v)
{
    double x;
    if (fnum(f, &x) || !(x == floor(x)) || fabs(x) > 1e9)
        return -1;
    *v = (int)x;
    return 0;
}

/* One data row (fields after the optional group column) into pt; -1 if a
 * field the table needs is not what out_points_csv writes there. */
static int parse_point(char **f, int n, wg_point *pt, int *dir)
{
    if (n < 15 || (strcmp(f[0], "up") && strcmp(f[0], "down")))
        return -1;
    memset(pt, 0, sizeof *pt);
    *dir = strcmp(f[0], "down") == 0 ? -1 : 1;
    double *num[9] = {&pt->value, &pt->impacts, &pt->min_xn, &pt->max_xn, &pt->lle,
                      &pt->err, &pt->tol, &pt->resid, NULL};
    static const int at[8] = {2, 7, 8, 9, 10, 11, 12, 13};
    for (int i = 0; num[i]; i++)
        if (fnum(f[at[i]], num[i]))
            return -1;
    if (fint(f[4], &pt->period) || fint(f[5], &pt->converged) || fint(f[14], &pt->steps) ||
        !isfinite(pt->value))
        return -1;
    pt->regime = lookup(wg_regime_name, WG_REGIME_DIVERGED + 1, f[3]);
    pt->motion = lookup(wg_motion_name, WG_MOTION_DOUBLE + 1, f[6]);
    pt->value2 = NAN;
    if (n >= 21 && f[18][0]) { /* the 2N check, when the run had --verify-steps */
        pt->checked = 1;
        pt->check_regime = lookup(wg_regime_name, WG_REGIME_DIVERGED + 1, f[18]);
        pt->check_motion = lookup(wg_motion_name, WG_MOTION_DOUBLE + 1, f[20]);
        if (fint(f[19], &pt->check_period) || pt->check_regime < 0 || pt->check_motion < 0)
            return -1;
    }
    /* what a run can write: a period up to WG_PERIOD_MAX (0: none), N in
     * the stepper's range, min_xn <= max_xn (P-7 and N = -3 were tabled) */
    if (pt->period < 0 || pt->period > WG_PERIOD_MAX || pt->converged < 0 || pt->converged > 1 ||
        pt->steps < WG_STEPS_MIN || pt->steps > WG_STEPS_MAX || pt->min_xn > pt->max_xn ||
        !(pt->impacts >= 0 || isnan(pt->impacts)) ||
        (pt->checked && (pt->check_period < 0 || pt->check_period > WG_PERIOD_MAX)))
        return -1;
    return pt->regime < 0 || pt->motion < 0 ? -1 : 0;
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

/* The columns after PARAM that the table reads, as out_points_csv names
 * them (later columns may follow). */
static const char *const COLS[] = {"regime", "period", "converged", "motion",
                                   "impacts_per_period", "min_xn", "max_xn", "lle_per_period",
                                   "err", "tol", "resid", "steps_per_period"};
enum { NCOLS = sizeof COLS / sizeof COLS[0] };

/* Header: [group,]dir,index,PARAM,regime,...: the group column's offset
 * (0, 1), or -1. *nf: its field count, which every row must have. */
static int parse_header(char *line, sweep_study *st, int *nf)
{
    char *f[64];
    int n = *nf = split(line, f, 64);
    int off = n > 0 && strcmp(f[0], "dir") != 0;
    if (n < 3 + off + NCOLS || strcmp(f[off], "dir") || strcmp(f[off + 1], "index"))
        return -1;
    for (int i = 0; i < NCOLS; i++)
        if (strcmp(f[off + 3 + i], COLS[i]))
            return -1;
    st->gparam = off ? wg_param_lookup(f[0]) : -1;
    st->param = wg_param_lookup(f[2 + off]);
    return (off && st->gparam < 0) || st->param < 0 ? -1 : off;
}

/* The file is verified as it is read: a header naming out_points_csv's
 * columns, rows of as many fields, each field the table uses a number or
 * a name it knows, every line whole, at least one row. A torn or foreign
 * file is refused with the line at fault (it once gave an empty table and
 * exit 0). */
int load_points_csv(const char *path, sweep_study *st, char *why, size_t whylen)
{
    FILE *fp = wg_file_fopen(path, "points file", 0, -1, NULL, why, whylen);
    char line[4096];
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
        double gv = NAN;
        if (n != nf || (off && fnum(f[0], &gv))) {
            snprintf(why, whylen, "%s:%d: %d fields, the header has %d", path, lineno, n, nf);
            rc = -1;
            break;
        }
        sweep_group *g = group_of(st, gv);
        if (!g || parse_point(f + off, n - off, &pt, &dir) || append(g, dir, &pt)) {
            snprintf(why, whylen, "%s:%d: %s", path, lineno,
                     g ? "a field is not what wgsweep writes there (a number, a regime or a "
                         "motion name)"
                       : "too many groups");
            rc = -1;
        }
    }
    if (!rc && !rows) {
        snprintf(why, whylen, "%s: no points after the header", path);
        rc = -1;
    }
    fclose(fp);
    finish_chains(st);
    return rc;
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

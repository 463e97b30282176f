/* sweep_load.c - read a points CSV written by out_points_csv back into a
 * study, so the transitions table can be recomputed without re-integrating
 * (wgsweep --table-from). Poincare values are not in that file: the loaded
 * points have nsec = 0. */
#include "sweep_load.h"

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

/* One data row (fields after the optional group column) into pt. */
static int parse_point(char **f, int n, wg_point *pt, int *dir)
{
    if (n < 15)
        return -1;
    memset(pt, 0, sizeof *pt);
    *dir = strcmp(f[0], "down") == 0 ? -1 : 1;
    pt->value = strtod(f[2], NULL);
    pt->regime = lookup(wg_regime_name, WG_REGIME_DIVERGED + 1, f[3]);
    pt->period = atoi(f[4]);
    pt->converged = atoi(f[5]);
    pt->motion = lookup(wg_motion_name, WG_MOTION_DOUBLE + 1, f[6]);
    pt->impacts = strtod(f[7], NULL);
    pt->min_xn = strtod(f[8], NULL);
    pt->max_xn = strtod(f[9], NULL);
    pt->lle = strtod(f[10], NULL);
    pt->err = strtod(f[11], NULL);
    pt->tol = strtod(f[12], NULL);
    pt->resid = strtod(f[13], NULL);
    pt->steps = atoi(f[14]);
    pt->value2 = NAN;
    if (n >= 21 && f[18][0]) { /* the 2N check, when the run had --verify-steps */
        pt->checked = 1;
        pt->check_regime = lookup(wg_regime_name, WG_REGIME_DIVERGED + 1, f[18]);
        pt->check_period = atoi(f[19]);
        pt->check_motion = lookup(wg_motion_name, WG_MOTION_DOUBLE + 1, f[20]);
    }
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

/* Header: [group,]dir,index,PARAM,... */
static int parse_header(char *line, sweep_study *st)
{
    char *f[32];
    int n = split(line, f, 32);
    int off = n > 0 && strcmp(f[0], "dir") != 0;
    if (n < 4 + off)
        return -1;
    st->gparam = off ? wg_param_lookup(f[0]) : -1;
    st->param = wg_param_lookup(f[2 + off]);
    return (off && st->gparam < 0) || st->param < 0 ? -1 : off;
}

int load_points_csv(const char *path, sweep_study *st, char *why, size_t whylen)
{
    FILE *fp = fopen(path, "r");
    char line[2048];
    if (!fp) {
        snprintf(why, whylen, "cannot read %s", path);
        return -1;
    }
    int off = fgets(line, sizeof line, fp) ? parse_header(line, st) : -1, lineno = 1, rc = 0;
    if (off < 0) {
        snprintf(why, whylen, "%s:1: not a wgsweep points CSV header", path);
        rc = -1;
    }
    while (!rc && fgets(line, sizeof line, fp)) {
        char *f[32];
        wg_point pt;
        int dir, n = split(line, f, 32);
        lineno++;
        sweep_group *g = n > off ? group_of(st, off ? strtod(f[0], NULL) : NAN) : NULL;
        if (!g || parse_point(f + off, n - off, &pt, &dir) || append(g, dir, &pt)) {
            snprintf(why, whylen, "%s:%d: malformed row (or too many groups)", path, lineno);
            rc = -1;
        }
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

/* cont_out.c - the files of a continuation run (see cont_out.h). */
#include "cont_out.h"
#include "cli.h"
#include "wormgear/wg_file.h"
#include "wormgear/wg_scene.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int cont_add_point(cont_result *r, const wg_cont_point *p)
{
    if (r->npt == r->ptcap) {
        int cap = r->ptcap ? 2 * r->ptcap : 256;
        wg_cont_point *q = realloc(r->pt, sizeof *q * (size_t)cap);
        if (!q)
            return -1;
        r->pt = q;
        r->ptcap = cap;
    }
    r->pt[r->npt++] = *p;
    return 0;
}

int cont_add_bif(cont_result *r, const wg_bif *b)
{
    if (r->nbif == r->bifcap) {
        int cap = r->bifcap ? 2 * r->bifcap : 64;
        wg_bif *q = realloc(r->bif, sizeof *q * (size_t)cap);
        if (!q)
            return -1;
        r->bif = q;
        r->bifcap = cap;
    }
    r->bif[r->nbif++] = *b;
    return 0;
}

void cont_result_free(cont_result *r)
{
    free(r->pt);
    free(r->bif);
    memset(r, 0, sizeof *r);
}

static FILE *open_w(const char *path, char *why, size_t whylen)
{
    FILE *f = fopen(path, "w");
    if (!f)
        snprintf(why, whylen, "cannot write %s", path);
    return f;
}

static int close_w(FILE *f, const char *path, char *why, size_t whylen)
{
    int bad = ferror(f);
    if (fclose(f) || bad) {
        snprintf(why, whylen, "error writing %s", path);
        return -1;
    }
    return 0;
}

static void state_header(FILE *f, int nstate)
{
    int model = nstate == wg_model_nstate(WG_MODEL_PRINTED) ? WG_MODEL_PRINTED : WG_MODEL_CONSISTENT;
    for (int j = 0; j < nstate && j < WG_NSTATE_MAX; j++)
        fprintf(f, ",%s", wg_state_name(model, j));
}

static void state_row(FILE *f, const double *y, int nstate)
{
    for (int j = 0; j < nstate; j++)
        fprintf(f, ",%.17g", y[j]);
}

int cont_write_branch(const char *path, const cont_result *r, int param, int nstate, char *why,
                      size_t whylen)
{
    FILE *f = open_w(path, why, whylen);
    if (!f)
        return -1;
    fprintf(f, "branch,index,%s,period,stable", wg_param_info_get(param)->name);
    state_header(f, nstate);
    fputs(",min_xn,max_xn,mu1_abs,mu1_arg,mu2_abs,mu2_arg,mu3_abs,mu3_arg,mesh_crossings,"
          "newton_its,residual\n", f);
    for (int i = 0; i < r->npt; i++) {
        const wg_cont_point *p = &r->pt[i];
        fprintf(f, "%d,%d,%.17g,%d,%d", p->branch, p->index, p->value, p->period, p->stable);
        state_row(f, p->y, nstate);
        fprintf(f, ",%.17g,%.17g", p->qmin[WG_C_MESH], p->qmax[WG_C_MESH]);
        for (int k = 0; k < 3; k++)
            if (k < p->nmult)
                fprintf(f, ",%.10g,%.10g", hypot(p->mre[k], p->mim[k]), atan2(p->mim[k], p->mre[k]));
            else
                fputs(",,", f);
        fprintf(f, ",%d,%d,%.3g\n", p->ncross[WG_C_MESH], p->newton_its, p->resid);
    }
    return close_w(f, path, why, whylen);
}

int cont_write_bifs(const char *path, const cont_result *r, int param, int nstate, char *why,
                    size_t whylen)
{
    FILE *f = open_w(path, why, whylen);
    if (!f)
        return -1;
    fprintf(f, "type,%s", wg_param_info_get(param)->name);
    state_header(f, nstate);
    fputs(",mu_re,mu_im,mu_abs,mu_arg,period,branch,contact,threshold,extreme,bracket\n", f);
    for (int i = 0; i < r->nbif; i++) {
        const wg_bif *b = &r->bif[i];
        int g = b->kind == WG_BIF_GRAZING;
        fprintf(f, "%s,%.17g", wg_bif_name(b->kind), b->value);
        state_row(f, b->y, nstate);
        fprintf(f, ",%.10g,%.10g,%.10g,%.10g,%d,%d,%s,%s,%s,%.3g\n", b->mu_re, b->mu_im,
                hypot(b->mu_re, b->mu_im), atan2(b->mu_im, b->mu_re), b->period, b->branch,
                g ? wg_contact_name(b->contact) : "-", g ? (b->side > 0 ? "+c" : "-c") : "-",
                g ? (b->extreme < 0 ? "min" : "max") : "-", b->bracket);
    }
    return close_w(f, path, why, whylen);
}

int cont_kind_lookup(const char *name)
{
    for (int k = 0; k < WG_NBIF; k++)
        if (strcmp(name, wg_bif_name(k)) == 0)
            return k;
    return -1;
}

/* Split a CSV line in place into at most max fields. */
static int split(char *line, char **fld, int max)
{
    int n = 0;
    line[strcspn(line, "\r\n")] = 0;
    for (char *p = line; n < max;) {
        fld[n++] = p;
        char *c = strchr(p, ',');
        if (!c)
            break;
        *c = 0;
        p = c + 1;
    }
    return n;
}

static int column(char **fld, int n, const char *name)
{
    for (int i = 0; i < n; i++)
        if (strcmp(fld[i], name) == 0)
            return i;
    return -1;
}

static int contact_lookup(const char *s)
{
    for (int j = 0; j < WG_NCONTACT; j++)
        if (strcmp(s, wg_contact_name(j)) == 0)
            return j;
    return -1;
}

enum { NCOL = 64 };

/* Columns of the header: type, the parameter, period, branch, contact,
 * threshold, extreme, bracket. */
static int header(char *line, cont_bifs *b, int *col)
{
    static const char *const names[] = {"period", "branch", "contact", "threshold", "extreme",
                                        "bracket"};
    char *fld[NCOL];
    int n = split(line, fld, NCOL);
    if (n < 2 || strcmp(fld[0], "type") != 0)
        return -1;
    snprintf(b->param, sizeof b->param, "%s", fld[1]);
    for (int k = 0; k < 6; k++)
        if ((col[k] = column(fld, n, names[k])) < 0)
            return -1;
    return 0;
}

static int row(char *line, const int *col, cont_row *r)
{
    char *fld[NCOL], *end;
    int n = split(line, fld, NCOL);
    for (int k = 0; k < 6; k++)
        if (col[k] >= n)
            return -1;
    r->kind = cont_kind_lookup(fld[0]);
    r->value = strtod(fld[1], &end);
    if (r->kind < 0 || *end || !isfinite(r->value))
        return -1;
    /* every field as wgcont writes it: a period 1..WG_SHOOT_NMAX; a grazing's
     * contact, side (+c, -c) and extreme (min, max), '-' for the others; a
     * bracket >= 0 (GARBAGE,zz,nowhere and a period of -99999999999 were
     * tabled: atoi and strcmp took anything) */
    long period = strtol(fld[col[0]], &end, 10);
    if (*end || end == fld[col[0]] || period < 1 || period > WG_SHOOT_NMAX)
        return -1;
    r->period = (int)period;
    int graze = r->kind == WG_BIF_GRAZING;
    r->contact = graze ? contact_lookup(fld[col[2]]) : -1;
    r->side = strcmp(fld[col[3]], "-c") == 0 ? -1 : 1;
    r->extreme = strcmp(fld[col[4]], "max") == 0 ? 1 : -1;
    if (graze ? r->contact < 0 || (strcmp(fld[col[3]], "+c") && strcmp(fld[col[3]], "-c")) ||
                    (strcmp(fld[col[4]], "min") && strcmp(fld[col[4]], "max"))
              : strcmp(fld[col[2]], "-") || strcmp(fld[col[3]], "-") || strcmp(fld[col[4]], "-"))
        return -1;
    r->bracket = strtod(fld[col[5]], &end);
    return *end || end == fld[col[5]] || !(r->bracket >= 0 && isfinite(r->bracket)) ? -1 : 0;
}

int cont_read_bifs(const char *path, cont_bifs *b, char *why, size_t whylen)
{
    memset(b, 0, sizeof *b);
    FILE *f = wg_file_fopen(path, "bifurcations file", 0, -1, NULL, why, whylen);
    if (!f)
        return -1;
    char line[4096];
    int col[6], cap = 0, rc = 0, lno = 1;
    int got = cli_read_line(f, line, sizeof line, path, 1, why, whylen);
    if (got < 0) {
        rc = -1; /* why says it */
    } else if (!got || header(line, b, col)) {
        snprintf(why, whylen, "%s: not a bifurcations CSV of wgcont (header type,PARAM,...)",
                 path);
        rc = -1;
    }
    while (!rc && (got = cli_read_line(f, line, sizeof line, path, ++lno, why, whylen))) {
        if (got < 0) { /* "period_doubling,1.19" of 1.1976546 read as 1.19 */
            rc = -1;
            break;
        }
        if (b->n == cap) {
            cap = cap ? 2 * cap : 64;
            cont_row *q = realloc(b->row, sizeof *q * (size_t)cap);
            if (!q) {
                snprintf(why, whylen, "out of memory reading %s", path);
                rc = -1;
                break;
            }
            b->row = q;
        }
        if (row(line, col, &b->row[b->n]) == 0)
            b->n++;
        else {
            snprintf(why, whylen, "%s:%d: not a bifurcation row", path, lno);
            rc = -1;
        }
    }
    fclose(f);
    if (rc)
        cont_bifs_free(b);
    return rc;
}

void cont_bifs_free(cont_bifs *b)
{
    free(b->row);
    b->row = NULL;
    b->n = 0;
}

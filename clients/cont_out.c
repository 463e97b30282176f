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

/* The columns after the state, as cont_write_bifs writes them. */
static const char *const BIF_COLS[] = {"mu_re", "mu_im", "mu_abs", "mu_arg", "period", "branch",
                                       "contact", "threshold", "extreme", "bracket"};
enum { NBIF_COLS = sizeof BIF_COLS / sizeof BIF_COLS[0] };

/* The header of a bifurcations CSV (its type,PARAM,state...,bracket line,
 * no newline) into buf: the writer's, and what the reader asks for. */
static void bifs_header(char *buf, size_t len, const char *pname, int nstate)
{
    int model = nstate == wg_model_nstate(WG_MODEL_PRINTED) ? WG_MODEL_PRINTED
                                                             : WG_MODEL_CONSISTENT;
    size_t n = (size_t)snprintf(buf, len, "type,%s", pname);
    for (int j = 0; j < nstate && j < WG_NSTATE_MAX && n < len; j++)
        n += (size_t)snprintf(buf + n, len - n, ",%s", wg_state_name(model, j));
    for (int k = 0; k < NBIF_COLS && n < len; k++)
        n += (size_t)snprintf(buf + n, len - n, ",%s", BIF_COLS[k]);
}

int cont_write_bifs(const char *path, const cont_result *r, int param, int nstate, char *why,
                    size_t whylen)
{
    FILE *f = open_w(path, why, whylen);
    if (!f)
        return -1;
    char hdr[1024];
    bifs_header(hdr, sizeof hdr, wg_param_info_get(param)->name, nstate);
    fprintf(f, "%s\n", hdr);
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

static int contact_lookup(const char *s)
{
    for (int j = 0; j < WG_NCONTACT; j++)
        if (strcmp(s, wg_contact_name(j)) == 0)
            return j;
    return -1;
}

enum { NCOL = 64 };

/* The header, exactly what cont_write_bifs writes for the continued
 * parameter it names and the consistent model's state (the only model
 * wgcont continues); a duplicated or missing column, a foreign parameter
 * are refused. The state's width into *ns, or -1. */
static int header(char *line, cont_bifs *b, int *ns)
{
    char want[1024], *comma = strchr(line, ',');
    line[strcspn(line, "\r\n")] = 0;
    if (!comma || strncmp(line, "type,", 5))
        return -1;
    char *end = strchr(comma + 1, ',');
    snprintf(b->param, sizeof b->param, "%.*s", end ? (int)(end - comma - 1) : 0, comma + 1);
    *ns = wg_model_nstate(WG_MODEL_CONSISTENT);
    bifs_header(want, sizeof want, b->param, *ns);
    return wg_param_lookup(b->param) >= 0 && strcmp(line, want) == 0 ? 0 : -1;
}

/* A number field as printf writes it, finite (and >= 0 if nonneg). */
static int fin(const char *t, int nonneg, double *v)
{
    return cli_csv_num(t, v) || !isfinite(*v) || (nonneg && *v < 0) ? -1 : 0;
}

/* One row, every field as wgcont writes it: a kind's name; the value in
 * the parameter's range; the state and the multiplier finite numbers
 * (its modulus >= 0); a period 1..WG_SHOOT_NMAX and a branch >= 0 as %d
 * writes them (" 1", "+1" were taken); a grazing's contact, side (+c, -c)
 * and extreme (min, max), '-' for the others; a bracket >= 0. -1 with
 * what (the column at fault) otherwise. */
static int row(char *line, int ns, const cont_bifs *b, cont_row *r, const char **what)
{
    char *fld[NCOL];
    double v;
    int n = split(line, fld, NCOL), c = 2 + ns, branch;
    *what = "as many fields as the header";
    if (n != c + NBIF_COLS)
        return -1;
    *what = "a type: fold, period_doubling, torus, grazing or branch_point";
    if ((r->kind = cont_kind_lookup(fld[0])) < 0)
        return -1;
    *what = "the parameter's value, finite and in its range";
    if (fin(fld[1], 0, &r->value) ||
        wg_param_check(wg_param_lookup(b->param), r->value, NULL, 0))
        return -1;
    for (int j = 2; j < c + 4; j++) {
        *what = j < c ? "the state: finite numbers"
                      : "mu_re .. mu_arg: finite numbers, mu_abs >= 0";
        if (fin(fld[j], j == c + 2, &v))
            return -1;
    }
    *what = "a period 1..32 as %d writes it";
    if (cli_csv_int(fld[c + 4], 1, WG_SHOOT_NMAX, &r->period))
        return -1;
    *what = "a branch number >= 0 as %d writes it";
    if (cli_csv_int(fld[c + 5], 0, 1000000000, &branch))
        return -1;
    int graze = r->kind == WG_BIF_GRAZING;
    const char *con = fld[c + 6], *th = fld[c + 7], *ex = fld[c + 8];
    r->contact = graze ? contact_lookup(con) : -1;
    r->side = strcmp(th, "-c") == 0 ? -1 : 1;
    r->extreme = strcmp(ex, "max") == 0 ? 1 : -1;
    *what = "a grazing's contact, +c or -c, min or max; - - - for the others";
    if (graze ? r->contact < 0 || (strcmp(th, "+c") && strcmp(th, "-c")) ||
                    (strcmp(ex, "min") && strcmp(ex, "max"))
              : strcmp(con, "-") || strcmp(th, "-") || strcmp(ex, "-"))
        return -1;
    *what = "a bracket: a finite number >= 0";
    return fin(fld[c + 9], 1, &r->bracket);
}

int cont_read_bifs(const char *path, cont_bifs *b, char *why, size_t whylen)
{
    memset(b, 0, sizeof *b);
    FILE *f = wg_file_fopen(path, "bifurcations file", 0, -1, NULL, why, whylen);
    if (!f)
        return -1;
    char line[4096];
    const char *what = "";
    int ns = 0, cap = 0, rc = 0, lno = 1;
    int got = cli_read_line(f, line, sizeof line, path, 1, why, whylen);
    if (got < 0) {
        rc = -1; /* why says it */
    } else if (!got || header(line, b, &ns)) {
        snprintf(why, whylen, "%s:1: not a bifurcations CSV header of wgcont (type,PARAM, the "
                 "state's columns, mu_re, ..., bracket, each once, as wgcont writes "
                 "PREFIX-bifurcations.csv)", path);
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
        if (row(line, ns, b, &b->row[b->n], &what) == 0)
            b->n++;
        else {
            snprintf(why, whylen, "%s:%d: not a bifurcation row as wgcont writes it (need %s)",
                     path, lno, what);
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

/* cont_out.h - a continuation run in memory and its files: PREFIX-branch.csv
 * and PREFIX-bifurcations.csv, written by wgcont; the bifurcations read back
 * by wgsweep --exact for the "exact (continuation)" column of its table.
 * Writers and readers return 0, or -1 with a message in why. */
#ifndef WG_CONT_OUT_H
#define WG_CONT_OUT_H

#include <stddef.h>
#include "wormgear/wg_cont.h"

/* What wgcont collected (growable arrays). */
typedef struct cont_result {
    wg_cont_point *pt;
    int npt, ptcap;
    wg_bif *bif;
    int nbif, bifcap;
    int newton_fails;    /* Newton failures reported (each halved the step) */
} cont_result;

/* A bifurcation as read back from PREFIX-bifurcations.csv. */
typedef struct cont_row {
    int kind;            /* enum wg_bif_kind */
    double value;
    int period, contact, side, extreme;
    double bracket;
} cont_row;

typedef struct cont_bifs {
    char param[32];      /* the continued parameter (the CSV's second column) */
    cont_row *row;
    int n;
} cont_bifs;

/* Append a point or a bifurcation: 0, or -1 when out of memory. */
int cont_add_point(cont_result *r, const wg_cont_point *p);
int cont_add_bif(cont_result *r, const wg_bif *b);

void cont_result_free(cont_result *r);

/* One row per point: branch, index, the parameter, period, stable, the
 * Poincare state, min/max x_n, the three largest multipliers' moduli and
 * arguments, mesh crossings per orbit, Newton iterations and residual. */
int cont_write_branch(const char *path, const cont_result *r, int param, int nstate, char *why,
                      size_t whylen);

/* One row per bifurcation: type, the parameter, the state, the multiplier
 * that crossed (re, im, modulus, argument), period, branch, contact,
 * threshold, extreme, location bracket. */
int cont_write_bifs(const char *path, const cont_result *r, int param, int nstate, char *why,
                    size_t whylen);

/* Read the type, parameter, period, branch and grazing columns back. */
int cont_read_bifs(const char *path, cont_bifs *b, char *why, size_t whylen);

void cont_bifs_free(cont_bifs *b);

/* Kind from its CSV name ("fold", "period_doubling" ...), or -1. */
int cont_kind_lookup(const char *name);

#endif

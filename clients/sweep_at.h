/* sweep_at.h - single-point views (wgsweep --at): regime, Lyapunov exponent,
 * Floquet multipliers of the refined orbit, and PNG/CSV of the phase
 * portrait, Poincare map and time trace. */
#ifndef WG_SWEEP_AT_H
#define WG_SWEEP_AT_H

#include <stdio.h>
#include "wormgear/wg_sweep.h"

typedef struct at_opts {
    const char *prefix;  /* output files prefix-at-V-*.png/.csv */
    const char *pname;   /* parameter name, for titles */
    double value;        /* its value at the point */
    int periods;         /* Poincare map periods */
    int trace_periods;   /* periods in the phase portrait and time trace */
    int png;             /* write PNGs */
} at_opts;

/* Analyse parameters p (the point value already set) from state y, print a
 * summary to out and write the views. 0 ok, 1 runtime error (message on
 * stderr). */
int at_view(const wg_params *p, const double *y, const wg_sweep_opts *o, const at_opts *ao,
            FILE *out);

#endif

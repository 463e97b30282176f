/* sweep_at.h - single-point views (wgsweep --at): regime, Lyapunov exponent,
 * Floquet multipliers of the refined orbit, and the phase portrait,
 * Poincare map (both with regime and Lyapunov exponent) and time trace
 * (physical time, mesh-period ticks) as figures (PNG, SVG or PDF) and a
 * CSV. */
#ifndef WG_SWEEP_AT_H
#define WG_SWEEP_AT_H

#include <stdio.h>
#include "units.h"
#include "wormgear/wg_sweep.h"

typedef struct at_opts {
    const char *prefix;  /* output files prefix-at-V-*.png/.csv */
    const char *pname;   /* parameter name, for titles */
    double value;        /* its value at the point */
    int periods;         /* Poincare map periods */
    int trace_periods;   /* periods in the phase portrait and time trace */
    int png;             /* write the figures */
    const char *format;  /* figures: "png" (NULL too), "svg" or "pdf" */
    const char *scene;   /* its name, for the captions */
    const wg_params *scene_p; /* the scene's own values (NULL: no "set away" line) */
    units_scale us;      /* the scene's scale: ms, µm, m/s on the figures */
} at_opts;

/* The state to start --at from, out of a snapshot file (format 2, as the
 * daemon's `save` writes: include/wormgear/wg_snapshot.h): read only if it is
 * a regular file of at most WG_SNAPSHOT_MAX bytes, verified (checksum) and
 * restored as the daemon would, taken in scene `scene` with model `model`,
 * then run with its own parameters, stepper and N to the next Poincare
 * section (psi = 0), where *p and y (WG_NSTATE_MAX) are taken. 0, or 1 with
 * why naming the file and what is wrong (never quoting it). */
int at_state_load(const char *path, const char *scene, int model, wg_params *p, double *y,
                  char *why, size_t whylen);

/* Analyse parameters p (the point value already set) from state y, print a
 * summary to out and write the views. 0 ok, 1 runtime error (message on
 * stderr). */
int at_view(const wg_params *p, const double *y, const wg_sweep_opts *o, const at_opts *ao,
            FILE *out);

#endif

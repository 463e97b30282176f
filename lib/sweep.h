/* sweep.h - what a sweep's chains (wg_chains.c) take from its point
 * analysis (wg_sweep.c): the workspace a chain keeps, one point's analysis
 * and its step-halving check. Private to the library. */
#ifndef WG_SWEEP_PRIV_H
#define WG_SWEEP_PRIV_H

#include "duo.h"
#include "wormgear/wg_sweep.h"

#include <signal.h>
#include <stddef.h>

/* Workspace of one chain: the main sim, its twin (LLE) and a 2N sim for the
 * integration error, each (re)initialised when N changes. */
typedef struct work {
    const wg_sweep_opts *o;
    wg_sim sim, twin, fine;
    int n_sim, n_twin, n_fine; /* N each was built with (0: not built) */
    int nstate;
    double *rec;               /* cap x nstate Poincare states */
    wg_period *stats;          /* their period statistics */
    int cap;                   /* rows: the record, or the transient's window */
    int nrec;                  /* sections stored by the current recording */
    wg_params hkey;            /* parameters hmax was found for */
    double hmax;               /* RK4 limit (wg_params_same_linear decides reuse) */
    int hvalid;
    int cut;                   /* the last transient ended early (o->settle) */
    volatile sig_atomic_t *stop;
    duo *duo;                  /* non-NULL: the sims' runs go through it */
} work;

/* A workspace for options o (stop: checked between a point's stages; d:
 * the main, twin and fine sims' runs go through it, or NULL); WG_ENOMEM if its record
 * buffer cannot be had. */
int sweep_work_init(work *w, const wg_sweep_opts *o, volatile sig_atomic_t *stop, duo *d);
void sweep_work_fini(work *w);

/* The analysis of one point at parameters p from state y (updated to the
 * final state) into pt; a status, with why for a failure. */
int sweep_point_analyse(work *w, const wg_params *p, double *y, wg_point *pt, char *why,
                        size_t whylen);

/* Step-halving check: analyse the attractor reached (state y) again in v
 * (a workspace with 2N steps per period) and store that classification in
 * pt (pt->checked; left 0 if it fails). */
void sweep_verify_point(work *v, const wg_params *p, const double *y, wg_point *pt);

/* wg_chains_run, and how many times a chain was taken up by another thread
 * between two of its points (*moves; tests see the hand-offs happen). */
int chains_run(wg_chain *cs, int n, const wg_sweep_opts *o, int threads,
               volatile sig_atomic_t *stop, wg_progress_fn progress, void *ctx, int *moves);

#endif

/* rig_ana.h - the regime analysis of one live sweep point (wgrig): the
 * offline sweep's own steps (wg_record_* in wg_sweep.h: statistics, the
 * one-period integration error |P_2N(x) - P_N(x)| on a local sim, tolerance
 * max(floor, factor * err), period detection, and for orbits with no period
 * the twin-trajectory Lyapunov exponent with the same thresholds). Only the
 * sections come from the daemon (rig_rec.h) instead of a local integration;
 * this file holds the local sims. */
#ifndef WG_RIG_ANA_H
#define WG_RIG_ANA_H

#include <stddef.h>
#include "rig_rec.h"
#include "wormgear/wg_sweep.h"

/* Local sims of the model the daemon runs (from PARAMS). */
typedef struct rig_ana {
    wg_params p;
    int model, stepper, steps;
    const wg_sweep_opts *o;
    wg_sim fine, base, twin;
    int have_fine, have_lle;
} rig_ana;

/* Analysis of parameters p (the point's value set) with the daemon's model,
 * stepper and N; o gives the tolerances. Sims are built when first needed. */
void rig_ana_init(rig_ana *a, const wg_params *p, int model, int stepper, int steps,
                  const wg_sweep_opts *o);
void rig_ana_fini(rig_ana *a);

/* First look at a record: pt is cleared, err/tol set (attempt 0 only) and
 * the period detected. Returns the period (> 0), 0 none, or a negative
 * return code (wg_status.h) with why. */
int rig_ana_period(rig_ana *a, const rig_rec *r, int attempt, wg_point *pt, char *why,
                   size_t whylen);

/* Largest Lyapunov exponent from the last recorded state (pt->lle). */
int rig_ana_lle(rig_ana *a, const rig_rec *r, wg_point *pt, char *why, size_t whylen);

/* Classify an orbit with no strict period from a fresh record taken after
 * the LLE, as the offline sweep does (loose tolerance when LLE <= lle_tol). */
void rig_ana_aperiodic(const rig_ana *a, const rig_rec *r, wg_point *pt);

#endif

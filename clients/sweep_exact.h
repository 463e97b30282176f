/* sweep_exact.h - the "exact (continuation)" column of wgsweep's
 * transitions table: which bifurcations located by wgcont
 * (PREFIX-bifurcations.csv) are a transition the sweep bracketed. */
#ifndef WG_SWEEP_EXACT_H
#define WG_SWEEP_EXACT_H

#include <stddef.h>
#include "cont_out.h"
#include "wormgear/wg_sweep.h"

/* The cell of a row seen by the up sweep (up) and/or the down sweep (dn),
 * either may be NULL: the located values of the same kind inside the row's
 * brackets widened by tight (a grid step), or failing that by win (the
 * up/down matching window), "-" when none. A grazing (impacts begin or
 * end) is a grazing of min x_n at +b, back-side impacts one at -b; a
 * doubling n -> 2n (or halving, or return to P1 from P2) a period
 * doubling of the period-n orbit; a jump the folds inside its hysteresis
 * interval; a quasi-periodic interval a torus. */
void exact_cell(const cont_bifs *x, const wg_transition *up, const wg_transition *dn,
                double tight, double win, char *buf, size_t len);

#endif

/* sweep_md.h - the Markdown transitions table of a sweep study (the paper's
 * Table 3, computed): per group, one row per transition with the up and
 * down sweeps side by side, the routes into chaos, the step-halving check
 * and the route of the up sweep. Written by wgsweep (also from an earlier
 * run's points, --table-from) and wgrig. */
#ifndef WG_SWEEP_MD_H
#define WG_SWEEP_MD_H

#include "sweep_out.h"

/* Write the transitions table of every group of st to path: 0, or -1 with
 * why. */
int md_write(const char *path, const sweep_study *st, char *why, size_t whylen);

#endif

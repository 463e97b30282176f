/* sweep_load.h - read a wgsweep points CSV back into a study (for
 * --table-from: recompute the transitions table without integrating). */
#ifndef WG_SWEEP_LOAD_H
#define WG_SWEEP_LOAD_H

#include "sweep_out.h"

/* Fill st's param, gparam, groups and chains (allocated; free with
 * load_free) from path. 0, or -1 with "file:line: ..." in why. The caller
 * sets scene, b, o and the other fields. Points carry no Poincare values. */
int load_points_csv(const char *path, sweep_study *st, char *why, size_t whylen);

/* Free the chains load_points_csv allocated. */
void load_free(sweep_study *st);

#endif

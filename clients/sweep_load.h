/* sweep_load.h - read a wgsweep points CSV back into a study (for
 * --table-from: recompute the transitions table without integrating). */
#ifndef WG_SWEEP_LOAD_H
#define WG_SWEEP_LOAD_H

#include "cont_out.h"
#include "sweep_out.h"

/* Fill st's param, gparam, groups and chains (allocated; free with
 * load_free) from path. 0, or -1 with "file:line: ..." in why (-2: out of
 * memory, said there too). The caller sets scene, b, o and the other
 * fields. Points carry no Poincare values. */
int load_points_csv(const char *path, sweep_study *st, char *why, size_t whylen);

/* Attach the n bifurcation files at paths (wgcont's, --exact) to st's
 * groups, one per group in order, read into ex[0..n-1]: 0, or -1 with why
 * ("--exact: ...": a count or parameter that does not fit, or the file's
 * own refusal), ex freed. */
int load_exact(const char *const *paths, int n, sweep_study *st, cont_bifs *ex, char *why,
               size_t whylen);

/* Free what load_exact read into ex[0..n-1]. */
void load_exact_free(cont_bifs *ex, int n);

/* Free the chains load_points_csv allocated. */
void load_free(sweep_study *st);

#endif

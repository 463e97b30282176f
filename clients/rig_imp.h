/* rig_imp.h - the mesh impacts wgrig hears on CONTACT, by period: kept for
 * the whole sweep, then counted over each point's recorded periods (the
 * impacts-per-period curve from CONTACT, beside the POINCARE statistics). */
#ifndef WG_RIG_IMP_H
#define WG_RIG_IMP_H

#include <stddef.h>
#include <stdint.h>

typedef struct rig_imp {
    int64_t *period;          /* period of each impact */
    size_t n, cap;
    int sorted;
} rig_imp;

/* Note an impact in period p; 0, or -1 when out of memory (not noted). */
int rig_imp_push(rig_imp *m, int64_t p);

/* Impacts in periods [p0, p1] (sorts them on the first count after a push). */
long rig_imp_count(rig_imp *m, int64_t p0, int64_t p1);

/* Free the list; m is empty again. */
void rig_imp_fini(rig_imp *m);

#endif

/* rig_imp.h - the mesh impacts wgrig hears on CONTACT, by period: kept for
 * the whole sweep, then counted over each point's recorded periods (the
 * impacts-per-period curve from CONTACT, beside the POINCARE statistics). */
#ifndef WG_RIG_IMP_H
#define WG_RIG_IMP_H

#include <stddef.h>
#include <stdint.h>

enum { RIG_IMP_LOST_MAX = 256 };

typedef struct rig_imp {
    int64_t *period;          /* period of each impact */
    size_t n, cap;
    int sorted;
    int64_t last;             /* period of the last event heard (-1: none yet) */
    int64_t lost[RIG_IMP_LOST_MAX][2]; /* periods where lost CONTACT messages' events lie */
    int nlost;                /* (beyond RIG_IMP_LOST_MAX: everything counts as lost) */
} rig_imp;

/* An empty list. */
void rig_imp_init(rig_imp *m);

/* The last event period heard, whichever contact (for rig_imp_lose). */
void rig_imp_heard(rig_imp *m, int64_t p);

/* CONTACT messages were lost before one whose first event is in period
 * p: their events lie in [the last period heard, p]. */
void rig_imp_lose(rig_imp *m, int64_t p);

/* 1 if periods [p0, p1] may have lost impacts (rig_imp_lose). */
int rig_imp_lost(const rig_imp *m, int64_t p0, int64_t p1);

/* Note an impact in period p; 0, or -1 when out of memory (not noted). */
int rig_imp_push(rig_imp *m, int64_t p);

/* Impacts in periods [p0, p1] (sorts them on the first count after a push). */
long rig_imp_count(rig_imp *m, int64_t p0, int64_t p1);

/* Free the list; m is empty again (rig_imp_init). */
void rig_imp_fini(rig_imp *m);

#endif

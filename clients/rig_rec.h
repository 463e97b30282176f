/* rig_rec.h - the Poincare sections wgrig records for one live sweep point
 * (from the daemon's POINCARE stream), and what a point takes from them
 * without any integration: statistics and the last section values. */
#ifndef WG_RIG_REC_H
#define WG_RIG_REC_H

#include <stdint.h>
#include "wormgear/wg_sweep.h"

/* Sections recorded from the POINCARE stream for one point. */
typedef struct rig_rec {
    int nstate, n, cap;
    double *y;           /* n x nstate states at the section */
    wg_period *stats;    /* the period that ended at each section */
    double *xn, *dxn;    /* x_n, x_n' at the section (as published) */
    int64_t *period;     /* daemon period index of each section */
} rig_rec;

/* Buffer for cap sections of nstate values; 0 or -1 (out of memory). */
int rig_rec_init(rig_rec *r, int nstate, int cap);
void rig_rec_fini(rig_rec *r);

/* Append one section (ignored when full). */
void rig_rec_push(rig_rec *r, const double *y, const wg_period *st, double xn, double dxn,
                  int64_t period);

/* Sections k0..k1 of r (0 <= k0 <= k1 < r->n), sharing r's buffers: read
 * it, do not push to it or free it. */
rig_rec rig_rec_slice(const rig_rec *r, int k0, int k1);

/* The record as the sweep library reads it (wg_record_*). */
wg_record rig_rec_view(const rig_rec *r);

/* Statistics (min/max x_n, worst motion, impacts per period) and the last
 * WG_POINT_NSEC Poincare values of the record into pt; y_end. */
void rig_rec_fill(const rig_rec *r, wg_point *pt);

#endif

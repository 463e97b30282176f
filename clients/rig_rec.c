/* rig_rec.c - the section record of a live sweep point (see rig_rec.h). */
#include "rig_rec.h"

#include <stdlib.h>
#include <string.h>

int rig_rec_init(rig_rec *r, int nstate, int cap)
{
    memset(r, 0, sizeof *r);
    r->nstate = nstate;
    r->cap = cap;
    r->y = malloc(sizeof(double) * (size_t)nstate * (size_t)cap);
    r->stats = malloc(sizeof(wg_period) * (size_t)cap);
    r->xn = malloc(sizeof(double) * (size_t)cap);
    r->dxn = malloc(sizeof(double) * (size_t)cap);
    r->period = malloc(sizeof(int64_t) * (size_t)cap);
    if (!r->y || !r->stats || !r->xn || !r->dxn || !r->period) {
        rig_rec_fini(r);
        return -1;
    }
    return 0;
}

void rig_rec_fini(rig_rec *r)
{
    free(r->y), free(r->stats), free(r->xn), free(r->dxn), free(r->period);
    r->y = NULL, r->stats = NULL, r->xn = r->dxn = NULL, r->period = NULL;
    r->n = r->cap = 0;
}

void rig_rec_push(rig_rec *r, const double *y, const wg_period *st, double xn, double dxn,
                  int64_t period)
{
    if (r->n >= r->cap)
        return;
    memcpy(r->y + (size_t)r->n * r->nstate, y, sizeof(double) * (size_t)r->nstate);
    r->stats[r->n] = *st;
    r->xn[r->n] = xn;
    r->dxn[r->n] = dxn;
    r->period[r->n++] = period;
}

rig_rec rig_rec_slice(const rig_rec *r, int k0, int k1)
{
    rig_rec s = *r;
    s.n = s.cap = k1 - k0 + 1;
    s.y += (size_t)k0 * (size_t)r->nstate;
    s.stats += k0, s.xn += k0, s.dxn += k0, s.period += k0;
    return s;
}

wg_record rig_rec_view(const rig_rec *r)
{
    return (wg_record){r->nstate, r->n, r->y, r->stats};
}

void rig_rec_fill(const rig_rec *r, wg_point *pt)
{
    wg_record v = rig_rec_view(r);
    wg_record_stats(&v, pt);
    int k0 = r->n > WG_POINT_NSEC ? r->n - WG_POINT_NSEC : 0;
    pt->nsec = r->n - k0;
    for (int i = 0; i < pt->nsec; i++) {
        pt->xn[i] = r->xn[k0 + i];
        pt->dxn[i] = r->dxn[k0 + i];
    }
    if (r->n)
        memcpy(pt->y_end, r->y + (size_t)(r->n - 1) * r->nstate, sizeof(double) * (size_t)r->nstate);
}

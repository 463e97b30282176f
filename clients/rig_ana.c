/* rig_ana.c - live point analysis, mirroring wg_sweep.c (see rig_ana.h). */
#include "rig_ana.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

void rig_ana_init(rig_ana *a, const wg_params *p, int model, int stepper, int steps,
                  const wg_sweep_opts *o)
{
    memset(a, 0, sizeof *a);
    a->p = *p;
    a->model = model;
    a->stepper = stepper;
    a->steps = steps;
    a->o = o;
}

void rig_ana_fini(rig_ana *a)
{
    if (a->have_fine)
        wg_sim_fini(&a->fine);
    if (a->have_lle)
        wg_sim_fini(&a->base), wg_sim_fini(&a->twin);
    a->have_fine = a->have_lle = 0;
}

static int sim_for(const rig_ana *a, wg_sim *s, int n, char *why, size_t whylen)
{
    wg_sim_config cfg = {a->model, a->stepper, n > WG_STEPS_MAX ? WG_STEPS_MAX : n};
    return wg_sim_init(s, &a->p, &cfg, why, whylen);
}

/* The one-period error of the record (wg_record_period_error). */
static int period_error(rig_ana *a, const rig_rec *r, double *err, char *why, size_t whylen)
{
    int rc;
    if (r->n < 2) {
        snprintf(why, whylen, "fewer than 2 sections recorded");
        return WG_EINVAL;
    }
    if (!a->have_fine) {
        if ((rc = sim_for(a, &a->fine, 2 * a->steps, why, whylen)))
            return rc;
        a->have_fine = 1;
    }
    wg_record v = rig_rec_view(r);
    return wg_record_period_error(&a->fine, &v, err);
}

int rig_ana_period(rig_ana *a, const rig_rec *r, int attempt, wg_point *pt, char *why,
                   size_t whylen)
{
    if (attempt == 0) {
        memset(pt, 0, sizeof *pt);
        pt->lle = NAN;
        pt->steps = a->steps;
        int rc = period_error(a, r, &pt->err, why, whylen);
        if (rc)
            return rc;
        pt->tol = fmax(a->o->tol_floor, a->o->tol_factor * pt->err);
    }
    int n = wg_period_detect(r->y, r->n, r->nstate, WG_PERIOD_MAX, pt->tol, &pt->resid);
    if (n > 0) {
        pt->regime = WG_REGIME_PERIODIC;
        pt->period = n;
        pt->converged = 1;
    }
    return n;
}

int rig_ana_lle(rig_ana *a, const rig_rec *r, wg_point *pt, char *why, size_t whylen)
{
    int rc;
    if (!a->have_lle) {
        if ((rc = sim_for(a, &a->base, a->steps, why, whylen)))
            return rc;
        if ((rc = sim_for(a, &a->twin, a->steps, why, whylen))) {
            wg_sim_fini(&a->base);
            return rc;
        }
        a->have_lle = 1;
    }
    double x[WG_NSTATE_MAX] = {0};
    memcpy(x, r->y + (size_t)(r->n - 1) * r->nstate, sizeof(double) * (size_t)r->nstate);
    rc = wg_lle_sims(&a->base, &a->twin, x, a->o->lle_periods, a->o->lle_d0, NULL, NULL,
                     &pt->lle);
    if (rc)
        snprintf(why, whylen, "LLE: %s", wg_status_str(rc));
    return rc;
}

void rig_ana_aperiodic(const rig_ana *a, const rig_rec *r, wg_point *pt)
{
    wg_record v = rig_rec_view(r);
    wg_record_classify(a->o, &v, pt);
}

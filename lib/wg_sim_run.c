/* wg_sim_run.c - the step loop: runs of plain steps in the kernel's own
 * loop (wg_krun), the general step (contacts, events, ramps), sections. */
#include "internal.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

/* ---- the step loop --------------------------------------------------------- */


static int cmp_event(const void *a, const void *b)
{
    double ta = ((const wg_event *)a)->tau, tb = ((const wg_event *)b)->tau;
    return (ta > tb) - (ta < tb);
}

/* Prepare a ramp step: current values, h with exactly 2 pi / N of phase,
 * and the phase law. Returns 1 if the ramp ends with this step. */
static int ramp_step(wg_sim *s, phase *ph, double *h)
{
    wg_ramp *r = &s->ramp;
    double dpsi = TWO_PI / s->cfg.steps_per_period;
    double el = s->tau - r->tau0, tr = r->dur - el;
    double slope = (r->v1 - r->v0) / r->dur;
    ph->psi0 = wg_sim_psi(s);
    if (r->id != WG_P_OMEGA) {
        s->p.v[r->id] = el >= r->dur ? r->v1 : r->v0 + slope * el;
        sim_coefficients(s);
        double om = s->p.v[WG_P_OMEGA];
        *ph = (phase){ph->psi0, om, 0.0, INFINITY, om};
        *h = dpsi / om;
        return *h >= tr;
    }
    double om0 = el >= r->dur ? r->v1 : r->v0 + slope * el;
    s->p.v[WG_P_OMEGA] = om0;
    double pe = tr > 0 ? tr * (om0 + 0.5 * slope * tr) : 0.0;
    if (pe >= dpsi) {
        *h = 2.0 * dpsi / (om0 + sqrt(om0 * om0 + 2.0 * slope * dpsi));
        *ph = (phase){ph->psi0, om0, slope, INFINITY, r->v1};
        return 0;
    }
    tr = tr > 0 ? tr : 0.0;
    *h = tr + (dpsi - pe) / r->v1;
    *ph = (phase){ph->psi0, om0, slope, tr, r->v1};
    return 1;
}

static void ramp_finish(wg_sim *s)
{
    s->p.v[s->ramp.id] = s->ramp.v1;
    s->ramp.active = 0;
    sim_coefficients(s);
    sim_build_table(s);
}

static void emit_section(wg_sim *s, const wg_sink *sink)
{
    s->core->last = s->core->cur;
    if (sink && sink->on_section) {
        wg_section sec;
        sec.tau = s->tau;
        sec.omega = s->p.v[WG_P_OMEGA];
        memcpy(sec.y, s->y, sizeof sec.y);
        wg_sim_outputs(s, &sec.out);
        sec.stats = s->core->cur;
        sink->on_section(sink->ctx, &sec);
    }
}

/* Bookkeeping after an accepted step from contacts (q0, v0) to (q1, v1). */
static void after_step(wg_sim *s, const double *q0, const double *v0, const double *q1,
                       const double *v1, double h, evbuf *b, const wg_sink *sink)
{
    herm_turn(q0[0], q1[0], v0[0], v1[0], h, &s->core->cur.min_xn, &s->core->cur.max_xn);
    s->core->cur.min_xn = dmin(s->core->cur.min_xn, q1[0]);
    s->core->cur.max_xn = dmax(s->core->cur.max_xn, q1[0]);
    if (b->n == 0)
        return;
    if (b->n > 1)
        qsort(b->ev, (size_t)b->n, sizeof b->ev[0], cmp_event);
    for (int i = 0; i < b->n; i++) {
        wg_event *ev = &b->ev[i];
        s->nevents[ev->contact][ev->kind]++;
        if (ev->contact == WG_C_MESH) {
            if (ev->kind == WG_EV_DRIVE_IMPACT || ev->kind == WG_EV_BACK_IMPACT)
                s->core->cur.impacts++;
            if (ev->kind == WG_EV_SEPARATION && s->core->cur.motion < WG_MOTION_SINGLE)
                s->core->cur.motion = WG_MOTION_SINGLE;
            if (ev->kind == WG_EV_BACK_IMPACT)
                s->core->cur.motion = WG_MOTION_DOUBLE;
        } else if (ev->kind == WG_EV_DRIVE_IMPACT || ev->kind == WG_EV_BACK_IMPACT) {
            int j = ev->contact - WG_C_X1; /* a bearing's impact, either side */
            s->core->cur.bimpacts[j]++;
            s->core->cur.bvmax[j] = dmax(s->core->cur.bvmax[j], fabs(ev->velocity));
        }
        if (sink && sink->on_event)
            sink->on_event(sink->ctx, ev);
    }
}

/* Commit the run's local copies back into the sim. */
static void sync_out(wg_sim *s, const double *y, const double *q, const double *v)
{
    memcpy(s->y, y, sizeof s->y);
    memcpy(s->core->q, q, sizeof s->core->q);
    memcpy(s->core->v, v, sizeof s->core->v);
}

/* The step just taken ended a period at x_n = xn: count it, and hand the
 * section to the sink (the caller has synced the state when it has one). */
static void period_end(wg_sim *s, const wg_sink *sink, double xn)
{
    s->period++;
    s->core->wrap_pending = 0;
    emit_section(s, sink);
    sim_period_start(s, xn);
}

/* Up to n plain steps in the kernel's own loop (wg_krun) from the state y
 * with contacts q, v (updated); returns how many it took. It stops after a
 * step that ends a period (s->k is then 0; the caller counts the period);
 * a step it stops before is left to the general step, and *has_trial says
 * whether its kernel's result is in y1 already. */
static uint64_t fast_steps(wg_sim *s, double *y, double *q, double *v, uint64_t n, double *y1,
                           int *has_trial)
{
    wg_sim_core *c = s->core;
    wg_krun r = {.xn = q[0], .dxn = v[0], .tau = s->tau, .tau_c = s->tau_c,
                 .min_xn = c->cur.min_xn, .max_xn = c->cur.max_xn, .k = s->k,
                 .N = (uint32_t)s->cfg.steps_per_period, .h = s->h, .fin = ABSURD * (1 - 1e-9),
                 .table = c->table, .trial = y1};
    memcpy(r.y, y, sizeof r.y);
    memcpy(r.lo, c->zlo, sizeof r.lo);
    memcpy(r.hi, c->zhi, sizeof r.hi);
    uint64_t m = c->krun(&c->kc, &r, n);
    *has_trial = r.has_trial;
    if (m == 0)
        return 0;
    memcpy(y, r.y, sizeof r.y);
    q[0] = r.xn;
    v[0] = r.dxn;
    for (int j = 0; j < 6 && (c->kflags & KF_BEAR); j++) { /* as ct_contacts */
        q[j + 1] = y[j];
        v[j + 1] = y[7 + j];
    }
    s->tau = r.tau;
    s->tau_c = r.tau_c;
    c->cur.min_xn = r.min_xn;
    c->cur.max_xn = r.max_xn;
    s->k = r.k == r.N ? 0 : r.k;
    s->steps += m;
    return m;
}

int wg_sim_run(wg_sim *s, uint64_t n, const wg_sink *sink, uint64_t *done)
{
    const uint32_t N = (uint32_t)s->cfg.steps_per_period;
    const int nst = s->nstate, locked = s->cfg.stepper == WG_STEPPER_RK4_EVENT;
    const void *kctx = s->cfg.model == WG_MODEL_PRINTED ? (const void *)&s->p : (const void *)&s->core->kc;
    /* Double-buffered state and contacts: the accepted step is a pointer
     * swap, and s->y is written only when a callback or the caller reads it.
     * Both buffers start equal (torsional kernels leave the bearings alone). */
    double yb[2][WG_NSTATE_MAX], qb[2][WG_NCONTACT], vb[2][WG_NCONTACT];
    memcpy(yb[0], s->y, sizeof yb[0]);
    memcpy(yb[1], s->y, sizeof yb[1]);
    memcpy(qb[0], s->core->q, sizeof qb[0]);
    memcpy(vb[0], s->core->v, sizeof vb[0]);
    int cur = 0;
    uint64_t i;
    int rc = WG_OK;
    /* plain steps run in the kernel's own loop unless a ramp or a per-step
     * callback needs the general step every time */
    const int fast = s->core->krun && !(sink && sink->on_step);
    for (i = 0; i < n; i++) {
        int has_trial = 0;
        if (fast && !s->ramp.active) {
            uint64_t m;
            while (i < n && (m = fast_steps(s, yb[cur], qb[cur], vb[cur], n - i, yb[!cur],
                                            &has_trial)) > 0) {
                i += m;
                if (s->k != 0)
                    break;
                if (sink && sink->on_section)
                    sync_out(s, yb[cur], qb[cur], vb[cur]);
                period_end(s, sink, qb[cur][0]);
            }
            if (i == n)
                break;
        }
        double *y0 = yb[cur], *y1 = yb[!cur], *q0 = qb[cur], *q1 = qb[!cur];
        double *v0 = vb[cur], *v1 = vb[!cur];
        const wg_exc *e;
        wg_exc live[3];
        double h;
        phase ph;
        int ramp_ends = 0;
        if (!s->ramp.active) {
            e = &s->core->table[2 * s->k];
            h = s->h;
        } else {
            ramp_ends = ramp_step(s, &ph, &h);
            ct_exc_at(s, &ph, 0.0, &live[0]);
            ct_exc_at(s, &ph, 0.5 * h, &live[1]);
            ct_exc_at(s, &ph, h, &live[2]);
            e = live;
        }
        if (!has_trial) /* else the run of plain steps computed it */
            s->core->kernel(y0, y1, kctx, e, h);
        int nc = ct_ncontacts(s), changed = 0;
        ct_contacts(s, y1, &e[2], q1, v1);
        changed = (ct_zone(q1[0], s->core->kc.b) ^ s->core->zone[0]);
        for (int j = 1; j < nc; j++) /* branch-free: any bearing left its zone */
            changed |= ct_zone(q1[j], s->core->kc.bj) ^ s->core->zone[j];
        evbuf b;
        b.n = 0;
        if (changed) {
            int zsave[WG_NCONTACT];
            uint64_t splits_before = s->nsplit;
            memcpy(zsave, s->core->zone, sizeof zsave);
            if (!s->ramp.active) {
                double om = s->p.v[WG_P_OMEGA];
                ph = (phase){wg_sim_psi(s), om, 0.0, INFINITY, om};
            }
            if (locked) {
                ct_split_step(s, &ph, y0, y1, h, &b);
                ct_contacts(s, y1, &e[2], q1, v1);
            } else {
                for (int j = 0; j < nc; j++) {
                    int z1 = ct_zone(q1[j], ct_threshold(s, j));
                    if (z1 != s->core->zone[j]) {
                        herm H = {q0[j], q1[j], v0[j] * h, v1[j] * h};
                        ct_interpolate(s, &b, j, s->core->zone[j], z1, &H, 0.0, h);
                        s->core->zone[j] = z1;
                        ct_set_lock(s, j, z1); /* the bounds (rk4 reads no lock) */
                    }
                }
            }
            if (!sim_finite_state(y1, nst)) { /* undo the zone updates and counts */
                s->nsplit = splits_before;
                memcpy(s->core->zone, zsave, sizeof zsave);
                for (int j = 0; j < WG_NCONTACT; j++)
                    ct_set_lock(s, j, s->core->zone[j]);
            }
        }
        if (!sim_finite_state(y1, nst)) {
            rc = WG_ENONFINITE;
            break;
        }
        cur = !cur; /* accept */
        double dt = h - s->tau_c, t = s->tau + dt;
        s->tau_c = (t - s->tau) - dt;
        s->tau = t;
        s->steps++;
        after_step(s, q0, v0, q1, v1, h, &b, sink);
        if (++s->k == N)
            s->k = 0, s->core->wrap_pending = 1;
        if (ramp_ends)
            ramp_finish(s);
        else if (s->ramp.active && s->ramp.id == WG_P_OMEGA)
            s->p.v[WG_P_OMEGA] = s->ramp.v0 + (s->ramp.v1 - s->ramp.v0) *
                                                  (s->tau - s->ramp.tau0) / s->ramp.dur;
        if (sink && (sink->on_step || (s->k == 0 && sink->on_section)))
            sync_out(s, y1, q1, v1);
        if (sink && sink->on_step)
            sink->on_step(sink->ctx, s);
        if (s->k == 0)
            period_end(s, sink, q1[0]);
    }
    sync_out(s, yb[cur], qb[cur], vb[cur]);
    if (done)
        *done = i;
    return rc;
}

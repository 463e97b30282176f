/* wg_sim_run.c - the step loop: runs of plain steps in the kernel's own
 * loop (wg_krun), the general step (contacts, events, ramps), sections. */
#include "internal.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <string.h>

/* ---- the step loop --------------------------------------------------------- */

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
    for (int i = 1; i < b->n; i++) { /* by time, stable: a step has a few */
        wg_event ev = b->ev[i];
        int j = i;
        for (; j > 0 && b->ev[j - 1].tau > ev.tau; j--)
            b->ev[j] = b->ev[j - 1];
        b->ev[j] = ev;
    }
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

/* The runner's steps, inlined into wg_sim_run and wg_sim_run_pair so that the
 * runner never escapes to a callee. */
#define RUN_INLINE static inline __attribute__((always_inline))

/* A run in progress (wg_sim_run, wg_sim_run_pair): double-buffered state
 * and contacts, so an accepted step is a buffer swap and s->y is written
 * only when a callback or the caller reads it; the steps asked for and
 * taken; whether the step to come was computed already (has_trial: its
 * kernel result is in the other buffer). */
typedef struct runbuf {
    double yb[2][WG_NSTATE_MAX], qb[2][WG_NCONTACT], vb[2][WG_NCONTACT];
} runbuf;

typedef struct runner {
    wg_sim *s;
    const wg_sink *sink;
    uint64_t n, i;
    runbuf *b; /* apart: handing its rows to a callee leaves the counters in registers */
    int cur, fast, has_trial, rc;
} runner;

RUN_INLINE void run_begin(runner *R, runbuf *b, wg_sim *s, uint64_t n, const wg_sink *sink)
{
    R->b = b;
    R->s = s, R->sink = sink, R->n = n, R->i = 0;
    /* both buffers start equal (torsional kernels leave the bearings alone) */
    memcpy(R->b->yb[0], s->y, sizeof R->b->yb[0]);
    memcpy(R->b->yb[1], s->y, sizeof R->b->yb[1]);
    memcpy(R->b->qb[0], s->core->q, sizeof R->b->qb[0]);
    memcpy(R->b->vb[0], s->core->v, sizeof R->b->vb[0]);
    R->cur = 0;
    /* plain steps run in the kernel's own loop unless a ramp or a per-step
     * callback needs the general step every time */
    R->fast = s->core->krun && !(sink && sink->on_step);
    R->has_trial = 0;
    R->rc = WG_OK;
}

RUN_INLINE void run_end(runner *R, uint64_t *done)
{
    sync_out(R->s, R->b->yb[R->cur], R->b->qb[R->cur], R->b->vb[R->cur]);
    if (done)
        *done = R->i;
}

/* Can the next steps run in the kernel's own loop? */
static int run_fast_now(const runner *R) { return R->fast && !R->s->ramp.active; }

/* A wg_krun for up to the steps left, from the run's state; a step it
 * stops before is written into the other buffer. Field by field: a
 * compound literal zeroed the whole struct first (336 bytes, a `rep stos`
 * that perf put at a fifth of wg_sim_run's own time on impacting runs),
 * though every field is written here. */
RUN_INLINE void krun_prep(runner *R, wg_krun *r)
{
    wg_sim *s = R->s;
    wg_sim_core *c = s->core;
    r->xn = R->b->qb[R->cur][0], r->dxn = R->b->vb[R->cur][0];
    r->tau = s->tau, r->tau_c = s->tau_c;
    r->min_xn = c->cur.min_xn, r->max_xn = c->cur.max_xn;
    r->k = s->k, r->N = (uint32_t)s->cfg.steps_per_period;
    r->h = s->h, r->fin = ABSURD * (1 - 1e-9);
    r->table = c->table;
    r->trial = R->b->yb[!R->cur], r->has_trial = 0;
    memcpy(r->y, R->b->yb[R->cur], sizeof r->y);
    memcpy(r->lo, c->zlo, sizeof r->lo);
    memcpy(r->hi, c->zhi, sizeof r->hi);
}

/* Take the m plain steps r ran. Returns 1 if the run goes on in the
 * kernel's loop (none refused: the steps asked for are done, or a period
 * ended and is counted here, or a paired run stopped for the other sim),
 * 0 if the general step takes the next step. */
RUN_INLINE int krun_commit(runner *R, const wg_krun *r, uint64_t m)
{
    wg_sim *s = R->s;
    wg_sim_core *c = s->core;
    R->has_trial = r->has_trial;
    if (m > 0) {
        double *y = R->b->yb[R->cur], *q = R->b->qb[R->cur], *v = R->b->vb[R->cur];
        memcpy(y, r->y, sizeof r->y);
        q[0] = r->xn;
        v[0] = r->dxn;
        for (int j = 0; j < 6 && (c->kflags & KF_BEAR); j++) { /* as ct_contacts */
            q[j + 1] = y[j];
            v[j + 1] = y[7 + j];
        }
        s->tau = r->tau;
        s->tau_c = r->tau_c;
        c->cur.min_xn = r->min_xn;
        c->cur.max_xn = r->max_xn;
        s->k = r->k == r->N ? 0 : r->k;
        s->steps += m;
        R->i += m;
        if (r->k == r->N) {
            if (R->sink && R->sink->on_section)
                sync_out(s, y, q, R->b->vb[R->cur]);
            period_end(s, R->sink, q[0]);
        }
    }
    return !r->has_trial;
}

/* Plain steps in the kernel's own loop until one is refused, the steps
 * asked for are done, or a sink's callback at a period's end started a ramp
 * (its steps are the general step's from the next one on). */
RUN_INLINE void run_fast(runner *R)
{
    while (R->i < R->n && run_fast_now(R)) {
        wg_krun r;
        krun_prep(R, &r);
        uint64_t m = R->s->core->krun(&R->s->core->kc, &r, R->n - R->i);
        if (!krun_commit(R, &r, m))
            break;
    }
}

/* One step by the general path: the kernel (unless the run computed it),
 * contacts, zone changes split at their events, ramps, callbacks, the
 * period's end. */
RUN_INLINE void run_general(runner *R)
{
    wg_sim *s = R->s;
    const wg_sink *sink = R->sink;
    const uint32_t N = (uint32_t)s->cfg.steps_per_period;
    const int nst = s->nstate, locked = s->cfg.stepper == WG_STEPPER_RK4_EVENT;
    const void *kctx = s->cfg.model == WG_MODEL_PRINTED ? (const void *)&s->p
                                                        : (const void *)&s->core->kc;
    const int cur = R->cur, has_trial = R->has_trial;
    double *y0 = R->b->yb[cur], *y1 = R->b->yb[!cur], *q0 = R->b->qb[cur], *q1 = R->b->qb[!cur];
    double *v0 = R->b->vb[cur], *v1 = R->b->vb[!cur];
    R->has_trial = 0;
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
    int finite = 1;
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
        finite = sim_finite_state(y1, nst);
        if (!finite) { /* undo the zone updates and counts */
            s->nsplit = splits_before;
            memcpy(s->core->zone, zsave, sizeof zsave);
            for (int j = 0; j < WG_NCONTACT; j++)
                ct_set_lock(s, j, s->core->zone[j]);
        }
    }
    if (!(changed ? finite : sim_finite_state(y1, nst))) {
        R->rc = WG_ENONFINITE;
        return;
    }
    R->cur = !cur; /* accept */
    R->i++;
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

/* Plain steps while the kernel's own loop can take them, then, if steps
 * are left, one by the general path. */
RUN_INLINE void run_segment(runner *R)
{
    if (run_fast_now(R))
        run_fast(R);
    if (R->i < R->n)
        run_general(R);
}

int wg_sim_run(wg_sim *s, uint64_t n, const wg_sink *sink, uint64_t *done)
{
    runner R;
    runbuf b;
    run_begin(&R, &b, s, n, sink);
    while (R.i < R.n && R.rc == WG_OK)
        run_segment(&R);
    run_end(&R, done);
    return R.rc;
}

/* The paired loop for the two runs as they stand, or NULL: both must take
 * plain steps of the same specialisation (any parameters, any N). */
static wg_krun2_fn pair_fn(const runner *R)
{
    const wg_sim_core *a = R[0].s->core, *b = R[1].s->core;
    if (a->kflags != b->kflags || a->isa_one != b->isa_one || !run_fast_now(&R[0]) ||
        !run_fast_now(&R[1]))
        return NULL;
    return krun2_select(a->kflags, a->isa_one);
}

/* Both sims' plain steps in one paired loop while both can take them (asked
 * again after every stop: a sink's callback at a period's end may change a
 * sim). 0 if they cannot now. */
static int pair_fast(runner *R)
{
    wg_krun2_fn f = pair_fn(R);
    if (!f)
        return 0;
    wg_sim *a = R[0].s, *b = R[1].s;
    int go[2] = {1, 1};
    while (f && go[0] && go[1] && R[0].i < R[0].n && R[1].i < R[1].n) {
        wg_krun r[2];
        uint64_t m[2];
        krun_prep(&R[0], &r[0]);
        krun_prep(&R[1], &r[1]);
        f(&a->core->kc, &r[0], R[0].n - R[0].i, &b->core->kc, &r[1], R[1].n - R[1].i, m);
        go[0] = krun_commit(&R[0], &r[0], m[0]);
        go[1] = krun_commit(&R[1], &r[1], m[1]);
        f = pair_fn(R);
    }
    return 1;
}

void wg_sim_run_pair(wg_sim *const s[2], const uint64_t n[2], const wg_sink *const sink[2],
                     uint64_t done[2], int rc[2])
{
    runner R[2];
    runbuf b[2];
    run_begin(&R[0], &b[0], s[0], n[0], sink[0]);
    run_begin(&R[1], &b[1], s[1], n[1], sink[1]);
    while (R[0].i < R[0].n && R[1].i < R[1].n && R[0].rc == WG_OK && R[1].rc == WG_OK) {
        if (pair_fast(R)) {
            /* a sim whose run refused a step takes it by the general path */
            for (int j = 0; j < 2; j++)
                if (R[j].i < R[j].n && R[j].has_trial)
                    run_general(&R[j]);
            continue;
        }
        for (int j = 0; j < 2; j++) /* one sim cannot pair: a segment of each in turn */
            if (R[j].i < R[j].n && R[j].rc == WG_OK)
                run_segment(&R[j]);
    }
    for (int j = 0; j < 2; j++) {
        run_end(&R[j], &done[j]);
        rc[j] = R[j].rc;
    }
}

/* ---- batches: up to KB_LANES runs, one per vector lane ----------------------- */

/* Run r (at most n plain steps, with the sim's constants K) into lane l. */
static void kb_load(wg_kbatch *B, int l, const wg_kcoef *K, const wg_krun *r, uint64_t n)
{
    double lo6[6], hi6[6];
    const double lim = krun_bounds(r, lo6, hi6);
    for (int b = 0; b < 6; b++) {
        B->q[b][l] = r->y[b];
        B->v[b][l] = r->y[7 + b];
        B->c[b][l] = K->c[b];
        B->m[b][l] = K->m[b];
        B->k[b][l] = K->k[b];
        B->nd[b][l] = -K->d[b];
        B->cd[b][l] = K->cd[b];
        B->ck[b][l] = K->ck[b];
        B->w[b][l] = K->w[1 + b];
        B->zc[b][l] = K->zc[1 + b];
        B->lo[b][l] = lo6[b];
        B->hi[b][l] = hi6[b];
    }
    B->s[l] = r->y[6], B->vs[l] = r->y[13];
    B->xn[l] = r->xn, B->dxn[l] = r->dxn, B->tau[l] = r->tau, B->tc[l] = r->tau_c;
    B->mn[l] = r->min_xn, B->mx[l] = r->max_xn;
    B->bj[l] = K->bj, B->M[l] = K->M, B->ds[l] = K->d[6], B->dp[l] = K->dp, B->b[l] = K->b;
    B->w0[l] = K->w[0], B->zc0[l] = K->zc[0], B->h[l] = r->h;
    B->lim[l] = lim, B->mlo[l] = r->lo[0], B->mhi[l] = r->hi[0];
    B->ep[l] = &r->table[2 * r->k];
    B->lim_steps[l] = n < (uint64_t)(r->N - r->k) ? n : (uint64_t)(r->N - r->k);
    B->trial[l] = r->trial;
}

/* Lane l back into its run r, which took m steps since it was loaded. */
static void kb_store(const wg_kbatch *B, int l, wg_krun *r, uint64_t m)
{
    for (int b = 0; b < 6; b++) {
        r->y[b] = B->q[b][l];
        r->y[7 + b] = B->v[b][l];
    }
    r->y[6] = B->s[l], r->y[13] = B->vs[l];
    r->xn = B->xn[l], r->dxn = B->dxn[l], r->tau = B->tau[l], r->tau_c = B->tc[l];
    r->min_xn = B->mn[l], r->max_xn = B->mx[l];
    r->k += (uint32_t)m;
    r->has_trial = (B->refused >> l) & 1u;
}

/* Lane j back into its run (m steps since it was loaded), committed as a
 * run of plain steps is. */
static void kb_commit(const wg_kbatch *B, int j, runner *R, wg_krun *r, uint64_t m)
{
    kb_store(B, j, r, m);
    krun_commit(R, r, m);
    R->s->core->batched += m;
}

/* Can run j join (or stay in) a batch of kind (kflags, isa)? */
static int batch_lane_ok(const runner *R, unsigned kflags, int isa)
{
    const wg_sim_core *c = R->s->core;
    return c->kflags == kflags && c->isa == isa && run_fast_now(R) && R->i < R->n &&
           R->rc == WG_OK;
}

/* The L runs' plain steps in one batched loop while all of them can take
 * them; a lane that stops (a period's end, a refused step, taken by the
 * general path here) goes on in the loop until one run's steps are done
 * or a run can no longer take plain steps. 0 if they cannot now. */
static int batch_fast(runner *R, int L)
{
    const unsigned kflags = R[0].s->core->kflags;
    const int isa = R[0].s->core->isa;
    wg_kbatch_fn f = kbatch_select(kflags, isa, L);
    for (int j = 0; j < L && f; j++)
        if (!batch_lane_ok(&R[j], kflags, isa))
            f = NULL;
    if (!f)
        return 0;
    wg_kbatch B;
    wg_krun r[KB_LANES];
    uint64_t taken[KB_LANES] = {0};
    for (int j = 0; j < L; j++) {
        krun_prep(&R[j], &r[j]);
        kb_load(&B, j, &R[j].s->core->kc, &r[j], R[j].n - R[j].i);
    }
    for (int j = L; j < KB_LANES; j++) /* lanes left out compute a copy of lane 0 */
        kb_load(&B, j, &R[0].s->core->kc, &r[0], R[0].n - R[0].i);
    B.active = (1u << L) - 1;
    int go = 1;
    while (go) {
        unsigned stop = f(&B);
        for (int j = 0; j < L; j++)
            taken[j] += B.ran[j];
        for (int j = 0; j < L; j++) {
            if (!((stop >> j) & 1u))
                continue;
            kb_commit(&B, j, &R[j], &r[j], taken[j]);
            taken[j] = 0;
            if (R[j].i < R[j].n && R[j].has_trial) /* the refused step */
                run_general(&R[j]);
            if (batch_lane_ok(&R[j], kflags, isa)) {
                krun_prep(&R[j], &r[j]);
                kb_load(&B, j, &R[j].s->core->kc, &r[j], R[j].n - R[j].i);
            } else {
                B.active &= ~(1u << j);
                go = 0;
            }
        }
        for (int j = 0; j < L && go; j++) /* a callback may have changed another sim */
            go = batch_lane_ok(&R[j], kflags, isa);
    }
    for (int j = 0; j < L; j++)
        if ((B.active >> j) & 1u) {
            B.refused &= ~(1u << j); /* a lane loaded again since refused nothing */
            kb_commit(&B, j, &R[j], &r[j], taken[j]);
        }
    return 1;
}

void wg_sim_run_batch(int L, wg_sim *const s[], const uint64_t n[], const wg_sink *const sink[],
                      uint64_t done[], int rc[])
{
    runner R[KB_LANES];
    runbuf b[KB_LANES];
    if (L > KB_LANES) /* refused whole: nothing runs */
        for (int j = 0; j < L; j++)
            done[j] = 0, rc[j] = WG_EINVAL;
    if (L < 1 || L > KB_LANES)
        return;
    for (int j = 0; j < L; j++)
        run_begin(&R[j], &b[j], s[j], n[j], sink[j]);
    for (;;) {
        int all = 1;
        for (int j = 0; j < L; j++)
            all &= R[j].i < R[j].n && R[j].rc == WG_OK;
        if (!all)
            break;
        if (L > 1 && batch_fast(R, L))
            continue;
        for (int j = 0; j < L; j++) /* a run cannot join: a segment of each in turn */
            if (R[j].i < R[j].n && R[j].rc == WG_OK)
                run_segment(&R[j]);
    }
    for (int j = 0; j < L; j++) {
        run_end(&R[j], &done[j]);
        rc[j] = R[j].rc;
    }
}

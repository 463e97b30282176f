/* wg_contact.c - contacts of the running model: coordinates and zones of
 * the mesh and the six bearings, the phase law within a step, crossings
 * located on a contact's Hermite interpolant, contact events, and the
 * rk4-event step split at located dead-zone crossings. */
#include "internal.h"

#include <math.h>
#include <string.h>

#define MAX_SPLITS CT_MAX_SPLITS

/* The phase law at t: psi(t) - psi0 = a + b (b, the part past the ramp's
 * end at tr, is 0 before it) and omega(t). */
static void phase_at(const phase *ph, double t, double *a, double *b, double *om)
{
    if (t <= ph->tr) {
        *a = t * (ph->om0 + 0.5 * ph->r * t);
        *b = 0.0;
        *om = ph->om0 + ph->r * t;
    } else {
        *a = ph->tr * (ph->om0 + 0.5 * ph->r * ph->tr);
        *b = ph->om1 * (t - ph->tr);
        *om = ph->om1;
    }
}

/* The excitation from c = cos psi and sn = sin psi: the three phase
 * offsets applied by rotation (wg_exc_eval's formula). */
static inline wg_exc exc_of(const wg_sim *s, double c, double sn, double om)
{
    const double *v = s->p.v, (*r)[2] = s->core->kc.rot;
    return (wg_exc){.kp = 1.0 + v[WG_P_K_A] * (c * r[0][0] - sn * r[0][1]),
                    .te = v[WG_P_E_M] * (c * r[1][0] - sn * r[1][1]),
                    .dte = v[WG_P_E_M] * om * (sn * r[1][0] + c * r[1][1]),
                    .fx = v[WG_P_F_M] + v[WG_P_F_E] * (c * r[2][0] - sn * r[2][1])};
}

/* Excitation at sub-step time t: one sine and cosine of psi (2 libm calls
 * instead of wg_exc_eval's 4). */
void ct_exc_at(const wg_sim *s, const phase *ph, double t, wg_exc *e)
{
    double a, b, om;
    phase_at(ph, t, &a, &b, &om);
    double psi = (ph->psi0 + a) + b;
    *e = exc_of(s, cos(psi), sin(psi), om);
}

/* The excitation at sub-step time t by rotating (c0, s0) = (cos, sin) of
 * psi0 through d = psi(t) - psi0, with no libm call while |d| <= 1/4: a
 * sine and cosine polynomial of d, to the d^7 and d^8 terms for |d| <=
 * 0.05 (N >= 126 steps a period), to d^11 and d^12 up to 1/4 (N >= 26),
 * each under 6e-18 off. Against the exact phase it is as accurate as
 * ct_exc_at (whose psi0 + d is rounded to 9e-16): 1.0e-15 against 1.3e-15
 * in cos and sin for N = 26 ... 4096; lib.test_model holds the two within
 * 2e-15 of each other. */
wg_exc ct_exc_rot(const wg_sim *s, const phase *ph, double c0, double s0, double t)
{
    double a, b, om, c, sn;
    phase_at(ph, t, &a, &b, &om);
    double d = a + b, d2 = d * d, S, C1;
    if (fabs(d) <= 0.05) {
        S = d * (1 + d2 * (-1.0 / 6 + d2 * (1.0 / 120 + d2 * (-1.0 / 5040))));
        C1 = d2 * (-0.5 + d2 * (1.0 / 24 + d2 * (-1.0 / 720 + d2 * (1.0 / 40320))));
    } else if (fabs(d) <= 0.25) {
        S = d * (1 + d2 * (-1.0 / 6 + d2 * (1.0 / 120 + d2 * (-1.0 / 5040 +
            d2 * (1.0 / 362880 + d2 * (-1.0 / 39916800))))));
        C1 = d2 * (-0.5 + d2 * (1.0 / 24 + d2 * (-1.0 / 720 + d2 * (1.0 / 40320 +
             d2 * (-1.0 / 3628800 + d2 * (1.0 / 479001600))))));
    } else { /* fewer than 26 steps a period */
        return exc_of(s, cos(ph->psi0 + d), sin(ph->psi0 + d), om);
    }
    c = c0 + (c0 * C1 - s0 * S); /* cos(psi0 + d) */
    sn = s0 + (s0 * C1 + c0 * S);
    return exc_of(s, c, sn, om);
}

/* The double just above c >= 0: x > c iff x >= above(c). */
static double above(double c)
{
    uint64_t u;
    memcpy(&u, &c, sizeof u);
    u = c == 0.0 ? 1 : u + 1;
    memcpy(&c, &u, sizeof c);
    return c;
}

void ct_set_lock(wg_sim *s, int contact, int zone)
{
    double c = ct_threshold(s, contact);
    s->core->kc.w[contact] = zone != 0 ? 1.0 : 0.0;
    s->core->kc.zc[contact] = zone * c;
    /* ct_zone(x, c) == zone iff zlo <= x <= zhi (never for NaN) */
    s->core->zlo[contact] = zone > 0 ? above(c) : zone == 0 ? -c : -INFINITY;
    s->core->zhi[contact] = zone < 0 ? -above(c) : zone == 0 ? c : INFINITY;
}

/* ---- events ---------------------------------------------------------------- */

/* Leaving zone z in direction dir (+1 up, -1 down) across the boundary at
 * +-c: the threshold crossed and the event kind (MODEL.md s5). */
static int transition(int z, int dir, double c, double *thr)
{
    if (dir < 0) {
        *thr = z == 1 ? c : -c;
        return z == 1 ? WG_EV_SEPARATION : WG_EV_BACK_IMPACT;
    }
    *thr = z == -1 ? -c : c;
    return z == -1 ? WG_EV_BACK_RELEASE : WG_EV_DRIVE_IMPACT;
}

static void ev_push(evbuf *b, const wg_sim *s, double tau, int contact, int kind, double vel)
{
    if (b->n == MAX_STEP_EVENTS)
        return;
    b->ev[b->n++] = (wg_event){tau, vel, s->period, contact, kind};
}

/* Interpolate the crossings of contact j from zone z0 to z1 on one step. */
void ct_interpolate(const wg_sim *s, evbuf *b, int j, int z0, int z1,
                                  const herm *H, double t0, double len)
{
    double c = ct_threshold(s, j), thr;
    int dir = z1 > z0 ? 1 : -1;
    for (int z = z0; z != z1; z += dir) {
        int kind = transition(z, dir, c, &thr);
        double t = herm_root(H, thr);
        ev_push(b, s, s->tau + t0 + t * len, j, kind, herm_der(H, t) / len);
    }
}

/* ---- rk4-event: split the step at located crossings -------------------- */

/* The excitation at the sub-step times of one split step, each by
 * ct_exc_rot from psi0's (cos, sin), kept per k (ct_psi0: psi0 = 2 pi k /
 * N). Each time is evaluated once: ct_split_step keeps the excitation at
 * the step's end, at the time the next substep starts and at the crossing
 * a substep ends at. */
typedef struct exc_rot0 {
    double c0, s0; /* cos psi0, sin psi0 */
} exc_rot0;

/* psi0 is wg_sim_psi(s) = 2 pi k / N at every step, an omega ramp's too
 * (ramp_step keeps the phase grid and adjusts h). */
static exc_rot0 exc_rot0_of(wg_sim *s, const phase *ph)
{
    ct_psi0 *z = &s->core->psi0[s->k];
    if (!z->set) {
        z->c = cos(ph->psi0);
        z->s = sin(ph->psi0);
        z->set = 1;
    }
    return (exc_rot0){z->c, z->s};
}

static wg_exc exc_at(const exc_rot0 *m, const wg_sim *s, const phase *ph, double t)
{
    return ct_exc_rot(s, ph, m->c0, m->s0, t);
}

/* From ya at t0 (excitation e0) to yb at t1 (excitation e1). */
static void substep(const wg_sim *s, const phase *ph, const exc_rot0 *m, const double *ya,
                    double *yb, double t0, double t1, const wg_exc *e0, const wg_exc *e1)
{
    wg_exc e[3] = {*e0, exc_at(m, s, ph, 0.5 * (t0 + t1)), *e1};
    s->core->kernel(ya, yb, &s->core->kc, e, t1 - t0);
}

/* Record a located crossing in the trace (NULL: not recording). */
static ct_split *trace_open(ct_trace *tr, double tstate, double tnext, const double *yc,
                            const double *vc)
{
    if (!tr || tr->n == CT_MAX_SPLITS)
        return NULL;
    ct_split *sp = &tr->sp[tr->n++];
    sp->t_state = tstate;
    sp->t_next = tnext;
    memcpy(sp->yc, yc, sizeof sp->yc);
    memcpy(sp->vc, vc, sizeof sp->vc);
    sp->n = 0;
    return sp;
}

static void trace_switch(ct_split *sp, int contact, int from, int to)
{
    if (!sp)
        return;
    sp->contact[sp->n] = contact;
    sp->zone_from[sp->n] = from;
    sp->zone_to[sp->n++] = to;
}

/* Integrate [0, h] from y0 into y1 with the zones of the kinked contacts
 * (c > 0) locked between located crossings; y1 holds the unsplit trial
 * step on entry. Crossings of smooth contacts (c = 0) are interpolated.
 * Appends events; leaves s->core->zone as at the end of the step. */
void ct_split_step(wg_sim *s, const phase *ph, const double *y0, double *y1, double h,
                       evbuf *b)
{
    double ya[WG_NSTATE_MAX], yc[WG_NSTATE_MAX];
    double qa[WG_NCONTACT], va[WG_NCONTACT], qb[WG_NCONTACT], vb[WG_NCONTACT];
    int nc = ct_ncontacts(s);
    double t = 0.0;
    const exc_rot0 m = exc_rot0_of(s, ph);
    /* the excitation at t, at h, at the crossing tc a substep ended at;
     * outside a ramp (one phase law, one h) those at 0 and h kept per k */
    wg_exc ea, eh, ec;
    ct_psi0 *z = &s->core->psi0[s->k];
    if (!s->ramp.active && z->gen == s->core->exc_gen) {
        ea = z->e0, eh = z->eh;
    } else {
        ea = exc_at(&m, s, ph, 0.0), eh = exc_at(&m, s, ph, h);
        if (!s->ramp.active)
            z->e0 = ea, z->eh = eh, z->gen = s->core->exc_gen;
    }
    memcpy(ya, y0, sizeof ya);
    memcpy(yc, y0, sizeof yc);
    double qc[WG_NCONTACT], vc[WG_NCONTACT], tstate = 0.0;
    unsigned left; /* the contacts y1 has out of their zones, as of the last pass */
    for (int splits = 0;; splits++) {
        if (splits > 0 && tstate == t) { /* ya = yc was evaluated there already */
            memcpy(qa, qc, sizeof qa);
            memcpy(va, vc, sizeof va);
        } else {
            ct_contacts(s, ya, &ea, qa, va);
        }
        ct_contacts(s, y1, &eh, qb, vb);
        int first = -1, dir = 0;
        double tfirst = 2.0, thr = 0.0;
        left = ct_left(s, qb, nc); /* the others keep their zones */
        for (unsigned lm = left; lm; lm &= lm - 1) {
            const int j = __builtin_ctz(lm);
            double c = ct_threshold(s, j), th;
            int z1 = ct_zone(qb[j], c), z = s->core->zone[j], d = z1 > z ? 1 : -1;
            if (z1 == z || c == 0.0)
                continue;
            herm H = {qa[j], qb[j], va[j] * (h - t), vb[j] * (h - t)};
            transition(z, d, c, &th);
            double tj = herm_root(&H, th);
            if (tj < tfirst) {
                tfirst = tj;
                first = j;
                thr = th;
                dir = d;
            }
        }
        if (first < 0 || splits == MAX_SPLITS || tfirst >= 1.0)
            break; /* none, too many, or one exactly at h: interpolated below */
        /* step to the crossing, then refine it by Newton on the coordinate */
        double tc = t + tfirst * (h - t);
        for (int it = 0; it < 3; it++) {
            ec = exc_at(&m, s, ph, tc);
            substep(s, ph, &m, ya, yc, t, tc, &ea, &ec);
            tstate = tc;
            ct_contacts(s, yc, &ec, qc, vc);
            double r = qc[first] - thr;
            if (fabs(r) <= 1e-13 * (1.0 + fabs(thr)) || vc[first] == 0.0)
                break;
            double tn = tc - r / vc[first];
            if (!(tn > t && tn < h))
                break;
            tc = tn;
        }
        int kind = transition(s->core->zone[first], dir, thr >= 0 ? thr : -thr, &thr);
        ev_push(b, s, s->tau + tc, first, kind, vc[first]);
        ct_split *rec = trace_open(s->core->trace, tstate, tc, yc, vc);
        trace_switch(rec, first, s->core->zone[first], s->core->zone[first] + dir);
        s->core->zone[first] += dir;
        ct_set_lock(s, first, s->core->zone[first]);
        s->nsplit++;
        /* Contacts at their boundary at the same instant switch in the same
         * split (a body's three bearing axes share k and xi and cross
         * together to ~1e-13): one split, not three. */
        for (unsigned lm = left; lm; lm &= lm - 1) {
            const int j = __builtin_ctz(lm);
            double c = ct_threshold(s, j), th;
            int z1 = ct_zone(qb[j], c), z = s->core->zone[j], d = z1 > z ? 1 : -1;
            if (j == first || z1 == z || c == 0.0)
                continue;
            int kj = transition(z, d, c, &th);
            if (fabs(qc[j] - th) > 1e-9 * (1.0 + fabs(th)))
                continue;
            ev_push(b, s, s->tau + tc, j, kj, vc[j]);
            trace_switch(rec, j, s->core->zone[j], s->core->zone[j] + d);
            s->core->zone[j] += d;
            ct_set_lock(s, j, s->core->zone[j]);
        }
        memcpy(ya, yc, sizeof ya);
        ea = tc == tstate ? ec : exc_at(&m, s, ph, tc); /* Newton ran out: tc is past tstate */
        t = tc;
        substep(s, ph, &m, ya, y1, t, h, &ea, &eh);
    }
    /* smooth contacts, and any left after MAX_SPLITS: interpolate over the
     * last piece (qb: y1's contacts, and left, from the pass that ended the
     * loop, which switched no zone after it) */
    for (unsigned lm = left; lm; lm &= lm - 1) {
        const int j = __builtin_ctz(lm);
        int z1 = ct_zone(qb[j], ct_threshold(s, j));
        if (z1 != s->core->zone[j]) {
            herm H = {qa[j], qb[j], va[j] * (h - t), vb[j] * (h - t)};
            ct_interpolate(s, b, j, s->core->zone[j], z1, &H, t, h - t);
            s->core->zone[j] = z1;
            ct_set_lock(s, j, z1);
        }
    }
}


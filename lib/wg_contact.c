/* wg_contact.c - contacts of the running model: coordinates and zones of
 * the mesh and the six bearings, the phase law within a step, crossings
 * located on a contact's Hermite interpolant, contact events, and the
 * rk4-event step split at located dead-zone crossings. */
#include "internal.h"

#include <math.h>
#include <string.h>

#define MAX_SPLITS CT_MAX_SPLITS

void ct_phase_at(const phase *ph, double t, double *psi, double *om)
{
    if (t <= ph->tr) {
        *psi = ph->psi0 + t * (ph->om0 + 0.5 * ph->r * t);
        *om = ph->om0 + ph->r * t;
    } else {
        double pe = ph->psi0 + ph->tr * (ph->om0 + 0.5 * ph->r * ph->tr);
        *psi = pe + ph->om1 * (t - ph->tr);
        *om = ph->om1;
    }
}

/* Excitation at sub-step time t: one sine and cosine of psi, the three
 * phase offsets applied by rotation (wg_exc_eval's formula, 2 libm calls
 * instead of 4). */
void ct_exc_at(const wg_sim *s, const phase *ph, double t, wg_exc *e)
{
    double psi, om;
    ct_phase_at(ph, t, &psi, &om);
    const double *v = s->p.v, (*r)[2] = s->core->kc.rot;
    double c = cos(psi), sn = sin(psi);
    e->kp = 1.0 + v[WG_P_K_A] * (c * r[0][0] - sn * r[0][1]);
    e->te = v[WG_P_E_M] * (c * r[1][0] - sn * r[1][1]);
    e->dte = v[WG_P_E_M] * om * (sn * r[1][0] + c * r[1][1]);
    e->fx = v[WG_P_F_M] + v[WG_P_F_E] * (c * r[2][0] - sn * r[2][1]);
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

/* The excitation at the sub-step times of one split step, each time
 * evaluated once: the same times recur (the step's end at every pass, the
 * crossing a substep ends at and the next one starts from, the contacts
 * there), and ct_exc_at costs a sine and a cosine. A plain step's two ends
 * are also kept across steps (ct_ends: a periodic orbit splits at the same
 * k every period). The same bits. */
enum { EXC_MEMO = 8 };
typedef struct exc_memo {
    double t[EXC_MEMO];
    wg_exc e[EXC_MEMO];
    int n, next;
    ct_ends *ends; /* plain step k's (NULL in a ramp) */
    double h;      /* its length */
} exc_memo;

static wg_exc exc_at(exc_memo *m, const wg_sim *s, const phase *ph, double t)
{
    for (int i = 0; i < m->n; i++)
        if (m->t[i] == t)
            return m->e[i];
    int i = m->next;
    m->next = (i + 1) % EXC_MEMO;
    m->n += m->n < EXC_MEMO;
    m->t[i] = t;
    int end = t == 0.0 ? 0 : t == m->h ? 1 : -1;
    if (m->ends && end >= 0 && m->ends->gen[end] == s->core->ends_gen) {
        m->e[i] = m->ends->e[end];
        return m->e[i];
    }
    ct_exc_at(s, ph, t, &m->e[i]);
    if (m->ends && end >= 0) {
        m->ends->e[end] = m->e[i];
        m->ends->gen[end] = s->core->ends_gen;
    }
    return m->e[i];
}

static void substep(const wg_sim *s, const phase *ph, exc_memo *m, const double *ya,
                    double *yb, double t0, double t1)
{
    wg_exc e[3] = {exc_at(m, s, ph, t0), exc_at(m, s, ph, 0.5 * (t0 + t1)), exc_at(m, s, ph, t1)};
    s->core->kernel(ya, yb, &s->core->kc, e, t1 - t0);
}

static void contacts_at(const wg_sim *s, const phase *ph, exc_memo *m, const double *y,
                        double t, double *q, double *v)
{
    wg_exc e = exc_at(m, s, ph, t);
    ct_contacts(s, y, &e, q, v);
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
    /* a plain step: h = s->h from psi0 = wg_sim_psi(s) at constant omega */
    exc_memo m = {.n = 0, .ends = s->ramp.active ? NULL : &s->core->ends[s->k], .h = h};
    memcpy(ya, y0, sizeof ya);
    memcpy(yc, y0, sizeof yc);
    double qc[WG_NCONTACT], vc[WG_NCONTACT], tstate = 0.0;
    for (int splits = 0;; splits++) {
        if (splits > 0 && tstate == t) { /* ya = yc was evaluated there already */
            memcpy(qa, qc, sizeof qa[0] * (size_t)nc);
            memcpy(va, vc, sizeof va[0] * (size_t)nc);
        } else {
            contacts_at(s, ph, &m, ya, t, qa, va);
        }
        contacts_at(s, ph, &m, y1, h, qb, vb);
        int first = -1, dir = 0;
        double tfirst = 2.0, thr = 0.0;
        for (int j = 0; j < nc; j++) {
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
        if (first < 0 || splits == MAX_SPLITS)
            break;
        /* step to the crossing, then refine it by Newton on the coordinate */
        double tc = t + tfirst * (h - t);
        for (int it = 0; it < 3; it++) {
            substep(s, ph, &m, ya, yc, t, tc);
            tstate = tc;
            contacts_at(s, ph, &m, yc, tc, qc, vc);
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
        for (int j = 0; j < nc; j++) {
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
        t = tc;
        substep(s, ph, &m, ya, y1, t, h);
    }
    /* smooth contacts, and any left after MAX_SPLITS: interpolate over the
     * last piece (qb: y1's contacts, from the pass that ended the loop) */
    for (int j = 0; j < nc; j++) {
        int z1 = ct_zone(qb[j], ct_threshold(s, j));
        if (z1 != s->core->zone[j]) {
            herm H = {qa[j], qb[j], va[j] * (h - t), vb[j] * (h - t)};
            ct_interpolate(s, b, j, s->core->zone[j], z1, &H, t, h - t);
            s->core->zone[j] = z1;
            ct_set_lock(s, j, z1);
        }
    }
}


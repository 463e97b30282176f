/* wg_shoot.c - the period-n map of the rk4-event stepper with its monodromy
 * matrix from the variational equations (see wg_shoot.h).
 *
 * The state is advanced by wg_sim_run itself, one step at a time, with the
 * sim's split trace switched on (internal.h): the variational equations
 * then replay that step with the same excitation entries, the same pieces
 * [0, t1], [t1', t2], ..., [tk', h] and the same zone locks, and get the
 * saltation matrix at each recorded crossing. */
#include "wormgear/wg_shoot.h"
#include "wormgear/wg_regime.h"
#include "wormgear/wg_status.h"
#include "internal.h"

#include <math.h>
#include <string.h>

enum { NS = 14 }; /* consistent-form state */

/* The linear part the kernels integrate, for the variational equations. */
typedef struct vctx {
    const wg_kcoef *K;
    int mb, bj, ka; /* which dead zones are kinked, and whether k_p varies */
    int bear;       /* bearings move (else only s, as the torsional kernels) */
    int d;          /* active columns */
} vctx;

int wg_orbit_dim(const wg_sim *s, int *idx)
{
    if (s->cfg.model == WG_MODEL_CONSISTENT && !(s->core->kflags & KF_BEAR)) {
        idx[0] = 6;
        idx[1] = 13;
        return 2;
    }
    for (int i = 0; i < s->nstate; i++)
        idx[i] = i;
    return s->nstate;
}

/* out = A z for one column: A the Jacobian of the zone-locked RHS with
 * mesh stiffness kp and lock weights w (mesh, then the six bearings). */
static void jac_col(const vctx *V, double kp, const double *w, const double *z, double *out)
{
    const wg_kcoef *K = V->K;
    double X = z[6], Vn = z[13];
    for (int i = 0; i < 6 && V->bear; i++) {
        X += K->c[i] * z[i];
        Vn += K->c[i] * z[7 + i];
    }
    double F = K->dp * Vn + (V->ka ? kp : 1.0) * (V->mb ? w[0] : 1.0) * X;
    memset(out, 0, sizeof(double) * NS);
    for (int i = 0; i < 6 && V->bear; i++) {
        out[i] = z[7 + i];
        out[7 + i] = -K->d[i] * z[7 + i] - K->k[i] * (V->bj ? w[1 + i] : 1.0) * z[i] - K->m[i] * F;
    }
    out[6] = z[13];
    out[13] = -K->d[6] * z[13] - F;
}

/* The zone-locked RHS f(y) with locks (w, zc), as the kernels compute it. */
static void rhs_locked(const vctx *V, const wg_exc *e, const double *w, const double *zc,
                       const double *y, double *f)
{
    const wg_kcoef *K = V->K;
    double xn = y[6] - e->te, dxn = y[13] + e->dte;
    for (int i = 0; i < 6 && V->bear; i++) {
        xn += K->c[i] * y[i];
        dxn += K->c[i] * y[7 + i];
    }
    double g = V->mb ? w[0] * xn - zc[0] : xn;
    double F = K->dp * dxn + (V->ka ? e->kp : 1.0) * g;
    memset(f, 0, sizeof(double) * NS);
    for (int i = 0; i < 6 && V->bear; i++) {
        double gb = V->bj ? w[1 + i] * y[i] - zc[1 + i] : y[i];
        f[i] = y[7 + i];
        f[7 + i] = -K->d[i] * y[7 + i] - K->k[i] * gb - K->m[i] * F;
    }
    f[6] = y[13];
    f[13] = (e->fx - F) - K->d[6] * y[13];
}

/* Y (NS x d, column-major) <- RK4 step of Y' = A(t) Y over h with the
 * excitation at the piece's start, middle and end (the kernels' stages). */
static void var_piece(const vctx *V, const wg_exc e[3], double h, const double *w, double *Y)
{
    double k1[NS], k2[NS], k3[NS], k4[NS], zt[NS];
    for (int j = 0; j < V->d; j++) {
        double *z = Y + j * NS;
        jac_col(V, e[0].kp, w, z, k1);
        for (int i = 0; i < NS; i++)
            zt[i] = z[i] + 0.5 * h * k1[i];
        jac_col(V, e[1].kp, w, zt, k2);
        for (int i = 0; i < NS; i++)
            zt[i] = z[i] + 0.5 * h * k2[i];
        jac_col(V, e[1].kp, w, zt, k3);
        for (int i = 0; i < NS; i++)
            zt[i] = z[i] + h * k3[i];
        jac_col(V, e[2].kp, w, zt, k4);
        for (int i = 0; i < NS; i++)
            z[i] += h / 6.0 * ((k1[i] + k4[i]) + 2.0 * (k2[i] + k3[i]));
    }
}

/* Gradient n of contact j's coordinate (x_n = c . q + s - te, or a bearing). */
static void contact_normal(const vctx *V, int j, double *n)
{
    memset(n, 0, sizeof(double) * NS);
    if (j == WG_C_MESH) {
        for (int i = 0; i < 6 && V->bear; i++)
            n[i] = V->K->c[i];
        n[6] = 1.0;
    } else {
        n[j - 1] = 1.0;
    }
}

/* The ODE's saltation at a recorded crossing, contact by contact (several
 * contacts at their boundary at the same instant switch in the same split):
 * S = I + (f+ - f-) n^T / v with f- and f+ the RHS under the locks before
 * and after, v = dq/dt at the crossing. The vector field is continuous
 * across every dead zone, so S - I is of the order of the crossing's
 * Newton residual: its largest entry goes to o->salt_ode, and S is applied
 * only for WG_MONODROMY_FLOW. Updates the locks and the crossing counts. */
static void saltation_ode(const vctx *V, const wg_sim *s, const wg_exc *e, const ct_split *sp,
                          double *w, double *zc, double *Y, wg_orbit *o, int apply)
{
    for (int c = 0; c < sp->n; c++) {
        int j = sp->contact[c];
        double fm[NS], fp[NS], n[NS], v = sp->vc[j];
        rhs_locked(V, e, w, zc, sp->yc, fm);
        w[j] = sp->zone_to[c] != 0 ? 1.0 : 0.0;
        zc[j] = sp->zone_to[c] * ct_threshold(s, j);
        rhs_locked(V, e, w, zc, sp->yc, fp);
        o->ncross[j]++;
        o->crossings++;
        if (v == 0.0)
            continue;
        contact_normal(V, j, n);
        for (int i = 0; i < NS; i++) {
            fp[i] = (fp[i] - fm[i]) / v;
            for (int k = 0; k < NS; k++)
                o->salt_ode = dmax(o->salt_ode, fabs(fp[i] * n[k]));
        }
        for (int col = 0; apply && col < V->d; col++) {
            double *z = Y + col * NS, nz = 0.0;
            for (int k = 0; k < NS; k++)
                nz += n[k] * z[k];
            for (int i = 0; i < NS; i++)
                z[i] += fp[i] * nz;
        }
    }
}

/* Excitation at a piece's start, middle and end (as substep in wg_contact.c). */
static void exc3(const wg_sim *s, const phase *ph, double t0, double t1, wg_exc e[3])
{
    ct_exc_at(s, ph, t0, &e[0]);
    ct_exc_at(s, ph, 0.5 * (t0 + t1), &e[1]);
    ct_exc_at(s, ph, t1, &e[2]);
}

/* y <- one RK4 step of the locked RHS over [t0, t1] (the kernels' stages). */
static void state_piece(const wg_sim *s, const vctx *V, const phase *ph, double t0, double t1,
                        const double *w, const double *zc, double *y)
{
    wg_exc e[3];
    double k[4][NS], yt[NS], h = t1 - t0;
    static const double a[3] = {0.5, 0.5, 1.0};
    exc3(s, ph, t0, t1, e);
    rhs_locked(V, &e[0], w, zc, y, k[0]);
    for (int st = 1; st < 4; st++) {
        for (int i = 0; i < NS; i++)
            yt[i] = y[i] + a[st - 1] * h * k[st - 1][i];
        rhs_locked(V, &e[(st + 1) / 2], w, zc, yt, k[st]);
    }
    for (int i = 0; i < NS; i++)
        y[i] += h / 6.0 * ((k[0][i] + k[3][i]) + 2.0 * (k[1][i] + k[2][i]));
}

/* Contact j's coordinate at state y and time t of the phase law. */
static double contact_q(const wg_sim *s, const vctx *V, const phase *ph, int j, double t,
                        const double *y)
{
    if (j != WG_C_MESH)
        return y[j - 1];
    wg_exc e;
    ct_exc_at(s, ph, t, &e);
    double x = y[6] - e.te;
    for (int i = 0; i < 6 && V->bear; i++)
        x += V->K->c[i] * y[i];
    return x;
}

/* The map's saltation, pending until the piece after the crossing is
 * integrated: Y <- Y - g a, a = n^T Y_left / v (one row entry per column). */
typedef struct pending {
    int on;
    double g[NS], a[NS];
} pending;

/* The saltation of the discrete map at split sp: the pieces [ta, ts] (locks
 * wb, zb) and [tn, tb] (locks wa, za) from ya, differentiated in the split
 * time by central differences: g = d/dt of their composition, v = d/dt of
 * the crossing contact's coordinate at the end of the first. This is
 * S = I + (f+ - f-) n^T / v with the one-sided velocities of the RK4 pieces
 * instead of the ODE's, so the product is the derivative of the map the
 * stepper computes (the split time moves with the state). */
static void saltation_map(const wg_sim *s, const vctx *V, const phase *ph, const double *ya,
                          double ta, const ct_split *sp, double tb, const double *wz[4],
                          const double *Y, pending *pd, wg_orbit *o)
{
    int j = sp->contact[0];
    double ts = sp->t_state, tn = sp->t_next, q[2], yr[2][NS], n[NS];
    double dt = dmin(1e-6 * s->h, 0.5 * dmin(ts - ta, tb - tn));
    pd->on = 0;
    if (!(dt > 1e-9 * s->h))
        return; /* a crossing at a piece's very end: S = I */
    for (int k = 0; k < 2; k++) {
        double sg = k ? dt : -dt;
        memcpy(yr[k], ya, sizeof yr[k]);
        state_piece(s, V, ph, ta, ts + sg, wz[0], wz[1], yr[k]);
        q[k] = contact_q(s, V, ph, j, ts + sg, yr[k]);
        state_piece(s, V, ph, tn + sg, tb, wz[2], wz[3], yr[k]);
    }
    double v = (q[1] - q[0]) / (2.0 * dt);
    if (v == 0.0)
        return;
    contact_normal(V, j, n);
    for (int i = 0; i < NS; i++) {
        pd->g[i] = (yr[1][i] - yr[0][i]) / (2.0 * dt);
        o->salt_map = dmax(o->salt_map, fabs(pd->g[i] / v));
    }
    for (int col = 0; col < V->d; col++) {
        double nz = 0.0;
        for (int k = 0; k < NS; k++)
            nz += n[k] * Y[col * NS + k];
        pd->a[col] = nz / v;
    }
    pd->on = 1;
}

static void apply_pending(const vctx *V, const pending *pd, double *Y)
{
    for (int col = 0; pd->on && col < V->d; col++)
        for (int i = 0; i < NS; i++)
            Y[col * NS + i] -= pd->g[i] * pd->a[col];
}


/* Extremes of every contact coordinate over a step (as after_step does
 * for x_n: the Hermite extremum when the rate changes sign, and the ends). */
static void extremes(wg_orbit *o, int nc, const double *q0, const double *v0, const double *q1,
                     const double *v1, double h)
{
    for (int j = 0; j < nc; j++) {
        if ((v0[j] < 0) != (v1[j] < 0)) {
            herm H = {q0[j], q1[j], v0[j] * h, v1[j] * h};
            if (v0[j] < 0)
                o->qmin[j] = dmin(o->qmin[j], herm_min(&H));
            else
                o->qmax[j] = dmax(o->qmax[j], herm_max(&H));
        }
        o->qmin[j] = dmin(o->qmin[j], q1[j]);
        o->qmax[j] = dmax(o->qmax[j], q1[j]);
    }
}

/* One step of the sim with its variational replay: the pieces between the
 * recorded splits, each with the locks in force, and a saltation at each
 * split. */
static int step(wg_sim *s, const vctx *V, int kind, double *Y, wg_orbit *o)
{
    double w[WG_NCONTACT], zc[WG_NCONTACT], q0[WG_NCONTACT], v0[WG_NCONTACT], y0[NS];
    memcpy(w, s->core->kc.w, sizeof w);
    memcpy(zc, s->core->kc.zc, sizeof zc);
    memcpy(q0, s->core->q, sizeof q0);
    memcpy(v0, s->core->v, sizeof v0);
    memcpy(y0, s->y, sizeof y0);
    uint32_t k = s->k;
    double h = s->h, om = s->p.v[WG_P_OMEGA];
    phase ph = {wg_sim_psi(s), om, 0.0, INFINITY, om};
    ct_trace tr;
    tr.n = 0;
    s->core->trace = &tr;
    int rc = wg_sim_run(s, 1, NULL, NULL);
    s->core->trace = NULL;
    if (rc)
        return rc;
    const double *ya = y0;
    double ta = 0.0;
    pending pd = {0};
    for (int i = 0; i <= tr.n; i++) {
        double tb = i < tr.n ? tr.sp[i].t_state : h;
        wg_exc e[3];
        if (tr.n == 0) {
            var_piece(V, &s->core->table[2 * k], h, w, Y);
        } else {
            exc3(s, &ph, ta, tb, e);
            var_piece(V, e, tb - ta, w, Y);
        }
        apply_pending(V, &pd, Y);
        if (i == tr.n)
            break;
        const ct_split *sp = &tr.sp[i];
        double wb[WG_NCONTACT], zb[WG_NCONTACT];
        memcpy(wb, w, sizeof wb);
        memcpy(zb, zc, sizeof zb);
        saltation_ode(V, s, &e[2], sp, w, zc, Y, o, kind == WG_MONODROMY_FLOW);
        const double *wz[4] = {wb, zb, w, zc};
        if (kind == WG_MONODROMY_MAP)
            saltation_map(s, V, &ph, ya, ta, sp, i + 1 < tr.n ? tr.sp[i + 1].t_state : h, wz,
                          Y, &pd, o);
        ya = sp->yc;
        ta = sp->t_next;
    }
    extremes(o, ct_ncontacts(s), q0, v0, s->core->q, s->core->v, h);
    return WG_OK;
}

static int supported(const wg_sim *s)
{
    return s->cfg.model == WG_MODEL_CONSISTENT && s->cfg.stepper == WG_STEPPER_RK4_EVENT &&
           !s->ramp.active;
}

int wg_orbit_map(wg_sim *s, int n, int kind, const double *x, wg_orbit *o)
{
    if (!supported(s))
        return WG_EUNSUPPORTED;
    if (n < 1 || n > WG_SHOOT_NMAX || (kind != WG_MONODROMY_MAP && kind != WG_MONODROMY_FLOW))
        return WG_EINVAL;
    unsigned kf = s->core->kflags;
    o->n = n;
    o->dim = wg_orbit_dim(s, o->idx);
    o->crossings = 0;
    o->salt_ode = o->salt_map = 0.0;
    memset(o->ncross, 0, sizeof o->ncross);
    vctx V = {&s->core->kc, (kf & KF_MB) != 0, (kf & KF_BJ) != 0, (kf & KF_KA) != 0,
              (kf & KF_BEAR) != 0, o->dim};
    double Y[NS * NS];
    memset(Y, 0, sizeof Y);
    for (int j = 0; j < o->dim; j++)
        Y[j * NS + o->idx[j]] = 1.0;
    wg_sim_set_state(s, x, 0, 0.0);
    for (int j = 0; j < WG_NCONTACT; j++) /* contacts that cannot move stay at 0 */
        o->qmin[j] = o->qmax[j] = j < ct_ncontacts(s) ? s->core->q[j] : 0.0;
    int N = s->cfg.steps_per_period;
    for (int p = 0; p < n; p++) {
        memcpy(o->ysec[p], s->y, sizeof o->ysec[p]);
        o->xnsec[p] = s->core->q[WG_C_MESH];
        for (int k = 0; k < N; k++) {
            int rc = step(s, &V, kind, Y, o);
            if (rc)
                return rc;
        }
    }
    memcpy(o->y, s->y, sizeof o->y);
    for (int i = 0; i < o->dim; i++)
        for (int j = 0; j < o->dim; j++)
            o->M[i * o->dim + j] = Y[j * NS + o->idx[i]];
    return WG_OK;
}

int wg_orbit_refine(wg_sim *s, int n, double *x, double tol, int maxit, double *resid,
                    wg_orbit *o)
{
    *resid = INFINITY;
    for (int it = 0;; it++) {
        int rc = wg_orbit_map(s, n, WG_MONODROMY_MAP, x, o);
        if (rc)
            return rc;
        int d = o->dim;
        double r[WG_NSTATE_MAX], a[WG_NSTATE_MAX * WG_NSTATE_MAX], res = 0.0;
        for (int i = 0; i < d; i++) {
            r[i] = x[o->idx[i]] - o->y[o->idx[i]]; /* -(P(x) - x) */
            res = dmax(res, fabs(r[i]));
        }
        *resid = res;
        if (res <= tol)
            return WG_OK;
        if (it == maxit)
            return WG_ERANGE;
        memcpy(a, o->M, sizeof(double) * (size_t)(d * d));
        for (int i = 0; i < d; i++)
            a[i * d + i] -= 1.0;
        if ((rc = la_solve(d, a, r)))
            return rc;
        for (int i = 0; i < d; i++)
            x[o->idx[i]] += r[i];
    }
}

int wg_orbit_floquet(const wg_orbit *o, double *wr, double *wi)
{
    double a[WG_NSTATE_MAX * WG_NSTATE_MAX];
    memcpy(a, o->M, sizeof(double) * (size_t)(o->dim * o->dim));
    return wg_eig(o->dim, a, wr, wi);
}

/* wg_sim.c - the integration driver: parameters, ramps, snapshots. The step
 * loop lives in wg_sim_run.c, contacts and events in wg_contact.c. */
#include "internal.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static const char *const stepper_names[] = {"default", "rk4", "rk4-event"};

const char *wg_stepper_name(int st)
{
    return st >= WG_STEPPER_DEFAULT && st <= WG_STEPPER_RK4_EVENT ? stepper_names[st + 1] : "?";
}

int wg_stepper_lookup(const char *name)
{
    for (int i = 0; i < 3; i++)
        if (strcmp(name, stepper_names[i]) == 0)
            return i - 1;
    return -2;
}

int wg_stepper_choose(int model, int stepper, int *chosen, char *why, size_t whylen)
{
    if (stepper == WG_STEPPER_DEFAULT)
        stepper = model == WG_MODEL_PRINTED ? WG_STEPPER_RK4 : WG_STEPPER_RK4_EVENT;
    if (stepper != WG_STEPPER_RK4 && stepper != WG_STEPPER_RK4_EVENT) {
        snprintf(why, whylen, "stepper %d does not exist (default, rk4 or rk4-event)", stepper);
        return WG_ERANGE;
    }
    if (model == WG_MODEL_PRINTED && stepper == WG_STEPPER_RK4_EVENT) {
        snprintf(why, whylen, "the printed form (for comparison only) supports the rk4 stepper "
                              "only");
        return WG_EUNSUPPORTED;
    }
    *chosen = stepper;
    return WG_OK;
}


/* ---- parameters --------------------------------------------------------- */

static unsigned kflags_of(const wg_sim *s)
{
    const double *v = s->p.v;
    unsigned f = 0;
    if (v[WG_P_E_M] != 0.0)
        f |= KF_EM;
    if (v[WG_P_K_A] != 0.0)
        f |= KF_KA;
    if (v[WG_P_B] != 0.0)
        f |= KF_MB;
    if (v[WG_P_B_J] != 0.0)
        f |= KF_BJ;
    if (s->cfg.stepper == WG_STEPPER_RK4_EVENT)
        f |= KF_LOCK;
    if (!wg_params_torsional(&s->p))
        f |= KF_BEAR;
    return f;
}

void sim_coefficients(wg_sim *s)
{
    const double *v = s->p.v;
    s->core->exc_gen++; /* ct_split_step's kept excitations are stale */
    model_mesh_vectors(s->cfg.model, &s->p, s->core->kc.c, s->core->kc.m);
    for (int i = 0; i < 6; i++) {
        s->core->kc.k[i] = v[WG_P_K1X + i];
        s->core->kc.d[i] = 2.0 * v[WG_P_XI1X + i];
    }
    s->core->kc.d[6] = 2.0 * v[WG_P_XI_G];
    double M = 1.0; /* the kernels' per-call constants, once per change */
    for (int i = 0; i < 6; i++) {
        s->core->kc.cd[i] = s->core->kc.c[i] * s->core->kc.d[i];
        s->core->kc.ck[i] = s->core->kc.c[i] * s->core->kc.k[i];
        M += s->core->kc.c[i] * s->core->kc.m[i];
    }
    s->core->kc.M = M;
    s->core->kc.dp = 2.0 * v[WG_P_XI_P];
    s->core->kc.b = v[WG_P_B];
    s->core->kc.bj = v[WG_P_B_J];
    static const int phase_id[3] = {WG_P_PHI1, WG_P_PHI2, WG_P_PHI};
    for (int i = 0; i < 3; i++) {
        s->core->kc.rot[i][0] = cos(v[phase_id[i]]);
        s->core->kc.rot[i][1] = sin(v[phase_id[i]]);
    }
    for (int j = 0; j < WG_NCONTACT; j++)
        ct_set_lock(s, j, s->core->zone[j]);
    s->core->kflags = kflags_of(s);
    int printed = s->cfg.model == WG_MODEL_PRINTED;
    s->core->kernel = printed ? kernel_printed : kernel_select(s->core->kflags, s->core->isa_one);
    s->core->krun = printed ? NULL : krun_select(s->core->kflags, s->core->isa_one);
}

void sim_build_table(wg_sim *s)
{
    int n = s->cfg.steps_per_period;
    double om = s->p.v[WG_P_OMEGA];
    wg_sim_core *c = s->core;
    const double *v = s->p.v;
    c->exc_gen++;
    /* the sines and cosines again only for new phases: an omega (a sweep's
     * every point, a rig's set) or an amplitude keeps them */
    if (!c->trig_set || c->trig_phi[0] != v[WG_P_PHI1] || c->trig_phi[1] != v[WG_P_PHI2] ||
        c->trig_phi[2] != v[WG_P_PHI]) {
        for (int j = 0; j <= 2 * n; j++)
            model_exc_trig(&s->p, M_PI * j / n, c->trig[j]);
        c->trig_phi[0] = v[WG_P_PHI1], c->trig_phi[1] = v[WG_P_PHI2], c->trig_phi[2] = v[WG_P_PHI];
        c->trig_set = 1;
    }
    for (int j = 0; j <= 2 * n; j++)
        model_exc_of_trig(&s->p, c->trig[j], om, &c->table[j]);
    c->table[2 * n] = c->table[0];
    s->h = TWO_PI / (om * n);
}

/* Do a and b give the same excitation table (omega and the excitation
 * terms; wg_exc_eval reads nothing else)? */
static int same_excitation(const wg_params *a, const wg_params *b)
{
    static const int ids[] = {WG_P_OMEGA, WG_P_K_A, WG_P_PHI1, WG_P_E_M,
                              WG_P_PHI2,  WG_P_F_M, WG_P_F_E,  WG_P_PHI};
    for (unsigned i = 0; i < sizeof ids / sizeof ids[0]; i++)
        if (a->v[ids[i]] != b->v[ids[i]])
            return 0;
    return 1;
}

/* wg_rk4_hmax with a one-entry cache: a change of omega, phase, forcing
 * or clearance (what a rig changes on the fly) costs nothing. */
static double hmax_of(wg_sim *s, const wg_params *p)
{
    if (s->core->hkey_hmax > 0.0 && wg_params_same_linear(&s->core->hkey, p))
        return s->core->hkey_hmax;
    double h = wg_rk4_hmax(s->cfg.model, p);
    s->core->hkey = *p;
    s->core->hkey_hmax = h;
    return h;
}

/* Stability of N at frequency omega for parameters p. */
static int check_steps(const wg_sim *s, double hmax, double omega, char *why, size_t whylen)
{
    int n = s->cfg.steps_per_period;
    if (s->cfg.model != WG_MODEL_CONSISTENT)
        return WG_OK;
    int need = wg_min_steps(hmax, omega);
    if (n < need) {
        if (why && whylen)
            snprintf(why, whylen,
                     "%d steps per mesh period is below the RK4 stability limit at omega = %g: "
                     "need N >= %d (h <= %.6g on the fastest linear mode)",
                     n, omega, need, hmax);
        return WG_ESTABILITY;
    }
    return WG_OK;
}

static void refresh_zones(wg_sim *s)
{
    wg_exc e;
    wg_exc_eval(&s->p, wg_sim_psi(s), s->p.v[WG_P_OMEGA], &e);
    ct_contacts(s, s->y, &e, s->core->q, s->core->v);
    for (int j = 0; j < WG_NCONTACT; j++) {
        s->core->zone[j] = ct_zone(s->core->q[j], ct_threshold(s, j));
        ct_set_lock(s, j, s->core->zone[j]);
    }
}

void sim_period_start(wg_sim *s, double xn)
{
    s->core->cur.period = s->period;
    s->core->cur.min_xn = s->core->cur.max_xn = xn;
    s->core->cur.motion = s->core->zone[0] == 1 ? WG_MOTION_NO_IMPACT
                    : s->core->zone[0] == 0 ? WG_MOTION_SINGLE : WG_MOTION_DOUBLE;
    s->core->cur.impacts = 0;
    memset(s->core->cur.bimpacts, 0, sizeof s->core->cur.bimpacts);
    memset(s->core->cur.bvmax, 0, sizeof s->core->cur.bvmax);
}

int wg_sim_check_params(wg_sim *s, const wg_params *p, char *why, size_t whylen)
{
    int rc = wg_params_check(p, why, whylen);
    return rc ? rc : check_steps(s, hmax_of(s, p), p->v[WG_P_OMEGA], why, whylen);
}

int wg_sim_set_params(wg_sim *s, const wg_params *p, char *why, size_t whylen)
{
    int rc = wg_sim_check_params(s, p, why, whylen);
    if (rc)
        return rc;
    double hmax = hmax_of(s, p); /* cached by the check */
    /* the table holds: built (h > 0), for the same inputs, and no ramp has
     * moved s->p past it */
    int table_holds = s->h > 0 && !s->ramp.active && same_excitation(&s->p, p);
    s->p = *p;
    s->hmax = hmax;
    s->ramp.active = 0;
    if (wg_params_torsional(p) && s->cfg.model == WG_MODEL_CONSISTENT)
        for (int i = 0; i < 6; i++) /* rigid bearings hold at zero */
            s->y[i] = s->y[7 + i] = 0.0;
    sim_coefficients(s);
    refresh_zones(s);
    if (!table_holds) /* 2N+1 sines and cosines: skipped for a damping or stiffness */
        sim_build_table(s);
    return WG_OK;
}

int wg_sim_init(wg_sim *s, const wg_params *p, const wg_sim_config *cfg, char *why,
                size_t whylen)
{
    memset(s, 0, sizeof *s);
    int stepper, rc;
    if (cfg->model != WG_MODEL_CONSISTENT && cfg->model != WG_MODEL_PRINTED) {
        snprintf(why, whylen, "model %d does not exist (consistent or printed)", cfg->model);
        return WG_ERANGE;
    }
    if ((rc = wg_stepper_choose(cfg->model, cfg->stepper, &stepper, why, whylen)))
        return rc;
    if (cfg->steps_per_period < WG_STEPS_MIN || cfg->steps_per_period > WG_STEPS_MAX) {
        snprintf(why, whylen, "steps per period = %d out of range [%d, %d]",
                 cfg->steps_per_period, WG_STEPS_MIN, WG_STEPS_MAX);
        return WG_ERANGE;
    }
    s->cfg = *cfg;
    s->cfg.stepper = stepper;
    s->nstate = wg_model_nstate(cfg->model);
    s->core = calloc(1, sizeof *s->core);
    if (s->core) {
        s->core->table = malloc(sizeof(wg_exc) * (size_t)(2 * cfg->steps_per_period + 1));
        s->core->trig = malloc(sizeof s->core->trig[0] * (size_t)(2 * cfg->steps_per_period + 1));
        s->core->psi0 = calloc((size_t)cfg->steps_per_period, sizeof(ct_psi0)); /* none set */
        s->core->isa = kernel_isa_choose();
        s->core->isa_one = kernel_isa_one(s->core->isa);
    }
    if (!s->core || !s->core->table || !s->core->trig || !s->core->psi0) {
        wg_sim_fini(s);
        snprintf(why, whylen, "out of memory for the excitation table");
        return WG_ENOMEM;
    }
    wg_equilibrium(cfg->model, p, s->y);
    if ((rc = wg_sim_set_params(s, p, why, whylen))) {
        wg_sim_fini(s);
        return rc;
    }
    sim_period_start(s, s->core->q[0]);
    return WG_OK;
}

void wg_sim_fini(wg_sim *s)
{
    if (s->core) {
        free(s->core->table);
        free(s->core->trig);
        free(s->core->psi0);
    }
    free(s->core);
    s->core = NULL;
}

/* The checks of a ramp of parameter id of `base` from *from (NULL: from its
 * value in base) to target over dur: what wg_sim_ramp and wg_sim_restore
 * accept. *hlo receives the stability limit over the ramp. */
static int ramp_check(wg_sim *s, const wg_params *base, int id, const double *from,
                      double target, double dur, double *hlo, char *why, size_t whylen)
{
    const wg_param_info *r = wg_param_info_get(id);
    if (!r) {
        snprintf(why, whylen, "parameter id %d does not exist", id);
        return WG_EUNKNOWN;
    }
    if (!(r->flags & WG_PF_RAMP)) {
        snprintf(why, whylen, "%s cannot be ramped (geometry); use set", r->name);
        return WG_EINVAL;
    }
    char num[32], msg[256];
    if (!(dur >= WG_RAMP_TAU_MIN && dur <= WG_RAMP_TAU_MAX)) {
        snprintf(why, whylen, "ramp duration %s tau out of range [%g, %g] tau",
                 wg_num_format(dur, num, sizeof num), WG_RAMP_TAU_MIN, WG_RAMP_TAU_MAX);
        return WG_ERANGE;
    }
    wg_params start = *base, end = *base;
    if (from)
        start.v[id] = *from;
    end.v[id] = target;
    int rc = wg_params_check(&start, msg, sizeof msg);
    if (rc) {
        snprintf(why, whylen, "ramp %s: %s", from ? "from" : "start", msg);
        return rc;
    }
    if ((rc = wg_params_check(&end, msg, sizeof msg))) {
        snprintf(why, whylen, "ramp target: %s", msg);
        return rc;
    }
    if (!isfinite((target - start.v[id]) / dur)) { /* ranges and dur bound it; say so */
        snprintf(why, whylen, "ramp of %s too fast: slope not finite", r->name);
        return WG_ERANGE;
    }
    /* Stability at both ends: stiffness and omega move monotonically. The
     * start last, so a jump to it finds its limit cached. */
    double hend = hmax_of(s, &end), hcur = hmax_of(s, &start);
    *hlo = hend < hcur ? hend : hcur;
    return check_steps(s, *hlo, dmin(start.v[WG_P_OMEGA], end.v[WG_P_OMEGA]), why, whylen);
}

int wg_sim_ramp(wg_sim *s, int id, const double *from, double target, double dur, char *why,
                size_t whylen)
{
    double hlo;
    int rc = ramp_check(s, &s->p, id, from, target, dur, &hlo, why, whylen);
    if (rc)
        return rc;
    if (from && *from != s->p.v[id]) { /* the jump: valid, so it applies */
        wg_params start = s->p;
        start.v[id] = *from;
        wg_sim_set_params(s, &start, why, whylen);
    }
    s->hmax = hlo;
    s->ramp = (wg_ramp){1, id, s->p.v[id], target, s->tau, dur};
    return WG_OK;
}

void wg_sim_set_state(wg_sim *s, const double *y, uint32_t k, double tau)
{
    memcpy(s->y, y, sizeof(double) * (size_t)s->nstate);
    s->k = k % (uint32_t)s->cfg.steps_per_period;
    s->tau = tau;
    s->tau_c = 0.0;
    if (wg_params_torsional(&s->p) && s->cfg.model == WG_MODEL_CONSISTENT)
        for (int i = 0; i < 6; i++) /* rigid bearings hold at zero */
            s->y[i] = s->y[7 + i] = 0.0;
    if (s->ramp.active) { /* cancelled mid-ramp: the table is for the old values */
        s->ramp.active = 0;
        sim_coefficients(s);
        sim_build_table(s);
    }
    refresh_zones(s);
    sim_period_start(s, s->core->q[0]);
}

void wg_sim_snapshot(const wg_sim *s, wg_snapshot *w)
{
    memset(w, 0, sizeof *w);
    w->model = s->cfg.model;
    w->stepper = s->cfg.stepper;
    w->steps_per_period = s->cfg.steps_per_period;
    w->p = s->p;
    memcpy(w->y, s->y, sizeof w->y);
    w->k = s->k;
    w->tau = s->tau;
    w->tau_c = s->tau_c;
    w->period = s->period;
    w->steps = s->steps;
    w->ramp = s->ramp;
    w->cur = s->core->cur;
    w->last = s->core->last;
}

/* ---- restore: every field checked as the live path would ------------------ */

static int restore_config(const wg_sim *s, const wg_snapshot *w, char *why, size_t whylen)
{
    if (w->model == s->cfg.model && w->stepper == s->cfg.stepper &&
        w->steps_per_period == s->cfg.steps_per_period)
        return WG_OK;
    return sim_refuse(WG_ESTATE, why, whylen, "snapshot taken with model %s, stepper %s, N = %d; "
                      "this run has model %s, stepper %s, N = %d", wg_model_name(w->model),
                      wg_stepper_name(w->stepper), w->steps_per_period, wg_model_name(s->cfg.model),
                      wg_stepper_name(s->cfg.stepper), s->cfg.steps_per_period);
}

/* The ramp record as wg_sim_ramp would have left it; *hlo its stability
 * limit (unchanged without a ramp). */
static int restore_ramp(wg_sim *s, const wg_snapshot *w, double *hlo, char *why, size_t whylen)
{
    const wg_ramp *r = &w->ramp;
    char msg[256];
    if (r->active != 0 && r->active != 1)
        return sim_refuse(WG_EINVAL, why, whylen, "snapshot ramp active = %d, must be 0 or 1",
                          r->active);
    if (!r->active)
        return WG_OK;
    int rc = ramp_check(s, &w->p, r->id, &r->v0, r->v1, r->dur, hlo, msg, sizeof msg);
    return rc ? sim_refuse(rc, why, whylen, "snapshot %s", msg) : sim_ramp_now_ok(w, why, whylen);
}

static int restore_check(wg_sim *s, const wg_snapshot *w, double *hlo, char *why,
                         size_t whylen)
{
    char msg[256];
    int rc = restore_config(s, w, why, whylen);
    if (!rc)
        rc = sim_snapshot_fields_ok(w, why, whylen);
    if (!rc && (rc = wg_sim_check_params(s, &w->p, msg, sizeof msg)))
        return sim_refuse(rc, why, whylen, "snapshot: %s", msg);
    return rc ? rc : restore_ramp(s, w, hlo, why, whylen);
}

int wg_sim_restore(wg_sim *s, const wg_snapshot *w, char *why, size_t whylen)
{
    double hlo = 0.0;
    int rc = restore_check(s, w, &hlo, why, whylen);
    if (rc)
        return rc;
    wg_sim_set_params(s, &w->p, why, whylen); /* checked above: cannot fail */
    wg_sim_set_state(s, w->y, w->k, w->tau);
    s->tau_c = w->tau_c;
    s->period = w->period;
    s->steps = w->steps;
    s->core->cur = w->cur;
    s->core->last = w->last;
    if (w->ramp.active) { /* as wg_sim_ramp left it: stable at both ends */
        s->hmax = hlo;
        s->ramp = w->ramp;
    }
    return WG_OK;
}

void wg_sim_reset(wg_sim *s)
{
    /* re-derive everything from the parameters (kernel, table, h) */
    s->ramp.active = 0;
    sim_coefficients(s);
    sim_build_table(s);
    double y[WG_NSTATE_MAX];
    wg_equilibrium(s->cfg.model, &s->p, y);
    wg_sim_set_state(s, y, 0, 0.0);
    s->period = s->steps = s->nsplit = 0;
    memset(s->nevents, 0, sizeof s->nevents);
    sim_period_start(s, s->core->q[0]);
}

double wg_sim_psi(const wg_sim *s) { return TWO_PI * s->k / s->cfg.steps_per_period; }
double wg_sim_omega(const wg_sim *s) { return s->p.v[WG_P_OMEGA]; }

double wg_sim_step_tau(const wg_sim *s)
{
    return TWO_PI / (s->p.v[WG_P_OMEGA] * s->cfg.steps_per_period);
}

double wg_sim_xn(const wg_sim *s) { return s->core->q[WG_C_MESH]; }

void wg_sim_outputs(const wg_sim *s, wg_outputs *o)
{
    wg_exc e;
    /* Without a ramp the table holds this phase's excitation: its entry 2k
     * is wg_exc_eval at pi 2k / N, which is wg_sim_psi's 2 pi k / N to the
     * bit. In a ramp the parameters move past the table. */
    if (!s->ramp.active)
        e = s->core->table[2 * s->k];
    else
        wg_exc_eval(&s->p, wg_sim_psi(s), s->p.v[WG_P_OMEGA], &e);
    wg_outputs_eval(s->cfg.model, &s->p, &e, s->y, o);
}

void wg_sim_angles(const wg_sim *s, double th[2])
{
    /* an on_step sink sees the step that ends a period before it is counted */
    wg_angles(s->cfg.model, &s->p, s->period + (uint64_t)s->core->wrap_pending, wg_sim_psi(s),
              s->y, th);
}

const char *wg_sim_isa_name(const wg_sim *s)
{
    return s->cfg.model == WG_MODEL_PRINTED ? "baseline" : kernel_isa_name(s->core->isa_one);
}

const char *wg_sim_kernel_name(const wg_sim *s, char *buf, size_t len)
{
    if (s->cfg.model == WG_MODEL_PRINTED) {
        snprintf(buf, len, "printed");
        return buf;
    }
    unsigned f = s->core->kflags;
    snprintf(buf, len, "%s%s%s%s%s%s", f & KF_BEAR ? "full" : "torsional",
             (f & KF_BEAR) && (f & KF_BJ) ? "+bj" : "", f & KF_MB ? "+b" : "",
             f & KF_KA ? "+ka" : "", f & KF_EM ? "+em" : "", f & KF_LOCK ? "+locked" : "");
    return buf;
}

/* wg_shoot.h - periodic orbits of the rk4-event map and their monodromy.
 *
 * P^n is n mesh periods of wg_sim_run from psi = 0 (the very map a sweep or
 * the daemon iterates). Alongside the state, wg_orbit_map integrates the
 * variational equations Y' = A(t) Y with the same RK4 stages, the same step
 * and the same split times as the state, switching the Jacobian A at every
 * dead-zone crossing the stepper located and applying the saltation matrix
 * S = I + (f+ - f-) n^T / (dq/dt) there. Inside a zone the locked system is
 * affine in the state, so the RK4 stages give the exact derivative of each
 * piece; the saltation carries the dependence of the split times on the
 * state (docs/analysis.md, "Monodromy"). Consistent form, rk4-event
 * stepper, constant parameters. No allocation. */
#ifndef WG_SHOOT_H
#define WG_SHOOT_H

#include "wg_sim.h"

enum { WG_SHOOT_NMAX = 32 }; /* longest period of an orbit */

/* One application of P^n with everything measured along the way. */
typedef struct wg_orbit {
    int n;                          /* periods */
    int dim;                        /* active coordinates: 14, or 2 (s, s') if torsional */
    int idx[WG_NSTATE_MAX];         /* their indices in the state vector */
    double y[WG_NSTATE_MAX];        /* P^n(x), full state */
    double M[WG_NSTATE_MAX * WG_NSTATE_MAX]; /* dim x dim row-major: dP_i/dx_j (active) */
    double ysec[WG_SHOOT_NMAX][WG_NSTATE_MAX]; /* state at the section starting period k */
    double xnsec[WG_SHOOT_NMAX];    /* x_n at those sections */
    double qmin[WG_NCONTACT], qmax[WG_NCONTACT]; /* extremes of each contact coordinate
                                       (x_n, then x1 .. z2), Hermite-refined as wg_period's */
    int ncross[WG_NCONTACT];        /* located crossings of each contact over the orbit */
    long crossings;                 /* all of them (saltation matrices applied) */
    double salt_ode;                /* largest |S - I| entry of the ODE's saltation */
    double salt_map;                /* largest |g / v| of the map's saltation */
} wg_orbit;

/* Which derivative wg_orbit_map integrates. */
enum wg_monodromy {
    WG_MONODROMY_MAP = 0,  /* the derivative of P^n itself: saltation with the RK4
                              pieces' one-sided velocities (the split times move
                              with the state) - for Newton and the multipliers */
    WG_MONODROMY_FLOW = 1  /* the flow's monodromy: saltation with the ODE's f-, f+
                              (the identity here, the field being continuous);
                              differs from MAP by the discretisation error */
};

/* Active coordinates of sim's model: writes idx, returns their number. */
int wg_orbit_dim(const wg_sim *sim, int *idx);

/* Apply P^n (1 <= n <= WG_SHOOT_NMAX) to the state x (nstate values) at
 * psi = 0 with sim's current parameters, filling *o with the monodromy of
 * `kind` (enum wg_monodromy). The sim's state, time and statistics are
 * overwritten (it ends at P^n(x)). WG_OK; WG_EUNSUPPORTED (printed form,
 * rk4 stepper, a ramp in progress), WG_EINVAL (n or kind out of range) or
 * WG_ENONFINITE from the run. */
int wg_orbit_map(wg_sim *sim, int n, int kind, const double *x, wg_orbit *o);

/* Newton on P^n(x) = x at fixed parameters with the variational monodromy:
 * x <- x - (M - I)^-1 (P^n(x) - x) until the max-norm residual is <= tol, at
 * most maxit iterations; finds unstable orbits too. *o holds the map at the
 * final x (so o->M is the monodromy there), *resid its residual. WG_OK,
 * WG_ERANGE (no convergence, or M - I singular) or a wg_orbit_map error. */
int wg_orbit_refine(wg_sim *sim, int n, double *x, double tol, int maxit, double *resid,
                    wg_orbit *o);

/* Floquet multipliers of o: eigenvalues of o->M (o->dim of them) sorted by
 * decreasing modulus. WG_OK or WG_ENONFINITE (QR did not converge). */
int wg_orbit_floquet(const wg_orbit *o, double *wr, double *wi);

#endif

/* wg_model.h - the worm-gear equations of motion (MODEL.md sections 1-2).
 *
 * State vector y (dimensionless, lengths / b_c, time tau = omega_n t):
 *   consistent form: y[0..6] = x1 y1 z1 x2 y2 z2 s, y[7..13] their velocities;
 *   printed form:    y[0..7] = x1 y1 z1 x2 y2 z2 th1 th2, y[8..15] velocities.
 * The excitation phase psi is kept outside y (see wg_sim.h). */
#ifndef WG_MODEL_H
#define WG_MODEL_H

#include <stdint.h>

#include "wg_param.h"

enum { WG_NDOF_MAX = 8, WG_NSTATE_MAX = 16 };

enum wg_model_kind {
    WG_MODEL_CONSISTENT = 0, /* 7 DOF + phase, the default (MODEL.md s2) */
    WG_MODEL_PRINTED = 1     /* 8 DOF as printed, for comparison only (s1) */
};

/* Contacts that have a dead zone: the mesh at +-b, each bearing at +-b_j. */
enum wg_contact {
    WG_C_MESH, WG_C_X1, WG_C_Y1, WG_C_Z1, WG_C_X2, WG_C_Y2, WG_C_Z2, WG_NCONTACT
};
enum { WG_NBEARING = WG_NCONTACT - WG_C_X1 }; /* the bearing contacts, x1 ... z2 */

/* Contact event kinds (MODEL.md s5), for the mesh and for each bearing. */
enum wg_event_kind {
    WG_EV_SEPARATION,   /* crossing +c downward */
    WG_EV_DRIVE_IMPACT, /* crossing +c upward */
    WG_EV_BACK_IMPACT,  /* crossing -c downward */
    WG_EV_BACK_RELEASE, /* crossing -c upward */
    WG_NEVKIND
};

/* Motion class of one mesh period (gear-rattle classes). */
enum wg_motion { WG_MOTION_NO_IMPACT, WG_MOTION_SINGLE, WG_MOTION_DOUBLE };

/* Excitation at one phase: k_p, TE term e_m cos(psi+phi2), its rate
 * e_m omega sin(psi+phi2), and the torque term f_m + f_e cos(psi+phi). */
typedef struct wg_exc {
    double kp, te, dte, fx;
} wg_exc;

/* Derived mesh and bearing quantities at one state. Bearing forces are in
 * units of the mesh force (K_m b_c): (k g(x) + 2 xi x') / mu. */
typedef struct wg_outputs {
    double xn, dxn, F;
    double fb[6]; /* x1 y1 z1 x2 y2 z2 */
} wg_outputs;

/* Names for printing: "consistent", "mesh", "drive_impact", "single_sided" ... */
const char *wg_model_name(int model);
const char *wg_contact_name(int contact);
const char *wg_event_name(int kind);
const char *wg_motion_name(int motion);

/* The model named name ("consistent" or "printed"), or -1. */
int wg_model_lookup(const char *name);

/* Number of state variables of a model (14 or 16). */
int wg_model_nstate(int model);

/* The dead-zone function g(x; c) of MODEL.md s2 (c >= 0). */
double wg_deadzone(double x, double c);

/* Excitation at phase psi (rad) and meshing frequency omega. */
void wg_exc_eval(const wg_params *p, double psi, double omega, wg_exc *e);

/* Reference right-hand side dy = f(y) for either model, unspecialised and
 * unoptimised: the definition the fast kernels are tested against. */
void wg_rhs(int model, const wg_params *p, const wg_exc *e, const double *y, double *dy);

/* Mesh displacement, velocity, force and bearing forces at state y. */
void wg_outputs_eval(int model, const wg_params *p, const wg_exc *e, const double *y,
                     wg_outputs *o);

/* Rotation angles of the worm (th[0] = theta1) and the wheel (th[1] =
 * theta2) in rad, wrapped to [0, 2 pi): derived outputs (MODEL.md s2), each
 * in the sense its body turns in operation and zero at the start of the run.
 * The rigid rotation is the mesh phase over the body's teeth,
 * (2 pi (period mod z) + psi) / z with `period` the completed mesh periods;
 * the elastic part splits the torsional coordinate s as the mesh force
 * accelerates the two inertias, theta1_e = s (a1/j1) / (rho1 D) and
 * theta2_e = -s (a3/j2) / (rho2 D), D = a1^2/j1 + a3^2/j2, so that
 * a1 rho1 theta1_e - a3 rho2 theta2_e = s (the worm leads and the wheel lags
 * under load). The printed form's th1, th2 give th1/rho1 and -th2/rho2. Uses
 * only the body rows z1, z2, rho1, rho2, j1, j2 and a1, a3 of p. */
void wg_angles(int model, const wg_params *p, uint64_t period, double psi, const double *y,
               double th[2]);

/* True when the scene has rigid bearings (mu1 = mu2 = 0): only s moves. */
int wg_params_torsional(const wg_params *p);

/* Static equilibrium under the mean load (MODEL.md s4): x_n = b + f_m at
 * psi = 0, bearings deflected by the static mesh force, zero velocities. */
void wg_equilibrium(int model, const wg_params *p, double *y);

/* Largest step h for which classical RK4 is stable on the model's linear
 * part in its stiffest configuration (every contact engaged, k_p = 1 + k_a),
 * the smallest h at which some h*lambda_i (lambda_i the eigenvalues of the
 * linear part) leaves RK4's stability region |R(z)| <= 1 + 1e-8; about
 * 30 us. Consistent form only; returns 0 for the printed form (it has
 * unstable modes by design). */
double wg_rk4_hmax(int model, const wg_params *p);

/* True when a and b have the same linear part, so wg_rk4_hmax gives the
 * same answer: same damping, k_a, geometry, mass ratios and bearings (the
 * frequency, phases, forcing, TE and clearances do not matter). For caches. */
int wg_params_same_linear(const wg_params *a, const wg_params *b);

/* Smallest steps per mesh period N for which h = 2 pi/(omega N) <= hmax. */
int wg_min_steps(double hmax, double omega);

#endif

/* units.h - dimensionless numbers in physical units, for what the clients
 * print, export and plot: a parameter of the table (wg_param.h) as Hz, µm,
 * N, N/m, N s/m, kg or degrees, and the model's outputs (time, frequency,
 * displacement, velocity, force), from the scale a scene or a PARAMS
 * message carries (MODEL.md s3: omega_n, b_c, K_m; m_e = K_m / omega_n^2).
 * No LCM, no cairo: wgctl, wglog, wgmon and the plots share it. */
#ifndef WG_UNITS_H
#define WG_UNITS_H

#include "wormgear/wg_param.h"

/* The physical scale: one tau is 1/omega_n s, x = 1 is b_c m, F = 1 is
 * K_m b_c N. */
typedef struct units_scale {
    double omega_n_rad_s;
    double length_m;
    double mesh_stiffness_N_m;
} units_scale;

/* 1 when every factor of s is finite and > 0 (a scale to convert with). */
int units_scale_ok(const units_scale *s);


/* The physical equivalent of parameter id at the values p (bearing rows
 * need the mass ratios mu1, mu2 of p): 0 with *v and *unit ("Hz", "µm",
 * "N", "N/m", "N s/m", "kg", "deg"), or -1 when there is none (the a_i,
 * k_a; a bearing row of a rigid body, mu = 0; a bad scale). */
int units_param(int id, const wg_params *p, const units_scale *s, double *v, const char **unit);

/* The factor k with physical = k * parameter, the same for every value of
 * parameter id at the other values p (omega -> Hz, lengths -> µm, ...):
 * 0 with *k and *unit, or -1 when the conversion is not a factor (the
 * masses, 1 / mu) or there is none. */
int units_param_factor(int id, const wg_params *p, const units_scale *s, double *k,
                       const char **unit);

/* How parameter id maps to physical units, in words for a listing with no
 * scale at hand ("Hz = omega omega_n / 2 pi (mesh frequency)"), or "" when it does not. */
const char *units_param_rule(int id);

/* Output factors: seconds per tau, Hz per omega, um per x, m/s per x'
 * (b_c omega_n), N per F (K_m b_c). */
double units_s_per_tau(const units_scale *s);
double units_hz_per_omega(const units_scale *s);
double units_um_per_x(const units_scale *s);
double units_m_s_per_v(const units_scale *s);
double units_n_per_f(const units_scale *s);

#endif

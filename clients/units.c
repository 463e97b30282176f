/* units.c - physical units of parameters and outputs (see units.h). */
#include "units.h"

#include <math.h>
#include <string.h>

#define TWO_PI 6.283185307179586

/* How a parameter converts. The bearing rows scale with the body's mass
 * M_i = m_e / mu_i = K_m / (omega_n^2 mu_i). */
enum kind { K_NONE, K_HZ, K_UM, K_N, K_DEG, K_CMESH, K_KBEAR, K_CBEAR, K_MASS, K_MM, K_INERTIA };

static const struct rule {
    enum kind kind;
    int body;        /* 1 worm, 2 wheel: the mu of the bearing rows */
    const char *words;
} rules[WG_NPARAM] = {
    [WG_P_OMEGA] = {K_HZ, 0, "Hz = omega omega_n / 2 pi (mesh frequency)"},
    [WG_P_XI_P] = {K_CMESH, 0, "N s/m = 2 xi_p K_m / omega_n"},
    [WG_P_XI_G] = {K_CMESH, 0, "N s/m = 2 xi_g K_m / omega_n"},
    [WG_P_PHI1] = {K_DEG, 0, "deg = rad 180 / pi"},
    [WG_P_E_M] = {K_UM, 0, "µm = e_m b_c"},
    [WG_P_PHI2] = {K_DEG, 0, "deg = rad 180 / pi"},
    [WG_P_F_M] = {K_N, 0, "N = f_m K_m b_c (mesh force)"},
    [WG_P_F_E] = {K_N, 0, "N = f_e K_m b_c"},
    [WG_P_PHI] = {K_DEG, 0, "deg = rad 180 / pi"},
    [WG_P_B] = {K_UM, 0, "µm = b b_c"},
    [WG_P_B_J] = {K_UM, 0, "µm = b_j b_c"},
    [WG_P_MU1] = {K_MASS, 1, "kg = m_e / mu1 (worm mass M1)"},
    [WG_P_MU2] = {K_MASS, 2, "kg = m_e / mu2 (wheel mass M2)"},
    [WG_P_K1X] = {K_KBEAR, 1, "N/m = k K_m / mu1"},
    [WG_P_K1Y] = {K_KBEAR, 1, "N/m = k K_m / mu1"},
    [WG_P_K1Z] = {K_KBEAR, 1, "N/m = k K_m / mu1"},
    [WG_P_K2X] = {K_KBEAR, 2, "N/m = k K_m / mu2"},
    [WG_P_K2Y] = {K_KBEAR, 2, "N/m = k K_m / mu2"},
    [WG_P_K2Z] = {K_KBEAR, 2, "N/m = k K_m / mu2"},
    [WG_P_XI1X] = {K_CBEAR, 1, "N s/m = 2 xi K_m / (mu1 omega_n)"},
    [WG_P_XI1Y] = {K_CBEAR, 1, "N s/m = 2 xi K_m / (mu1 omega_n)"},
    [WG_P_XI1Z] = {K_CBEAR, 1, "N s/m = 2 xi K_m / (mu1 omega_n)"},
    [WG_P_XI2X] = {K_CBEAR, 2, "N s/m = 2 xi K_m / (mu2 omega_n)"},
    [WG_P_XI2Y] = {K_CBEAR, 2, "N s/m = 2 xi K_m / (mu2 omega_n)"},
    [WG_P_XI2Z] = {K_CBEAR, 2, "N s/m = 2 xi K_m / (mu2 omega_n)"},
    [WG_P_RHO1] = {K_MM, 1, "mm = rho1 b_c (worm lever arm R1)"},
    [WG_P_RHO2] = {K_MM, 2, "mm = rho2 b_c (wheel lever arm R2)"},
    [WG_P_J1] = {K_INERTIA, 1, "kg m^2 = j1 m_e R1^2 (worm inertia I1; m_e = K_m / omega_n^2)"},
    [WG_P_J2] = {K_INERTIA, 2, "kg m^2 = j2 m_e R2^2 (wheel inertia I2)"},
};

int units_scale_ok(const units_scale *s)
{
    return s && isfinite(s->omega_n_rad_s) && s->omega_n_rad_s > 0 && isfinite(s->length_m) &&
           s->length_m > 0 && isfinite(s->mesh_stiffness_N_m) && s->mesh_stiffness_N_m > 0;
}

const char *units_param_rule(int id)
{
    return id >= 0 && id < WG_NPARAM && rules[id].words ? rules[id].words : "";
}

int units_param(int id, const wg_params *p, const units_scale *s, double *v, const char **unit)
{
    if (id < 0 || id >= WG_NPARAM || rules[id].kind == K_NONE || !units_scale_ok(s))
        return -1;
    const struct rule *r = &rules[id];
    double x = p->v[id], wn = s->omega_n_rad_s, km = s->mesh_stiffness_N_m;
    int bearing = r->kind == K_KBEAR || r->kind == K_CBEAR || r->kind == K_MASS;
    double mu = bearing ? p->v[r->body == 1 ? WG_P_MU1 : WG_P_MU2] : 1.0;
    double arm = r->body ? p->v[r->body == 1 ? WG_P_RHO1 : WG_P_RHO2] * s->length_m : 0.0;
    if (bearing && !(mu > 0))
        return -1; /* a rigid body: no mass, no bearing */
    static const char *const name[] = {"", "Hz", "µm", "N", "deg", "N s/m", "N/m", "N s/m", "kg",
                                       "mm", "kg m^2"};
    switch (r->kind) {
    case K_HZ: *v = x * wn / TWO_PI; break;
    case K_UM: *v = x * s->length_m * 1e6; break;
    case K_N: *v = x * km * s->length_m; break;
    case K_DEG: *v = x * 360.0 / TWO_PI; break;
    case K_CMESH: *v = 2 * x * km / wn; break;
    case K_KBEAR: *v = x * km / mu; break;
    case K_CBEAR: *v = 2 * x * km / (mu * wn); break;
    case K_MASS: *v = km / (wn * wn * x); break;
    case K_MM: *v = x * s->length_m * 1e3; break;
    case K_INERTIA: *v = x * km / (wn * wn) * arm * arm; break;
    default: return -1;
    }
    *unit = name[r->kind];
    return 0;
}

int units_param_factor(int id, const wg_params *p, const units_scale *s, double *k,
                       const char **unit)
{
    wg_params q = *p;
    double v1, v2;
    if (id < 0 || id >= WG_NPARAM)
        return -1;
    q.v[id] = 1.0;
    if (units_param(id, &q, s, &v1, unit))
        return -1;
    q.v[id] = 2.0;
    if (units_param(id, &q, s, &v2, unit) || fabs(v2 - 2 * v1) > 1e-12 * fabs(v2))
        return -1;
    *k = v1;
    return 0;
}

double units_s_per_tau(const units_scale *s) { return 1.0 / s->omega_n_rad_s; }
double units_hz_per_omega(const units_scale *s) { return s->omega_n_rad_s / TWO_PI; }
double units_um_per_x(const units_scale *s) { return s->length_m * 1e6; }
double units_m_s_per_v(const units_scale *s) { return s->length_m * s->omega_n_rad_s; }
double units_n_per_f(const units_scale *s) { return s->mesh_stiffness_N_m * s->length_m; }

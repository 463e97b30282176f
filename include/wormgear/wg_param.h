/* wg_param.h - the one parameter table of the dimensionless model.
 *
 * Each model parameter (MODEL.md section 2) has one row: ASCII name, unit,
 * allowed range, default (the table3 scene) and a help line. Scene files,
 * `--set`, daemon commands and `params` listings all go through this table,
 * so the bounds exist exactly once. */
#ifndef WG_PARAM_H
#define WG_PARAM_H

#include <stddef.h>

enum wg_param_id {
    WG_P_OMEGA, WG_P_XI_P, WG_P_XI_G, WG_P_K_A, WG_P_PHI1, WG_P_E_M,
    WG_P_PHI2, WG_P_F_M, WG_P_F_E, WG_P_PHI, WG_P_B, WG_P_B_J,
    WG_P_A1, WG_P_A2, WG_P_A3, WG_P_MU1, WG_P_MU2,
    WG_P_K1X, WG_P_K1Y, WG_P_K1Z, WG_P_K2X, WG_P_K2Y, WG_P_K2Z,
    WG_P_XI1X, WG_P_XI1Y, WG_P_XI1Z, WG_P_XI2X, WG_P_XI2Y, WG_P_XI2Z,
    /* Body data (WG_PF_BODY): only the derived angles theta1, theta2 use
     * them (wg_angles); they never change the dynamics. */
    WG_P_Z1, WG_P_Z2, WG_P_RHO1, WG_P_RHO2, WG_P_J1, WG_P_J2,
    WG_NPARAM
};

/* The rows before the body data: the parameters of the equations. */
enum { WG_NPARAM_DYN = WG_P_Z1 };

/* Row flags. */
enum {
    WG_PF_RAMP = 1u << 0,  /* may be ramped at run time */
    WG_PF_ANGLE = 1u << 1, /* an angle in radians */
    WG_PF_GEOM = 1u << 2,  /* geometry/mass ratio: changes the linear modes */
    WG_PF_BODY = 1u << 3,  /* body data for derived outputs: no effect on the motion */
    WG_PF_INT = 1u << 4,   /* a whole number (teeth) */
    WG_PF_TIED = 1u << 5   /* tied to other rows by a constraint (the direction cosines:
                              a1^2 + a2^2 + a3^2 = 1, wg_params_check): changed only
                              together with them, never swept alone */
};

typedef struct wg_param_info {
    const char *name;  /* ASCII key: "omega", "xi_p", ... */
    const char *unit;  /* "1" for dimensionless, "rad" for angles */
    double min, max;   /* closed range */
    double def;        /* default: the table3 scene */
    unsigned flags;    /* WG_PF_* */
    const char *help;  /* one line */
} wg_param_info;

/* A full parameter set, indexed by enum wg_param_id. */
typedef struct wg_params {
    double v[WG_NPARAM];
} wg_params;

/* Row of parameter `id` (0 <= id < WG_NPARAM), or NULL. */
const wg_param_info *wg_param_info_get(int id);

/* Id of the parameter called `name`, or -1. */
int wg_param_lookup(const char *name);

/* WG_OK if v is finite and in the row's range (and a whole number for a
 * WG_PF_INT row); else WG_ERANGE with "name = v out of range [min, max]"
 * (or "... must be a whole number in [min, max]") written to why (may be
 * NULL). */
int wg_param_check(int id, double v, char *why, size_t whylen);

/* Parse `text` (strtod, whole string, finite) and range-check it.
 * WG_EINVAL for text that is not a number, WG_ERANGE as wg_param_check. */
int wg_param_parse(int id, const char *text, double *v, char *why, size_t whylen);

/* Parse "name=value", range-check and store into p. WG_EUNKNOWN, WG_EINVAL
 * or WG_ERANGE with a message; p is unchanged on error. */
int wg_param_assign(wg_params *p, const char *assignment, char *why, size_t whylen);

/* The shortest decimal text that reads back (strtod) as exactly v: "0.08",
 * "6.283185307179586", "1e+15", "nan". Returns buf. */
const char *wg_num_format(double v, char *buf, size_t len);

/* "[min, max]" for a person to read and copy: each bound in 6 significant
 * digits, rounded inwards so the text is accepted ("[-6.28318, 6.28318]"
 * for +-2 pi, where %g's 6.28319 is out of range). Returns buf. */
const char *wg_range_shown(double min, double max, char *buf, size_t len);

/* The table's unit as a reader should see it: "-" for a dimensionless
 * parameter (the table's "1"), else the unit itself ("rad"). Every help
 * text and table shows this. */
const char *wg_unit_shown(const char *table_unit);

/* Fill p with the table defaults (the table3 scene). */
void wg_params_default(wg_params *p);

/* Check every value against its row and the cross-parameter rule
 * a1^2 + a2^2 + a3^2 = 1 (within 1e-3). WG_OK or WG_ERANGE with why. */
int wg_params_check(const wg_params *p, char *why, size_t whylen);

#endif

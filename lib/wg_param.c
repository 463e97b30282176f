/* wg_param.c - the parameter table and its checks. */
#include "wormgear/wg_param.h"
#include "wormgear/wg_status.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TWO_PI 6.283185307179586
#define R WG_PF_RAMP
#define A (WG_PF_ANGLE | WG_PF_RAMP)
#define G WG_PF_GEOM
#define BODY WG_PF_BODY

/* Defaults: the table3 scene of MODEL.md s4 (a_i from alpha_n = 20 deg,
 * z1 = 3, m = 4 mm, d1 = 44 mm). */
static const wg_param_info table[WG_NPARAM] = {
    [WG_P_OMEGA] = {"omega", "1", 0.01, 10.0, 1.0, R,
                    "dimensionless meshing frequency (mesh freq / omega_n)"},
    [WG_P_XI_P] = {"xi_p", "1", 0.0, 2.0, 0.08, R, "mesh damping ratio"},
    [WG_P_XI_G] = {"xi_g", "1", 0.0, 2.0, 0.0, R, "torsional (shaft) damping ratio on s"},
    [WG_P_K_A] = {"k_a", "1", 0.0, 0.95, 0.29651, R,
                  "mesh stiffness variation: k_p = 1 + k_a cos(psi + phi1)"},
    [WG_P_PHI1] = {"phi1", "rad", -TWO_PI, TWO_PI, 1.6130, A, "phase of the stiffness variation"},
    [WG_P_E_M] = {"e_m", "1", 0.0, 10.0, 0.2, R, "transmission error amplitude (/ b_c)"},
    [WG_P_PHI2] = {"phi2", "rad", -TWO_PI, TWO_PI, 6.2704, A, "phase of the transmission error"},
    [WG_P_F_M] = {"f_m", "1", 0.0, 10.0, 0.27576, R, "mean input load"},
    [WG_P_F_E] = {"f_e", "1", 0.0, 10.0, 0.092442, R, "fluctuating load amplitude"},
    [WG_P_PHI] = {"phi", "rad", -TWO_PI, TWO_PI, 1.5404, A, "phase of the fluctuating load"},
    [WG_P_B] = {"b", "1", 0.0, 100.0, 1.0, R, "half backlash (/ b_c)"},
    [WG_P_B_J] = {"b_j", "1", 0.0, 1000.0, 1.0, R, "bearing radial/axial clearance (/ b_c)"},
    [WG_P_A1] = {"a1", "1", 0.0, 1.0, 0.24724948462317603, G | WG_PF_TIED,
                 "line-of-action cosine along x: cos(alpha_n) sin(beta)"},
    [WG_P_A2] = {"a2", "1", 0.0, 1.0, 0.3420201433256687, G | WG_PF_TIED,
                 "line-of-action cosine along y: sin(alpha_n)"},
    [WG_P_A3] = {"a3", "1", 0.0, 1.0, 0.9065814436183122, G | WG_PF_TIED,
                 "line-of-action cosine along z: cos(alpha_n) cos(beta)"},
    [WG_P_MU1] = {"mu1", "1", 0.0, 100.0, 2.7442, G, "mass ratio m_e / M1 (0: rigid bearings)"},
    [WG_P_MU2] = {"mu2", "1", 0.0, 100.0, 0.40424, G, "mass ratio m_e / M2 (0: rigid bearings)"},
    [WG_P_K1X] = {"k1x", "1", 1e-3, 1e4, 21.198, R | G, "worm bearing stiffness x"},
    [WG_P_K1Y] = {"k1y", "1", 1e-3, 1e4, 21.198, R | G, "worm bearing stiffness y"},
    [WG_P_K1Z] = {"k1z", "1", 1e-3, 1e4, 21.198, R | G, "worm bearing stiffness z"},
    [WG_P_K2X] = {"k2x", "1", 1e-3, 1e4, 3.1226, R | G, "wheel bearing stiffness x"},
    [WG_P_K2Y] = {"k2y", "1", 1e-3, 1e4, 3.1226, R | G, "wheel bearing stiffness y"},
    [WG_P_K2Z] = {"k2z", "1", 1e-3, 1e4, 3.1226, R | G, "wheel bearing stiffness z"},
    [WG_P_XI1X] = {"xi1x", "1", 0.0, 10.0, 0.47914, R, "worm bearing damping x"},
    [WG_P_XI1Y] = {"xi1y", "1", 0.0, 10.0, 0.47914, R, "worm bearing damping y"},
    [WG_P_XI1Z] = {"xi1z", "1", 0.0, 10.0, 0.47914, R, "worm bearing damping z"},
    [WG_P_XI2X] = {"xi2x", "1", 0.0, 10.0, 0.18390, R, "wheel bearing damping x"},
    [WG_P_XI2Y] = {"xi2y", "1", 0.0, 10.0, 0.18390, R, "wheel bearing damping y"},
    [WG_P_XI2Z] = {"xi2z", "1", 0.0, 10.0, 0.18390, R, "wheel bearing damping z"},
    /* Body data of table3 (MODEL.md s3: R1 = 22 mm, R2 = 74 mm, I1 = 1.733e-4,
     * I2 = 1.331e-2 kg m^2, m_e = 1.9651 kg, b_c = 0.1 mm, d2 = 148 mm = m z2). */
    [WG_P_Z1] = {"z1", "1", 1, 12, 3, BODY | WG_PF_INT, "worm starts (theta1 output only)"},
    [WG_P_Z2] = {"z2", "1", 4, 1000, 37, BODY | WG_PF_INT, "wheel teeth (theta2 output only)"},
    [WG_P_RHO1] = {"rho1", "1", 1.0, 1e7, 220.0, BODY,
                   "worm lever arm R1 / b_c (theta1 output only)"},
    [WG_P_RHO2] = {"rho2", "1", 1.0, 1e7, 740.0, BODY,
                   "wheel lever arm R2 / b_c (theta2 output only)"},
    [WG_P_J1] = {"j1", "1", 1e-6, 1e6, 0.18221, BODY,
                 "worm inertia I1 / (m_e R1^2) (theta outputs only)"},
    [WG_P_J2] = {"j2", "1", 1e-6, 1e6, 1.2369, BODY,
                 "wheel inertia I2 / (m_e R2^2) (theta outputs only)"},
};

const wg_param_info *wg_param_info_get(int id)
{
    return (id >= 0 && id < WG_NPARAM) ? &table[id] : NULL;
}

int wg_param_lookup(const char *name)
{
    for (int i = 0; i < WG_NPARAM; i++)
        if (strcmp(table[i].name, name) == 0)
            return i;
    return -1;
}

const char *wg_num_format(double v, char *buf, size_t len)
{
    int plain = fabs(v) >= 1e-4 && fabs(v) < 1e15; /* "10", never "1e+01" */
    for (int prec = 1; prec <= 17; prec++) {
        snprintf(buf, len, "%.*g", prec, v);
        if (!isfinite(v) || (strtod(buf, NULL) == v && !(plain && strchr(buf, 'e'))))
            break;
    }
    return buf;
}

/* v in 6 significant digits, rounded inwards (dir +1: up, -1: down). */
static double bound_shown(double v, int dir)
{
    char buf[32];
    snprintf(buf, sizeof buf, "%.6g", v);
    double r = strtod(buf, NULL);
    if (r == v || v == 0.0 || !isfinite(v))
        return r;
    double p = pow(10.0, 5 - floor(log10(fabs(v))));
    r = (dir > 0 ? ceil(v * p) : floor(v * p)) / p;
    return dir > 0 ? (r < v ? nextafter(r, INFINITY) : r) : (r > v ? nextafter(r, -INFINITY) : r);
}

const char *wg_range_shown(double min, double max, char *buf, size_t len)
{
    snprintf(buf, len, "[%.10g, %.10g]", bound_shown(min, +1), bound_shown(max, -1));
    return buf;
}

/* "[min, max]" of a row, each bound in the text that reads back exactly. */
static const char *range_text(const wg_param_info *r, char *buf, size_t len)
{
    char lo[32], hi[32];
    snprintf(buf, len, "[%s, %s]", wg_num_format(r->min, lo, sizeof lo),
             wg_num_format(r->max, hi, sizeof hi));
    return buf;
}

int wg_param_check(int id, double v, char *why, size_t whylen)
{
    const wg_param_info *r = wg_param_info_get(id);
    if (!r) {
        if (why && whylen)
            snprintf(why, whylen, "parameter id %d does not exist", id);
        return WG_EUNKNOWN;
    }
    int whole = !(r->flags & WG_PF_INT) || (isfinite(v) && v == floor(v));
    if (!isfinite(v) || v < r->min || v > r->max || !whole) {
        char num[32], range[80];
        if (why && whylen)
            snprintf(why, whylen, "%s = %s %s %s", r->name, wg_num_format(v, num, sizeof num),
                     whole ? "out of range" : "must be a whole number in",
                     range_text(r, range, sizeof range));
        return WG_ERANGE;
    }
    return WG_OK;
}

int wg_param_parse(int id, const char *text, double *v, char *why, size_t whylen)
{
    const wg_param_info *r = wg_param_info_get(id);
    if (!r)
        return wg_param_check(id, 0, why, whylen);
    char *end;
    errno = 0;
    double x = strtod(text, &end);
    while (end != text && (*end == ' ' || *end == '\t'))
        end++;
    if (end == text || *end != '\0') {
        char range[80];
        if (why && whylen)
            snprintf(why, whylen, "%s = '%s' is not a number (allowed range %s)", r->name, text,
                     range_text(r, range, sizeof range));
        return WG_EINVAL;
    }
    int erange = errno == ERANGE;
    int rc = wg_param_check(id, x, why, whylen);
    if (rc == WG_OK)
        *v = x;
    else if (erange && why && whylen) { /* "omega = 0 out of range" for 1e-400: say what was typed */
        size_t n = strlen(why);
        snprintf(why + n, whylen - n, " (typed '%s', which a double holds as %g)", text, x);
    }
    return rc;
}

int wg_param_assign(wg_params *p, const char *assignment, char *why, size_t whylen)
{
    const char *eq = strchr(assignment, '=');
    char name[64];
    size_t len = eq ? (size_t)(eq - assignment) : 0;
    if (!eq || len == 0 || len >= sizeof name) {
        if (why && whylen)
            snprintf(why, whylen, "'%s' is not of the form name=value", assignment);
        return WG_EINVAL;
    }
    memcpy(name, assignment, len);
    name[len] = '\0';
    int id = wg_param_lookup(name);
    if (id < 0) {
        if (why && whylen)
            snprintf(why, whylen, "unknown parameter '%s' (see --help for the list)", name);
        return WG_EUNKNOWN;
    }
    return wg_param_parse(id, eq + 1, &p->v[id], why, whylen);
}

void wg_params_default(wg_params *p)
{
    for (int i = 0; i < WG_NPARAM; i++)
        p->v[i] = table[i].def;
}

int wg_params_check(const wg_params *p, char *why, size_t whylen)
{
    for (int i = 0; i < WG_NPARAM; i++) {
        int rc = wg_param_check(i, p->v[i], why, whylen);
        if (rc)
            return rc;
    }
    double a1 = p->v[WG_P_A1], a2 = p->v[WG_P_A2], a3 = p->v[WG_P_A3];
    double n2 = a1 * a1 + a2 * a2 + a3 * a3;
    if (fabs(n2 - 1.0) > 1e-3) {
        if (why && whylen)
            snprintf(why, whylen,
                     "a1^2 + a2^2 + a3^2 = %.6g, must be 1 within 1e-3 (direction cosines)", n2);
        return WG_ERANGE;
    }
    return WG_OK;
}

const char *wg_unit_shown(const char *table_unit)
{
    return !table_unit || !*table_unit || strcmp(table_unit, "1") == 0 ? "-" : table_unit;
}

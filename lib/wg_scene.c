/* wg_scene.c - scene files (INI via libinih), physical unit conversion. */
#include "wormgear/wg_scene.h"
#include "wormgear/wg_file.h"
#include "wormgear/wg_status.h"

#include <dirent.h>
#include <errno.h>
#include <fcntl.h>
#include <ini.h>
#include <limits.h>
#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* The scene directory relative to the directory of the running program
 * (bin/ or sbin/ of the install prefix, or a build tree's daemon/, clients/,
 * where CMake copies scenes/ to share/wormgear/scenes). */
#ifndef WG_SCENES_FROM_BIN
#define WG_SCENES_FROM_BIN "../share/wormgear/scenes"
#endif

#define TWO_PI 6.283185307179586

/* The [physical] section: SI or the unit in the key's name. */
enum phys_id {
    PH_LENGTH, PH_ALPHA, PH_STARTS, PH_MODULE, PH_D1, PH_R1, PH_R2, PH_M1, PH_I1, PH_M2, PH_I2,
    PH_RIGID, PH_KM, PH_XIP, PH_CM, PH_XIG, PH_KA, PH_PHI1, PH_TE, PH_PHI2, PH_BACKLASH,
    PH_CLEAR, PH_TG, PH_TE_AMP, PH_PHI, PH_KB, PH_KB1, PH_KB2, PH_ZB, PH_CB1, PH_CB2, PH_FMESH,
    PH_TEETH, NPHYS
};

#define NA NAN
static const wg_param_info phys[NPHYS] = {
    [PH_LENGTH] = {"length_scale_m", "m", 1e-7, 0.1, 1e-4, 0, "length scale b_c"},
    [PH_ALPHA] = {"pressure_angle_deg", "deg", 5, 45, 20, 0, "normal pressure angle alpha_n"},
    [PH_STARTS] = {"worm_starts", "1", 1, 12, 3, 0, "number of worm threads z1"},
    [PH_MODULE] = {"module_mm", "mm", 0.1, 100, 4, 0, "axial module m"},
    [PH_D1] = {"worm_diameter_mm", "mm", 1, 2000, 44, 0, "worm pitch diameter d1"},
    [PH_R1] = {"worm_radius_mm", "mm", 0.5, 1000, NA, 0, "worm lever arm R1 (default d1/2)"},
    [PH_R2] = {"wheel_radius_mm", "mm", 1, 5000, NA, 0, "wheel lever arm R2"},
    [PH_M1] = {"worm_mass_kg", "kg", 1e-3, 1e5, NA, 0, "worm mass M1"},
    [PH_I1] = {"worm_inertia_kgm2", "kg m^2", 1e-10, 1e5, NA, 0, "worm polar inertia I1"},
    [PH_M2] = {"wheel_mass_kg", "kg", 1e-3, 1e5, NA, 0, "wheel mass M2"},
    [PH_I2] = {"wheel_inertia_kgm2", "kg m^2", 1e-10, 1e5, NA, 0, "wheel polar inertia I2"},
    [PH_RIGID] = {"rigid_bearings", "0/1", 0, 1, 0, 0, "1: rigid bearings (torsional model)"},
    [PH_KM] = {"mesh_stiffness_N_m", "N/m", 1e5, 1e12, NA, 0, "mean mesh stiffness K_m"},
    [PH_XIP] = {"mesh_damping_ratio", "1", 0, 2, NA, 0, "mesh damping ratio xi_p"},
    [PH_CM] = {"mesh_damping_Ns_m", "N s/m", 0, 1e9, NA, 0, "mesh damping C_m (or the ratio)"},
    [PH_XIG] = {"shaft_damping_ratio", "1", 0, 2, 0, 0, "torsional damping ratio xi_g"},
    [PH_KA] = {"stiffness_variation", "1", 0, 0.95, 0, 0, "k_a"},
    [PH_PHI1] = {"stiffness_phase_rad", "rad", -TWO_PI, TWO_PI, 0, 0, "phi1"},
    [PH_TE] = {"te_amplitude_um", "um", 0, 1e4, 0, 0, "transmission error amplitude E_m"},
    [PH_PHI2] = {"te_phase_rad", "rad", -TWO_PI, TWO_PI, 0, 0, "phi2"},
    [PH_BACKLASH] = {"backlash_um", "um", 0, 1e4, 0, 0, "half backlash"},
    [PH_CLEAR] = {"clearance_um", "um", 0, 1e5, 0, 0, "bearing clearance"},
    [PH_TG] = {"input_torque_Nm", "N m", 0, 1e7, 0, 0, "mean input torque T_g"},
    [PH_TE_AMP] = {"torque_amplitude_Nm", "N m", 0, 1e7, 0, 0, "fluctuating input torque"},
    [PH_PHI] = {"torque_phase_rad", "rad", -TWO_PI, TWO_PI, 0, 0, "phi"},
    [PH_KB] = {"bearing_stiffness_N_m", "N/m", 1e3, 1e14, NA, 0, "both bearings, x y z"},
    [PH_KB1] = {"worm_bearing_stiffness_N_m", "N/m", 1e3, 1e14, NA, 0, "worm bearings, x y z"},
    [PH_KB2] = {"wheel_bearing_stiffness_N_m", "N/m", 1e3, 1e14, NA, 0, "wheel bearings, x y z"},
    [PH_ZB] = {"bearing_damping_ratio", "1", 0, 10, NA, 0, "modal zeta_b: xi = zeta_b sqrt(k)"},
    [PH_CB1] = {"worm_bearing_damping_Ns_m", "N s/m", 0, 1e9, NA, 0, "worm bearing damping"},
    [PH_CB2] = {"wheel_bearing_damping_Ns_m", "N s/m", 0, 1e9, NA, 0, "wheel bearing damping"},
    [PH_FMESH] = {"mesh_frequency_hz", "Hz", 0, 1e7, NA, 0, "mesh frequency (sets omega)"},
    [PH_TEETH] = {"wheel_teeth", "1", 4, 1000, NA, 0,
                  "wheel teeth z2 (default 2 R2 / module, rounded)"},
};

int wg_scene_nphys(void) { return NPHYS; }
const wg_param_info *wg_scene_phys_info(int i) { return i >= 0 && i < NPHYS ? &phys[i] : NULL; }

static const char *const state_keys[2][WG_NSTATE_MAX] = {
    {"x1", "y1", "z1", "x2", "y2", "z2", "s", "dx1", "dy1", "dz1", "dx2", "dy2", "dz2", "ds"},
    {"x1", "y1", "z1", "x2", "y2", "z2", "th1", "th2", "dx1", "dy1", "dz1", "dx2", "dy2",
     "dz2", "dth1", "dth2"},
};

const char *wg_state_name(int model, int i)
{
    if (model < 0 || model > 1 || i < 0 || i >= wg_model_nstate(model))
        return NULL;
    return state_keys[model][i];
}

void wg_scale_default(wg_scale *s)
{
    s->omega_n_rad_s = 31901.0;
    s->length_m = 1e-4;
    s->me_kg = 1.965;
    s->mesh_stiffness_N_m = s->me_kg * s->omega_n_rad_s * s->omega_n_rad_s;
}

/* A key the loader took, for the duplicate check. Only known keys are
 * recorded (an unknown one ends the load), so KEYS_MAX never fills: the
 * [scene], [params], [physical], [scale] keys, state and the 18 names of
 * both models' state values. */
enum { KEYS_MAX = 3 + WG_NPARAM + NPHYS + 3 + 1 + 18 };

/* A scene is a few hundred bytes; a file larger than this is not one. */
enum { SCENE_FILE_MAX = 1 << 20 };

typedef struct taken {
    char sec[12], name[32];
    int line;
} taken;

typedef struct loader {
    FILE *f;
    const char *path;
    int line;
    int indented;   /* the line read starts with white space */
    int header;     /* a [section] line came since the last key */
    int nset;       /* key = value lines seen */
    taken keys[KEYS_MAX];
    int nkeys;
    wg_scene *sc;
    char *why;
    size_t whylen;
    int rc;
    double ph[NPHYS];
    int ph_line[NPHYS];
    int nphys;
    int scale_line; /* the first [scale] key's (a [physical] scene takes its scale from it) */
    int par_line[WG_NPARAM];
    double par[WG_NPARAM];
    int state_given, state_line;
    double y0[2][WG_NSTATE_MAX]; /* [initial] in the consistent and printed layouts */
    int y0_line[2][WG_NSTATE_MAX];
} loader;

/* The first error of a load, at a line given (0: none, "file: ..."). */
__attribute__((format(printf, 4, 5))) static int failf(loader *L, int line, int rc,
                                                       const char *fmt, ...)
{
    if (L->rc == WG_OK) {
        char msg[400];
        va_list ap;
        va_start(ap, fmt);
        vsnprintf(msg, sizeof msg, fmt, ap);
        va_end(ap);
        wg_text_clean(msg); /* it quotes the file's text */
        if (line)
            snprintf(L->why, L->whylen, "%s:%d: %s", L->path, line, msg);
        else
            snprintf(L->why, L->whylen, "%s: %s", L->path, msg);
        L->rc = rc;
    }
    return 0;
}

/* Lines for libinih, counted; and what it does not tell the handler: an
 * indented line after a key is that key's value continued (its multi-line
 * values), unless a [section] line came between; an indented "[section]"
 * there is such a line too, not a header (inih reads it so).
 *
 * A NUL byte ends the parse at its line (inih would end the line there and
 * drop the rest: "omega = 1.2<NUL>garbage" ran, a line after a NUL was
 * skipped), and so does a line longer than inih's buffer (it read on from
 * the cut, so a long comment could carry a key, and the error named the
 * next line), each as the daemon's config reader says it. */
static char *reader(char *str, int num, void *stream)
{
    loader *L = stream;
    int n = 0, c = EOF;
    if (L->rc != WG_OK)
        return NULL;
    while ((c = getc(L->f)) != EOF && c != '\n') {
        if (c == 0)
            return failf(L, L->line + 1, WG_EINVAL, "a NUL byte (column %d): a scene file is "
                         "text", n + 1), NULL;
        if (n >= num - 2) { /* count the rest, for the message */
            long chars = n + 1;
            while ((c = getc(L->f)) != EOF && c != '\n')
                chars++;
            return failf(L, L->line + 1, WG_EINVAL, "line too long: %ld characters, the limit "
                         "is %d", chars, num - 2), NULL;
        }
        str[n++] = (char)c;
    }
    if (n == 0 && c == EOF)
        return NULL;
    if (c == '\n')
        str[n++] = '\n';
    str[n] = 0;
    L->line++;
    L->indented = *str == ' ' || *str == '\t';
    int continues = L->indented && !L->header && L->nset > 0;
    if (str[strspn(str, " \t")] == '[' && !continues)
        L->header = 1;
    return str;
}

static int number(loader *L, const wg_param_info *row, const char *value, double *out)
{
    char *end;
    double x = strtod(value, &end);
    while (end != value && (*end == ' ' || *end == '\t'))
        end++;
    if (end == value || *end != '\0' || !isfinite(x)) {
        char rng[80];
        snprintf(rng, sizeof rng, "[%g, %g]%s%s", row->min, row->max,
                 strcmp(row->unit, "1") ? " " : "", strcmp(row->unit, "1") ? row->unit : "");
        int n = (int)strlen(value), k = n; /* quoted, cut at 40 (failf cleans it) */
        if (n > 40) /* not inside a UTF-8 character */
            for (k = 37; k > 0 && ((unsigned char)value[k] & 0xc0) == 0x80; k--)
                ;
        return failf(L, L->line, WG_EINVAL, "%s: '%.*s%s' is not a number (allowed %s)",
                     row->name, k, value, n > 40 ? "..." : "", rng);
    }
    if (x < row->min || x > row->max) {
        char msg[120];
        snprintf(msg, sizeof msg, "%.17g out of range [%g, %g]%s%s", x, row->min, row->max,
                 strcmp(row->unit, "1") ? " " : "", strcmp(row->unit, "1") ? row->unit : "");
        return failf(L, L->line, WG_ERANGE, "%s: value %s", row->name, msg);
    }
    *out = x;
    return 1;
}

static int on_scene(loader *L, const char *name, const char *value)
{
    wg_scene *sc = L->sc;
    int is_name = strcmp(name, "name") == 0;
    if (is_name || strcmp(name, "description") == 0) { /* shown on terminals, in files */
        const char *rule = is_name ? "1 to 63 printable ASCII characters (a snapshot stores it)"
                                   : "at most 159 bytes, no control characters";
        size_t n = strlen(value), bad = 0, cap = is_name ? sizeof sc->name
                                                         : sizeof sc->description;
        while (bad < n && (unsigned char)value[bad] >= 0x20 && value[bad] != 0x7f &&
               (!is_name || (unsigned char)value[bad] < 0x7f))
            bad++;
        if (bad < n) /* it was printed as it came */
            return failf(L, L->line, WG_EINVAL, "[scene] %s: %s; a %s byte at column %zu", name,
                         rule, is_name ? "control or non-ASCII" : "control", bad + 1);
        if (n >= cap || (is_name && n == 0)) /* it was cut */
            return failf(L, L->line, WG_EINVAL, "[scene] %s: %s; %zu given", name, rule, n);
        snprintf(is_name ? sc->name : sc->description, cap, "%s", value);
    } else if (strcmp(name, "model") == 0) {
        int m = wg_model_lookup(value);
        if (m < 0)
            return failf(L, L->line, WG_EINVAL, "model: '%s' is not one of [consistent, "
                         "printed]", value);
        sc->model = m;
    } else
        return failf(L, L->line, WG_EUNKNOWN, "[scene] %s: unknown key (allowed: name, "
                     "description, model)", name);
    return 1;
}

static int on_initial(loader *L, const char *name, const char *value)
{
    if (strcmp(name, "state") == 0) {
        L->state_line = L->line;
        if (strcmp(value, "equilibrium") == 0)
            L->state_given = 0;
        else if (strcmp(value, "given") == 0)
            L->state_given = 1;
        else
            return failf(L, L->line, WG_EINVAL, "state: '%s' is not one of [equilibrium, "
                         "given]", value);
        return 1;
    }
    int found = 0;
    for (int m = 0; m < 2; m++)
        for (int i = 0; i < WG_NSTATE_MAX && state_keys[m][i]; i++)
            if (strcmp(state_keys[m][i], name) == 0) {
                wg_param_info row = {name, "1", -1e6, 1e6, 0, 0, ""};
                if (!number(L, &row, value, &L->y0[m][i]))
                    return 0;
                L->y0_line[m][i] = L->line;
                found = 1;
            }
    if (found)
        return 1;
    return failf(L, L->line, WG_EUNKNOWN, "[initial] %s: unknown key (state, x1..z2, s or th1 "
                 "th2, dx1..ds)", name);
}

/* Refuse a key given before in its section (the later value won, silently),
 * or an indented line continuing a value (which replaced it, silently):
 * 1 if the key is new. */
static int first_time(loader *L, const char *section, const char *name)
{
    const taken *last = L->nkeys ? &L->keys[L->nkeys - 1] : NULL;
    if (L->indented && !L->header && last && !strcmp(last->sec, section) &&
        !strcmp(last->name, name))
        return failf(L, L->line, WG_EINVAL, "[%s] %s: this indented line would continue the "
                     "value of line %d; a value is one line (remove the indent)",
                     section, name, last->line);
    for (int i = 0; i < L->nkeys; i++)
        if (!strcmp(L->keys[i].sec, section) && !strcmp(L->keys[i].name, name))
            return failf(L, L->line, WG_EINVAL, "[%s] %s: given twice (first at line %d); a "
                         "key may be given once in its section", section, name, L->keys[i].line);
    return 1;
}

/* Record a key taken (known, so it fits: see KEYS_MAX). */
static void remember(loader *L, const char *section, const char *name)
{
    if (L->nkeys == KEYS_MAX)
        return;
    taken *t = &L->keys[L->nkeys++];
    snprintf(t->sec, sizeof t->sec, "%s", section);
    snprintf(t->name, sizeof t->name, "%s", name);
    t->line = L->line;
}

/* One key = value line of a known section, or the unknown-section error. */
static int on_key(loader *L, const char *section, const char *name, const char *value)
{
    if (strcmp(section, "scene") == 0)
        return on_scene(L, name, value);
    if (strcmp(section, "initial") == 0)
        return on_initial(L, name, value);
    if (strcmp(section, "params") == 0) {
        int id = wg_param_lookup(name);
        if (id < 0)
            return failf(L, L->line, WG_EUNKNOWN, "[params] %s: unknown parameter (wgsim "
                         "--help lists them)", name);
        if (!number(L, wg_param_info_get(id), value, &L->par[id]))
            return 0;
        L->par_line[id] = L->line;
        return 1;
    }
    if (strcmp(section, "physical") == 0 || strcmp(section, "scale") == 0) {
        int scale = section[1] == 'c';
        static const char *const scale_keys[] = {"omega_n_rad_s", "length_m", "mesh_stiffness_N_m"};
        if (scale) {
            for (int i = 0; i < 3; i++)
                if (strcmp(name, scale_keys[i]) == 0) {
                    wg_param_info row = {name, i == 0 ? "rad/s" : i == 1 ? "m" : "N/m",
                                         i == 1 ? 1e-9 : 1e-3, 1e15, 0, 0, ""};
                    double x;
                    if (!number(L, &row, value, &x))
                        return 0;
                    double *dst[] = {&L->sc->scale.omega_n_rad_s, &L->sc->scale.length_m,
                                     &L->sc->scale.mesh_stiffness_N_m};
                    *dst[i] = x;
                    L->scale_line = L->scale_line ? L->scale_line : L->line;
                    return 1;
                }
            return failf(L, L->line, WG_EUNKNOWN, "[scale] %s: unknown key (omega_n_rad_s, "
                         "length_m, mesh_stiffness_N_m)", name);
        }
        for (int i = 0; i < NPHYS; i++)
            if (strcmp(name, phys[i].name) == 0) {
                if (!number(L, &phys[i], value, &L->ph[i]))
                    return 0;
                if (i == PH_RIGID && L->ph[i] != 0.0 && L->ph[i] != 1.0) /* 0.5 was rigid */
                    return failf(L, L->line, WG_ERANGE, "[physical] rigid_bearings = %g: 0 "
                                 "(the bearings' stiffness and clearance) or 1 (rigid: the "
                                 "torsional model), nothing between", L->ph[i]);
                L->ph_line[i] = L->line;
                L->nphys++;
                return 1;
            }
        return failf(L, L->line, WG_EUNKNOWN, "[physical] %s: unknown key (see wgsim --help "
                     "for the list)", name);
    }
    return failf(L, L->line, WG_EUNKNOWN, "[%s]: unknown section (allowed: scene, params, "
                 "physical, scale, initial)", section);
}

static int handler(void *user, const char *section, const char *name, const char *value)
{
    loader *L = user;
    L->nset++;
    int text = !strcmp(section, "scene") && (!strcmp(name, "name") || !strcmp(name, "description"));
    if (!text && (strstr(value, " #") || strstr(value, "\t#"))) /* inih ends a value at " ;" */
        return failf(L, L->line, WG_EINVAL, "%s: '%s': " WG_INI_HASH_HINT " (a value may not "
                     "hold ' #')", name, value);
    int ok = first_time(L, section, name) && on_key(L, section, name, value);
    if (ok)
        remember(L, section, name);
    L->header = 0;
    return ok;
}

/* Index of state value `name` in model m's layout, or -1. */
static int state_index(int m, const char *name)
{
    for (int i = 0; i < WG_NSTATE_MAX && state_keys[m][i]; i++)
        if (strcmp(state_keys[m][i], name) == 0)
            return i;
    return -1;
}

/* The first state value given (smallest line) in either layout: its line,
 * and its name in *name; 0 if none. */
static int first_state_value(const loader *L, const char **name)
{
    int best = 0;
    for (int m = 0; m < 2; m++)
        for (int i = 0; i < WG_NSTATE_MAX && state_keys[m][i]; i++)
            if (L->y0_line[m][i] && (!best || L->y0_line[m][i] < best)) {
                best = L->y0_line[m][i];
                *name = state_keys[m][i];
            }
    return best;
}

/* [initial] against the scene's model (known only after the whole file):
 * state = given takes every state value of the model (a missing one
 * started at 0) and none of the other model's; an equilibrium start takes
 * none (they were ignored). WG_OK, or WG_EINVAL with why. */
static int check_initial(loader *L)
{
    int m = L->sc->model == WG_MODEL_PRINTED, n = wg_model_nstate(L->sc->model);
    const char *model = wg_model_name(L->sc->model), *name = NULL;
    if (!L->state_given) {
        int line = first_state_value(L, &name);
        if (line)
            failf(L, line, WG_EINVAL, "[initial] %s: a state value, but the start is the "
                  "equilibrium (%s) and would ignore it: set state = given with all the "
                  "values of the %s model, or remove it", name,
                  L->state_line ? "state = equilibrium" : "the default", model);
        return L->rc;
    }
    char missing[200] = ""; /* 16 names at most */
    for (int i = 0; i < n; i++)
        if (!L->y0_line[m][i]) {
            size_t k = strlen(missing);
            snprintf(missing + k, sizeof missing - k, "%s%s", k ? ", " : "", state_keys[m][i]);
        }
    if (missing[0])
        failf(L, L->state_line, WG_EINVAL, "[initial] state = given needs all %d state values "
              "of the %s model; missing: %s", n, model, missing);
    for (int i = 0; i < WG_NSTATE_MAX && state_keys[!m][i]; i++)
        if (L->y0_line[!m][i] && state_index(m, state_keys[!m][i]) < 0)
            failf(L, L->y0_line[!m][i], WG_EINVAL, "[initial] %s: not a state value of the %s "
                  "model, it would be ignored (its values: %s ... %s)", state_keys[!m][i], model,
                  state_keys[m][0], state_keys[m][n - 1]);
    return L->rc; /* the first failf's, or WG_OK */
}

/* Convert the [physical] section (MODEL.md s3). */
static int convert(loader *L)
{
    double *ph = L->ph;
    wg_params *p = &L->sc->p;
    static const int need[] = {PH_R2, PH_M1, PH_I1, PH_M2, PH_I2, PH_KM};
    for (unsigned i = 0; i < sizeof need / sizeof need[0]; i++)
        if (isnan(ph[need[i]])) {
            L->line = 0;
            snprintf(L->why, L->whylen, "%s: [physical] needs %s (%s)", L->path,
                     phys[need[i]].name, phys[need[i]].help);
            return WG_EINVAL;
        }
    double bc = ph[PH_LENGTH];
    double an = ph[PH_ALPHA] * M_PI / 180.0;
    double beta = atan(ph[PH_STARTS] * ph[PH_MODULE] / ph[PH_D1]);
    double a1 = cos(an) * sin(beta), a2 = sin(an), a3 = cos(an) * cos(beta);
    double R1 = (isnan(ph[PH_R1]) ? 0.5 * ph[PH_D1] : ph[PH_R1]) * 1e-3, R2 = ph[PH_R2] * 1e-3;
    double me = 1.0 / (a1 * a1 * R1 * R1 / ph[PH_I1] + a3 * a3 * R2 * R2 / ph[PH_I2]);
    double wn = sqrt(ph[PH_KM] / me);
    double M[2] = {ph[PH_M1], ph[PH_M2]};
    int rigid = ph[PH_RIGID] != 0.0;
    p->v[WG_P_A1] = a1;
    p->v[WG_P_A2] = a2;
    p->v[WG_P_A3] = a3;
    p->v[WG_P_MU1] = rigid ? 0.0 : me / M[0];
    p->v[WG_P_MU2] = rigid ? 0.0 : me / M[1];
    double kb[2] = {isnan(ph[PH_KB1]) ? ph[PH_KB] : ph[PH_KB1],
                    isnan(ph[PH_KB2]) ? ph[PH_KB] : ph[PH_KB2]};
    double cb[2] = {ph[PH_CB1], ph[PH_CB2]};
    for (int b = 0; b < 2; b++)
        for (int d = 0; d < 3; d++) {
            int i = 3 * b + d;
            if (!isnan(kb[b]))
                p->v[WG_P_K1X + i] = kb[b] / (M[b] * wn * wn);
            double k = p->v[WG_P_K1X + i];
            if (!isnan(cb[b]))
                p->v[WG_P_XI1X + i] = cb[b] / (2.0 * M[b] * wn);
            else if (!isnan(ph[PH_ZB]))
                p->v[WG_P_XI1X + i] = ph[PH_ZB] * sqrt(k);
        }
    if (!isnan(ph[PH_XIP]))
        p->v[WG_P_XI_P] = ph[PH_XIP];
    else if (!isnan(ph[PH_CM]))
        p->v[WG_P_XI_P] = ph[PH_CM] / (2.0 * me * wn);
    p->v[WG_P_XI_G] = ph[PH_XIG];
    p->v[WG_P_K_A] = ph[PH_KA];
    p->v[WG_P_PHI1] = ph[PH_PHI1];
    p->v[WG_P_E_M] = ph[PH_TE] * 1e-6 / bc;
    p->v[WG_P_PHI2] = ph[PH_PHI2];
    p->v[WG_P_B] = ph[PH_BACKLASH] * 1e-6 / bc;
    p->v[WG_P_B_J] = ph[PH_CLEAR] * 1e-6 / bc;
    double fscale = a1 * R1 * ph[PH_KM] * bc;
    p->v[WG_P_F_M] = ph[PH_TG] / fscale;
    p->v[WG_P_F_E] = ph[PH_TE_AMP] / fscale;
    p->v[WG_P_PHI] = ph[PH_PHI];
    if (!isnan(ph[PH_FMESH]))
        p->v[WG_P_OMEGA] = TWO_PI * ph[PH_FMESH] / wn;
    /* Body data for theta1, theta2 (the a_i above fix D = 1 with these). */
    p->v[WG_P_Z1] = ph[PH_STARTS];
    p->v[WG_P_Z2] = isnan(ph[PH_TEETH]) ? round(2.0 * ph[PH_R2] / ph[PH_MODULE]) : ph[PH_TEETH];
    p->v[WG_P_RHO1] = R1 / bc;
    p->v[WG_P_RHO2] = R2 / bc;
    p->v[WG_P_J1] = ph[PH_I1] / (me * R1 * R1);
    p->v[WG_P_J2] = ph[PH_I2] / (me * R2 * R2);
    wg_scale *s = &L->sc->scale;
    s->omega_n_rad_s = wn;
    s->length_m = bc;
    s->mesh_stiffness_N_m = ph[PH_KM];
    s->me_kg = me;
    return WG_OK;
}

/* The [physical] keys each dimensionless parameter is derived from, most
 * specific first (PH_KM, the scale, is everyone's last resort). */
static int derived_source(const loader *L, int id)
{
    static const signed char src[WG_NPARAM][3] = {
        [WG_P_OMEGA] = {PH_FMESH, -1}, [WG_P_XI_P] = {PH_XIP, PH_CM, -1},
        [WG_P_XI_G] = {PH_XIG, -1},    [WG_P_K_A] = {PH_KA, -1},
        [WG_P_PHI1] = {PH_PHI1, -1},   [WG_P_E_M] = {PH_TE, -1},
        [WG_P_PHI2] = {PH_PHI2, -1},   [WG_P_F_M] = {PH_TG, -1},
        [WG_P_F_E] = {PH_TE_AMP, -1},  [WG_P_PHI] = {PH_PHI, -1},
        [WG_P_B] = {PH_BACKLASH, -1},  [WG_P_B_J] = {PH_CLEAR, -1},
        [WG_P_A1] = {PH_MODULE, PH_ALPHA, -1}, [WG_P_A2] = {PH_ALPHA, -1},
        [WG_P_A3] = {PH_MODULE, PH_ALPHA, -1}, [WG_P_MU1] = {PH_M1, -1},
        [WG_P_MU2] = {PH_M2, -1},
        [WG_P_K1X] = {PH_KB1, PH_KB, -1}, [WG_P_K1Y] = {PH_KB1, PH_KB, -1},
        [WG_P_K1Z] = {PH_KB1, PH_KB, -1}, [WG_P_K2X] = {PH_KB2, PH_KB, -1},
        [WG_P_K2Y] = {PH_KB2, PH_KB, -1}, [WG_P_K2Z] = {PH_KB2, PH_KB, -1},
        [WG_P_XI1X] = {PH_CB1, PH_ZB, -1}, [WG_P_XI1Y] = {PH_CB1, PH_ZB, -1},
        [WG_P_XI1Z] = {PH_CB1, PH_ZB, -1}, [WG_P_XI2X] = {PH_CB2, PH_ZB, -1},
        [WG_P_XI2Y] = {PH_CB2, PH_ZB, -1}, [WG_P_XI2Z] = {PH_CB2, PH_ZB, -1},
        [WG_P_Z1] = {PH_STARTS, -1},       [WG_P_Z2] = {PH_TEETH, PH_R2, PH_MODULE},
        [WG_P_RHO1] = {PH_R1, PH_D1, -1},  [WG_P_RHO2] = {PH_R2, -1},
        [WG_P_J1] = {PH_I1, PH_R1, PH_D1},  [WG_P_J2] = {PH_I2, PH_R2, -1},
    };
    for (int k = 0; k < 3 && src[id][k] > 0; k++)
        if (L->ph_line[src[id][k]])
            return src[id][k];
    return PH_KM;
}

/* Range-check every value, naming the line it came from: its own [params]
 * line, or the [physical] key it was derived from. */
static int check_all(loader *L)
{
    char msg[300];
    for (int i = 0; i < WG_NPARAM; i++) {
        if (wg_param_check(i, L->sc->p.v[i], msg, sizeof msg) == WG_OK)
            continue;
        if (L->par_line[i] || !L->sc->physical) {
            snprintf(L->why, L->whylen, "%s:%d: %s", L->path, L->par_line[i], msg);
        } else {
            int ph = derived_source(L, i);
            snprintf(L->why, L->whylen, "%s:%d: %s gives %s", L->path, L->ph_line[ph],
                     phys[ph].name, msg);
        }
        return WG_ERANGE;
    }
    if (wg_params_check(&L->sc->p, msg, sizeof msg) != WG_OK) {
        snprintf(L->why, L->whylen, "%s:%d: %s", L->path, L->par_line[WG_P_A1], msg);
        return WG_ERANGE;
    }
    return WG_OK;
}

int wg_scene_load(wg_scene *sc, const char *path, char *why, size_t whylen)
{
    memset(sc, 0, sizeof *sc);
    loader L;
    memset(&L, 0, sizeof L);
    L.path = path;
    L.sc = sc;
    L.why = why;
    L.whylen = whylen;
    for (int i = 0; i < NPHYS; i++)
        L.ph[i] = phys[i].def;
    wg_params_default(&sc->p);
    wg_scale_default(&sc->scale);
    snprintf(sc->path, sizeof sc->path, "%s", path);
    if (!(L.f = wg_file_fopen(path, "scene file", 0, SCENE_FILE_MAX, NULL, why, whylen)))
        return WG_EIO;
    int r = ini_parse_stream(reader, &L, handler, &L);
    fclose(L.f);
    if (L.rc)
        return L.rc;
    if (r != 0) {
        snprintf(why, whylen, "%s:%d: syntax error (expected [section] or key = value)", path, r);
        return WG_EINVAL;
    }
    if (!L.nset) { /* else the defaults ran under the file's name */
        failf(&L, 0, WG_EINVAL, "no settings (the file is empty or holds only comments and "
              "[section] lines); a scene gives at least one key = value");
        return L.rc;
    }
    int rc = check_initial(&L);
    if (rc)
        return rc;
    if (L.nphys && L.scale_line) { /* the [scale] keys were overwritten, without a word */
        failf(&L, L.scale_line, WG_EINVAL, "[scale] in a scene with [physical]: its scale "
              "comes from the [physical] data (omega_n from K_m and the inertias, b_c from "
              "length_scale_m); give one of the two sections");
        return L.rc;
    }
    if (L.nphys) {
        sc->physical = 1;
        rc = convert(&L);
        if (rc)
            return rc;
    }
    for (int i = 0; i < WG_NPARAM; i++)
        if (L.par_line[i])
            sc->p.v[i] = L.par[i];
    if (!sc->name[0]) {
        const char *base = strrchr(path, '/');
        snprintf(sc->name, sizeof sc->name, "%s", base ? base + 1 : path);
        char *dot = strrchr(sc->name, '.');
        if (dot)
            *dot = '\0';
    }
    sc->has_state = L.state_given;
    memcpy(sc->y0, L.y0[sc->model == WG_MODEL_PRINTED], sizeof sc->y0);
    return check_all(&L);
}

static int exists(const char *p) { return access(p, R_OK) == 0; }

void wg_scene_data_dir(char *dir, size_t len)
{
    char exe[1024];
    ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
    dir[0] = 0;
    if (n <= 0)
        return;
    exe[n] = 0;
    char *slash = strrchr(exe, '/');
    if (slash)
        *slash = 0;
    snprintf(dir, len, "%s/%s", exe, WG_SCENES_FROM_BIN);
    char real[1024];
    if (realpath(dir, real))
        snprintf(dir, len, "%s", real);
}

static int only_ini(const struct dirent *e)
{
    size_t n = strlen(e->d_name);
    return n > 4 && !strcmp(e->d_name + n - 4, ".ini");
}

/* Order of scene names: "table3" before "table3-physical". */
static int by_stem(const struct dirent **a, const struct dirent **b)
{
    size_t na = strlen((*a)->d_name) - 4, nb = strlen((*b)->d_name) - 4;
    int c = strncmp((*a)->d_name, (*b)->d_name, na < nb ? na : nb);
    return c ? c : (na > nb) - (na < nb);
}

/* Is the name (m bytes) one of the ", "-separated names in list? */
static int listed(const char *list, const char *name, size_t m)
{
    for (const char *p = list; *p;) {
        size_t k = strcspn(p, ",");
        if (k == m && strncmp(p, name, m) == 0)
            return 1;
        p += k;
        p += *p ? 2 : 0;
    }
    return 0;
}

/* Is p a regular file (after symlinks), as wg_scene_load wants? */
static int regular_path(const char *p)
{
    struct stat st;
    return stat(p, &st) == 0 && S_ISREG(st.st_mode);
}

/* The same for dir/name. */
static int regular(const char *dir, const char *name)
{
    char p[1024];
    snprintf(p, sizeof p, "%s/%s", dir, name);
    return regular_path(p);
}

/* Append ", "-separated names of the NAME.ini files in dir, sorted, each
 * name once (the same scenes in $WG_SCENE_PATH and the data directory); a
 * directory NAME.ini is no scene, so not offered as one. */
static void list_scenes(const char *dir, char *out, size_t len)
{
    struct dirent **e;
    int n = *dir ? scandir(dir, &e, only_ini, by_stem) : -1;
    for (int i = 0; i < n; i++) {
        size_t k = strlen(out), m = strlen(e[i]->d_name) - 4;
        if (!listed(out, e[i]->d_name, m) && regular(dir, e[i]->d_name))
            snprintf(out + k, len - k, "%s%.*s", k ? ", " : "", (int)m, e[i]->d_name);
        free(e[i]);
    }
    if (n >= 0)
        free(e);
}

int wg_scene_is_file(const char *s)
{
    size_t n = strlen(s);
    return strchr(s, '/') || (n > 4 && strcmp(s + n - 4, ".ini") == 0);
}

int wg_scene_find(const char *name, char *path, size_t pathlen, char *why, size_t whylen)
{
    if (wg_scene_is_file(name)) { /* whole, or refused: cut, it named another file */
        if ((size_t)snprintf(path, pathlen, "%s", name) < pathlen)
            return WG_OK;
        snprintf(why, whylen, "scene file path of %zu characters: the limit is %zu",
                 strlen(name), pathlen - 1);
        return WG_EINVAL;
    }
    char dirs[2048], data[1024], found[512] = "", other[512] = "";
    const char *env = getenv("WG_SCENE_PATH");
    wg_scene_data_dir(data, sizeof data);
    snprintf(dirs, sizeof dirs, "%s:%s", env ? env : "", data);
    for (char *save = NULL, *d = strtok_r(dirs, ":", &save); d; d = strtok_r(NULL, ":", &save)) {
        if (!*d)
            continue;
        if ((size_t)snprintf(path, pathlen, "%s/%s.ini", d, name) >= pathlen)
            continue; /* cut: another file's name */
        if (regular_path(path) && exists(path))
            return WG_OK;
        if (!other[0] && exists(path)) /* a directory NAME.ini: a later file wins */
            snprintf(other, sizeof other, "%s", path);
        list_scenes(d, found, sizeof found);
    }
    if (other[0]) { /* only something else by that name: the loader says what */
        snprintf(path, pathlen, "%s", other);
        return WG_OK;
    }
    snprintf(why, whylen, "scene '%s' not found: looked for %s.ini in $WG_SCENE_PATH (%s) and "
             "%s; scenes there: %s", name, name, env && *env ? env : "unset",
             *data ? data : "(no data directory)", *found ? found : "none");
    return WG_EIO;
}

int wg_scene_open(wg_scene *sc, const char *name, char *why, size_t whylen)
{
    char path[512];
    int rc = wg_scene_find(name, path, sizeof path, why, whylen);
    return rc ? rc : wg_scene_load(sc, path, why, whylen);
}

int wg_scene_apply_sets(wg_scene *sc, const char *const *sets, int n, char *why, size_t whylen)
{
    wg_params p = sc->p;
    for (int i = 0; i < n; i++) {
        int rc = wg_param_assign(&p, sets[i], why, whylen);
        if (rc)
            return rc;
    }
    int rc = wg_params_check(&p, why, whylen);
    if (!rc)
        sc->p = p;
    return rc;
}

double wg_scale_seconds(const wg_scale *s, double tau) { return tau / s->omega_n_rad_s; }

void wg_scene_initial(const wg_scene *sc, double *y)
{
    int n = wg_model_nstate(sc->model);
    if (sc->has_state)
        memcpy(y, sc->y0, sizeof(double) * (size_t)n);
    else
        wg_equilibrium(sc->model, &sc->p, y);
}

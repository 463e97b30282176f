/* wg_scene.h - scene files: INI, dimensionless or physical (MODEL.md s3-s4).
 *
 * [scene]    name, description, model = consistent|printed
 * [params]   any row of the parameter table, dimensionless (wg_param.h)
 * [physical] masses, inertias, radii, stiffnesses, torque, backlash in um...
 *            converted once at load; [params] keys then override.
 * [scale]    omega_n_rad_s, length_m, mesh_stiffness_N_m for physical output
 * [initial]  state = equilibrium | given; with `given`, every state value of
 *            the model (x1 ... ds; printed: th1 th2 dth1 dth2 for s, ds), and
 *            none without it.
 * Errors read "file:line: key: value out of range [min, max]"; a key given
 * twice in a section, an indented (continued) value and a file with no
 * settings are errors too. */
#ifndef WG_SCENE_H
#define WG_SCENE_H

#include <stddef.h>
#include "wg_param.h"
#include "wg_model.h"

/* Physical scale of a scene: how dimensionless numbers map to SI. */
typedef struct wg_scale {
    double omega_n_rad_s; /* natural frequency of the mesh mode */
    double length_m;      /* b_c */
    double mesh_stiffness_N_m; /* K_m */
    double me_kg;         /* equivalent mass m_e */
} wg_scale;

typedef struct wg_scene {
    char name[64];
    char description[160];
    char path[512];
    int model;               /* enum wg_model_kind */
    int physical;            /* 1 if given in physical units */
    wg_params p;
    wg_scale scale;
    int has_state;           /* [initial] state = given */
    double y0[WG_NSTATE_MAX];
} wg_scene;

/* Default physical scale (MODEL.md s3): omega_n 31901 rad/s, b_c 1e-4 m. */
void wg_scale_default(wg_scale *s);

/* Load a scene from a file. WG_OK, or WG_EIO / WG_EINVAL / WG_ERANGE /
 * WG_EUNKNOWN with "file:line: key: ..." in why; WG_EIO with the reason
 * when the file cannot be opened or is not a regular file (a directory, a
 * FIFO: refused without reading or waiting). */
int wg_scene_load(wg_scene *sc, const char *path, char *why, size_t whylen);

/* Resolve NAME or FILE: a path containing '/' or ending in ".ini" is used as
 * given; otherwise NAME.ini is looked up in $WG_SCENE_PATH (colon-separated),
 * then in the data directory next to the program (wg_scene_data_dir). The
 * error lists the scenes those directories hold (regular files only). */
int wg_scene_find(const char *name_or_file, char *path, size_t pathlen,
                  char *why, size_t whylen);

/* 1 when wg_scene_find takes s as a file path ('/' in it, or ".ini" at its
 * end), 0 when as a scene name looked up in the scene directories. */
int wg_scene_is_file(const char *s);

/* The scene directory of this installation, found from the running
 * program: <prefix>/share/wormgear/scenes for <prefix>/bin or sbin (so an
 * install can move), or a build tree's copy of scenes/; "" if unknown. */
void wg_scene_data_dir(char *dir, size_t len);

/* wg_scene_find then wg_scene_load. */
int wg_scene_open(wg_scene *sc, const char *name_or_file, char *why, size_t whylen);

/* Apply n "name=value" overrides (--set, a config's [params]) to the
 * scene's parameters in order, then check the whole set (each range and
 * the a1^2 + a2^2 + a3^2 = 1 rule). WG_OK, or WG_EUNKNOWN / WG_EINVAL /
 * WG_ERANGE with why naming the override; the scene is unchanged on error. */
int wg_scene_apply_sets(wg_scene *sc, const char *const *sets, int n, char *why, size_t whylen);

/* Physical seconds of a span of dimensionless time tau (tau / omega_n). */
double wg_scale_seconds(const wg_scale *s, double tau);

/* Initial state of the scene (given, or static equilibrium). */
void wg_scene_initial(const wg_scene *sc, double *y);

/* Name of state variable i of a model: "x1" ... "s", "dx1" ... "ds"
 * (printed: "th1", "th2", "dth1", "dth2" for s, ds), the [initial] keys and
 * every CSV's column names; NULL outside 0 .. wg_model_nstate(model) - 1. */
const char *wg_state_name(int model, int i);

/* Physical parameter table (rows of the [physical] section), for --help. */
int wg_scene_nphys(void);
const wg_param_info *wg_scene_phys_info(int i);

#endif

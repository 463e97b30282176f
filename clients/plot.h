/* plot.h - PNG figures of sweeps and orbits with cairo: bifurcation
 * diagrams (up/down sweeps, +-b lines, regime shading, min-x_n panel),
 * 2-D regime maps, and x-y plots (phase portrait, Poincare map, time trace).
 * Shared by wgsweep and wgrig. Each function writes one PNG and returns 0,
 * or -1 with a message in why. */
#ifndef WG_PLOT_H
#define WG_PLOT_H

#include <stddef.h>
#include "wormgear/wg_sweep.h"

/* A bifurcation diagram of one up/down sweep pair (either may be empty). */
typedef struct plot_bif {
    const char *title;
    const char *xlabel;      /* e.g. "omega" */
    const wg_point *up, *down;
    int nup, ndown;          /* points in run order */
    double b;                /* backlash: the +-b lines */
    const wg_transition *tr; /* marked as ticks under the title (may be NULL) */
    int ntr;
} plot_bif;

/* Colour modes of a regime map. */
enum { PLOT_MAP_REGIME = 0, PLOT_MAP_MOTION = 1 };

/* A 2-D map: rows[i] is a chain over the x parameter at row value value2. */
typedef struct plot_map {
    const char *title, *xlabel, *ylabel;
    const wg_chain *rows;
    int nrows;
    int mode;                /* PLOT_MAP_REGIME or PLOT_MAP_MOTION */
} plot_map;

/* A curve or a cloud of points, with optional +-b guide lines. */
typedef struct plot_xy {
    const char *title, *xlabel, *ylabel;
    const double *x, *y;
    int n;
    int dots;                /* 1: points, 0: a polyline */
    double b;                /* guides at +-b when > 0 */
    int b_on_x;              /* 1: vertical guides (x is x_n), 0: horizontal */
} plot_xy;

/* Write a bifurcation diagram (1400 x 1000) to path. */
int plot_bifurcation(const char *path, const plot_bif *pb, char *why, size_t whylen);

/* Write a regime map (1200 x 900) to path. */
int plot_regime_map(const char *path, const plot_map *pm, char *why, size_t whylen);

/* Write an x-y plot (1000 x 800) to path. */
int plot_xy_png(const char *path, const plot_xy *px, char *why, size_t whylen);

/* Background colour of a point's regime (r, g, b in [0, 1]); strong = 1
 * gives the saturated variant used in maps. Also used for legends. */
void plot_regime_colour(const wg_point *p, int strong, double rgb[3]);

/* Release cairo's and fontconfig's caches (call once at exit, after the
 * last plot; keeps leak checkers quiet). */
void plot_fini(void);

#endif

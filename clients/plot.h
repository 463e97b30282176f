/* plot.h - figures of sweeps and orbits with cairo, as PNG, SVG or PDF:
 * bifurcation diagrams (up/down sweeps, +-b lines, regime shading, min-x_n
 * panel), 2-D regime maps, and x-y plots (phase portrait, Poincare map,
 * time trace). Every figure has a title, caption lines (the caller says
 * what made it: scene, parameters, numerics) and axes with symbols and
 * units, and may carry a second scale on each axis (omega in Hz, x_n in
 * um). An SVG carries its title, caption and axis labels as <title> and
 * <desc>, a PDF as its Title and Subject. Shared by wgsweep, wgrig and
 * wgcont. Each function writes one file and returns 0, or -1 with a
 * message in why. */
#ifndef WG_PLOT_H
#define WG_PLOT_H

#include <stddef.h>
#include "wormgear/wg_sweep.h"

/* What every figure carries besides its data. */
typedef struct plot_page {
    const char *format;      /* "png" (or NULL), "svg" or "pdf" */
    const char *caption[4];  /* lines under the title (NULL: none) */
} plot_page;

/* A second scale on an axis: the value k * v beside each value v (k 0:
 * none), with its own label (e.g. "mesh frequency (Hz)"). */
typedef struct plot_scale2 {
    double k;
    const char *label;
    double step;             /* between its ticks (0: a round step of its own) */
} plot_scale2;

/* 1 when format is one plot_* writes ("png", "svg", "pdf"). */
int plot_format_ok(const char *format);

/* A bifurcation diagram of one up/down sweep pair (either may be empty). */
typedef struct plot_bif {
    const char *title;
    const char *xlabel;      /* symbol and unit, e.g. "ω = mesh frequency / ω_n  (-)" */
    const wg_point *up, *down;
    int nup, ndown;          /* points in run order */
    double b;                /* backlash: the +-b lines (NAN: b is the swept parameter,
                                the lines x_n = +-value) */
    const wg_transition *tr; /* marked as ticks under the title (may be NULL) */
    int ntr;
    plot_scale2 x2;          /* under the parameter's numbers (Hz for omega) */
    plot_scale2 y2;          /* right of x_n (um) */
    plot_page pg;
} plot_bif;

/* Colour modes of a regime map. */
enum { PLOT_MAP_REGIME = 0, PLOT_MAP_MOTION = 1 };

/* A 2-D map: rows[i] is a chain over the x parameter at row value value2. */
typedef struct plot_map {
    const char *title, *xlabel, *ylabel;
    const wg_chain *rows;
    int nrows;
    int mode;                /* PLOT_MAP_REGIME or PLOT_MAP_MOTION */
    plot_scale2 x2, y2;      /* top and right */
    plot_page pg;
} plot_map;

/* A curve or a cloud of points, with optional +-b guide lines. */
typedef struct plot_xy {
    const char *title, *xlabel, *ylabel;
    const double *x, *y;
    int n;
    int dots;                /* 1: points, 0: a polyline */
    double b;                /* guides at +-b when > 0 */
    int b_on_x;              /* 1: vertical guides (x is x_n), 0: horizontal */
    plot_scale2 x2, y2;      /* top (e.g. mesh periods of a time axis) and right */
    const char *note;        /* a line in the plot's top left corner (NULL: none) */
    plot_page pg;
    int split;               /* > 0: [0, split) an up sweep, the rest a down sweep: two
                                lines with markers (dots, rings) and a legend */
} plot_xy;

/* Write a bifurcation diagram (1400 x 1080) to path: Poincare x_n of the
 * up sweep as filled dots over the down sweep's open rings (both visible
 * where they agree), the main panel shaded by the up sweep's regime (the
 * down sweep's when there is no up sweep; the legend says which), strips
 * of both sweeps' regimes above it. */
int plot_bifurcation(const char *path, const plot_bif *pb, char *why, size_t whylen);

/* Write a regime map (1200 x 960) to path. */
int plot_regime_map(const char *path, const plot_map *pm, char *why, size_t whylen);

/* Write an x-y plot (1000 x 860) to path. */
int plot_xy_write(const char *path, const plot_xy *px, char *why, size_t whylen);

/* Background colour of a point's regime (r, g, b in [0, 1]); strong = 1
 * gives the saturated variant used in maps. Also used for legends. */
void plot_regime_colour(const wg_point *p, int strong, double rgb[3]);

/* Release cairo's and fontconfig's caches (call once at exit, after the
 * last plot; keeps leak checkers quiet). */
void plot_fini(void);

#endif

/* plot_cont.h - the figure of a continuation run: its branches over a
 * sweep's bifurcation diagram (PNG, SVG or PDF with cairo). */
#ifndef WG_PLOT_CONT_H
#define WG_PLOT_CONT_H

#include <stddef.h>
#include "cont_out.h"
#include "plot.h"
#include "wormgear/wg_sweep.h"

typedef struct plot_cont {
    const char *title;
    const char *caption[3];    /* lines under the title (NULL: none) */
    const char *xlabel;        /* with symbol and unit */
    double xlo, xhi;           /* the parameter range */
    double b;                  /* backlash: the +-b guides */
    const cont_result *r;
    const wg_point *up, *down; /* the sweep (may be NULL / 0 points) */
    int nup, ndown;
    const char *format;        /* "png", "svg" or "pdf" */
    plot_scale2 x2;            /* under the parameter's numbers (Hz for omega; k 0: none) */
    plot_scale2 y2;            /* right of x_n (um; k 0: none) */
} plot_cont;

/* Two panels over the parameter: the Poincare x_n of every branch point
 * (each section of a period-n orbit a curve; stable solid, unstable
 * dashed; colour by period) over the sweep's dots, and min x_n over the
 * orbit with +-b; every bifurcation marked and labelled. 0 or -1 with why. */
int plot_continuation(const char *path, const plot_cont *pc, char *why, size_t whylen);

#endif

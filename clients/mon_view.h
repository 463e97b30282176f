/* mon_view.h - wgmon's two plots as text, each with labelled axes:
 *
 * - the x_n trace over a window of mesh periods, with a time axis in
 *   periods and (when PARAMS gave the scale) milliseconds of simulated
 *   time. With enough STATE samples per period (>= 8) it scrolls: the last
 *   periods, newest at the right. With fewer (physical real time: ~2000
 *   samples/s against 5077 mesh periods/s) raw samples would alias, so the
 *   samples of the last window_s seconds are folded onto the window by
 *   their phase, psi = 2 pi (step mod N) / N, from the section psi = 0: a
 *   stroboscopic (equivalent-time) picture, and the plot says so.
 * - the Poincare scatter x_n' against x_n of the last window_s seconds,
 *   density shaded, with both ranges (and x_n in um) on its axes. */
#ifndef WG_MON_VIEW_H
#define WG_MON_VIEW_H

#include <stddef.h>
#include <stdint.h>
#include "mon_text.h"

/* Ring of STATE samples. */
typedef struct mon_trace {
    int64_t *step;           /* the daemon's step index of each sample */
    double *x, *t;           /* x_n; receive time, monotonic s */
    long n, cap;             /* samples ever pushed; capacity */
    int decimation;          /* steps between samples, in the latest message */
} mon_trace;

/* Ring of POINCARE sections. */
typedef struct mon_sections {
    double *t, *x, *v;       /* receive time; x_n, x_n' */
    int *imp, *mot;          /* mesh impacts, motion class of the period */
    long n, cap;
} mon_sections;

/* What the plots need besides the rings. */
typedef struct mon_view_ctx {
    int N;                   /* steps per mesh period (0: unknown) */
    double omega;            /* the meshing frequency now */
    double omega_n_rad_s;    /* the scale (0: unknown, no ms axis) */
    double length_m;         /* b_c (0: unknown, no um) */
    int periods;             /* the trace's window, mesh periods */
    double window_s;         /* wall seconds of sections and folded samples */
    double now;              /* monotonic s */
    double since;            /* monotonic s the rings began to fill (listening began,
                              * or the plots were cleared) */
} mon_view_ctx;

/* Rings of cap entries: 0, or -1 out of memory. Free with *_free. */
int mon_trace_alloc(mon_trace *tr, long cap);
int mon_sections_alloc(mon_sections *s, long cap);
void mon_trace_free(mon_trace *tr);
void mon_sections_free(mon_sections *s);

void mon_trace_push(mon_trace *tr, int64_t step, double x, double t);
void mon_sections_push(mon_sections *s, double t, double x, double v, int imp, int mot);

/* Oldest ring index whose time is >= since (times non-decreasing; the
 * indices n0 .. n-1 are the recent ones). */
long mon_view_from(const double *t, long n, long cap, double since);

/* The seconds "the last window_s seconds" really cover, as a label into
 * buf: window_s ("5"), or less while the rings began to fill later
 * ("0.53": wgmon --once listens about a second). Returns buf. */
const char *mon_view_span(const mon_view_ctx *c, char *buf, size_t len);

/* 1 when the trace would be stroboscopic (fewer than 8 samples a period). */
int mon_view_strobe(const mon_trace *tr, const mon_view_ctx *c);

/* The two plots in at most rows lines of f (f->cols wide): side by side
 * from 100 columns or when stacking would leave them under 5 rows each,
 * else stacked. Titles shorten to one line and the ms row goes when rows
 * are few; nothing is drawn below 3 canvas rows or 12 columns. */
void mon_view_plots(mon_text *f, const mon_trace *tr, const mon_sections *pc,
                    const mon_view_ctx *c, int rows);

#endif

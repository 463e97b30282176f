/* plot_draw.h - plot.c's drawing helpers for the clients' other figures
 * (plot_cont.c): a data frame and its coordinates, text, axes with ticks,
 * dashed guides, legend boxes, and a sweep's Poincare dots and min x_n
 * curve. All draw on a cairo context in device units. */
#ifndef WG_PLOT_DRAW_H
#define WG_PLOT_DRAW_H

#include <cairo.h>
#include <stddef.h>
#include "plot.h"
#include "wormgear/wg_sweep.h"

/* A plotting area: pixel box and data ranges. */
typedef struct frame {
    double x0, y0, w, h;
    double xmin, xmax, ymin, ymax;
} frame;

static inline double px(const frame *f, double x)
{
    return f->x0 + (x - f->xmin) / (f->xmax - f->xmin) * f->w;
}

static inline double py(const frame *f, double y)
{
    return f->y0 + f->h - (y - f->ymin) / (f->ymax - f->ymin) * f->h;
}

/* The figures' font. */
#define PD_FONT "DejaVu Sans"

/* The ticks of an axis over [lo, hi] at the multiples of st in it (at
 * most PD_TICKS_MAX, each once; none for a step that is not a positive
 * finite number) into t, and their labels into lab, with the significant
 * digits that tell neighbours apart (%g's 6 where those do, at most 15).
 * Returns how many. */
enum { PD_TICKS_MAX = 64, PD_TICK_LABEL = 32 };
int pd_ticks(double lo, double hi, double st, double t[PD_TICKS_MAX],
             char lab[PD_TICKS_MAX][PD_TICK_LABEL]);

/* [lo, hi] made the unit window about its middle where its spread is
 * under 1e-4 of its magnitude (magnitudes under 1 counted as 1; no data,
 * non-finite ends: [-0.5, 0.5]), so ticks can show it. */
void pd_min_span(double *lo, double *hi);

/* What a figure says in words (title, caption, axis labels): an SVG's
 * <title> and <desc>, a PDF's Title and Subject. */
typedef struct pd_doc {
    char title[320];
    char desc[2048];         /* lines apart by '\n' */
} pd_doc;

/* A white page of w x h (pixels, or points for SVG and PDF) in format
 * ("png", NULL too, "svg", "pdf") that writes to path: its context. */
cairo_t *pd_canvas(const char *path, const char *format, int w, int h, cairo_surface_t **s);

/* The title and caption lines centred at the top of a page w wide: the
 * baseline of the last line drawn. */
double pd_page_head(cairo_t *cr, double w, const char *title, const plot_page *pg);

/* The doc of a page: its title, the caption lines; then a line "what: s"
 * (what NULL: s alone) per pd_words. */
void pd_doc_init(pd_doc *d, const char *title, const plot_page *pg);
void pd_words(pd_doc *d, const char *what, const char *s);

/* Write the page (PNG; SVG and PDF end here) with the doc d (may be NULL),
 * and free it: 0, or -1 with why. */
int pd_finish(cairo_surface_t *s, cairo_t *cr, const char *path, const char *format,
              const pd_doc *d, char *why, size_t whylen);

/* A second scale sc on an axis of f: where 0 on top, 1 a row under the x
 * numbers, 2 on the right (nothing when sc->k is 0). */
void pd_scale2(cairo_t *cr, const frame *f, const plot_scale2 *sc, int where);

/* Text at (x, y), size in points, align 0 left .. 1 right (UTF-8). */
void pd_text(cairo_t *cr, double x, double y, double size, double align, const char *s);

/* The white halo of pd_text(cr, x, y, size, align, s): its glyphs filled
 * and widened by PD_HALO px on each side (solid, whatever the dash). Labels
 * over curves stay legible when every label's halo is drawn before any
 * label's text (so that no halo covers another label's letters). Like
 * pd_text it leaves the font set; it clears the current path. */
#define PD_HALO 1.5
void pd_halo(cairo_t *cr, double x, double y, double size, double align, const char *s);

/* The frame's box, ticks and numbers (x numbers and label only if
 * xnumbers), axis labels. */
void pd_axes(cairo_t *cr, const frame *f, const char *xlabel, const char *ylabel, int xnumbers);

/* Dashed horizontal guide at data y, labelled at the right. */
void pd_hguide(cairo_t *cr, const frame *f, double y, const char *label);

/* A filled legend box with its label. */
void pd_legend_box(cairo_t *cr, double x, double y, const double rgb[3], const char *label);

/* A sweep's Poincare x_n as dots, and its min x_n as a curve. */
void pd_dots(cairo_t *cr, const frame *f, const wg_point *pts, int n, const double c[3]);
void pd_min_curve(cairo_t *cr, const frame *f, const wg_point *pts, int n, const double c[3]);

/* The colours of the up and down sweeps. */
extern const double PD_UP[3], PD_DOWN[3];

#endif

/* plot.c - cairo figures for sweeps and orbits (see plot.h). */
#include "plot.h"
#include "plot_draw.h"

#include <cairo.h>
#include <fontconfig/fontconfig.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>


static const double C_UP[3] = {0.12, 0.40, 0.80}, C_DOWN[3] = {0.85, 0.25, 0.10};
const double PD_UP[3] = {0.12, 0.40, 0.80}, PD_DOWN[3] = {0.85, 0.25, 0.10};

void plot_regime_colour(const wg_point *p, int strong, double rgb[3])
{
    static const double pal[][2][3] = {
        {{1.00, 1.00, 1.00}, {0.85, 0.88, 0.92}}, /* period 1 */
        {{1.00, 0.95, 0.69}, {0.99, 0.85, 0.30}}, /* period 2 */
        {{1.00, 0.84, 0.62}, {0.98, 0.62, 0.22}}, /* period 4 */
        {{1.00, 0.70, 0.54}, {0.85, 0.38, 0.12}}, /* period 8..32, powers of 2 */
        {{0.78, 0.90, 1.00}, {0.35, 0.62, 0.90}}, /* other periods */
        {{0.88, 0.88, 0.88}, {0.60, 0.60, 0.60}}, /* periodic, n unresolved */
        {{0.78, 0.94, 0.78}, {0.30, 0.72, 0.30}}, /* quasi-periodic */
        {{1.00, 0.70, 0.78}, {0.80, 0.10, 0.25}}, /* chaotic */
        {{0.45, 0.45, 0.45}, {0.15, 0.15, 0.15}}, /* none / diverged */
    };
    int k = 8;
    if (p->regime == WG_REGIME_PERIODIC) {
        int n = p->period;
        k = n == 1 ? 0 : n == 2 ? 1 : n == 4 ? 2 : n == 0 ? 5 : (n & (n - 1)) == 0 ? 3 : 4;
    } else if (p->regime == WG_REGIME_QUASIPERIODIC) {
        k = 6;
    } else if (p->regime == WG_REGIME_CHAOTIC) {
        k = 7;
    }
    memcpy(rgb, pal[k][strong ? 1 : 0], sizeof(double) * 3);
}

void plot_fini(void)
{
    cairo_debug_reset_static_data();
    FcFini();
}

/* ---- small drawing helpers ------------------------------------------------ */

static void set_rgb(cairo_t *cr, const double c[3], double a)
{
    cairo_set_source_rgba(cr, c[0], c[1], c[2], a);
}

/* The font set at size, and the current point where s starts for
 * text(cr, x, y, size, align, s). */
static void text_at(cairo_t *cr, double x, double y, double size, double align, const char *s)
{
    cairo_text_extents_t e;
    cairo_select_font_face(cr, PD_FONT, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
    cairo_text_extents(cr, s, &e);
    cairo_move_to(cr, x - align * e.x_advance, y);
}

static void text(cairo_t *cr, double x, double y, double size, double align, const char *s)
{
    text_at(cr, x, y, size, align, s);
    cairo_show_text(cr, s);
}

static void vtext(cairo_t *cr, double x, double y, double size, const char *s)
{
    cairo_save(cr);
    cairo_translate(cr, x, y);
    cairo_rotate(cr, -M_PI / 2);
    text(cr, 0, 0, size, 0.5, s);
    cairo_restore(cr);
}

/* Tick step: 1, 2 or 5 times a power of ten, about n ticks over the range. */
static double tick_step(double lo, double hi, int n)
{
    double raw = (hi - lo) / n, p = pow(10.0, floor(log10(raw))), m = raw / p;
    return (m < 1.5 ? 1.0 : m < 3.5 ? 2.0 : m < 7.5 ? 5.0 : 10.0) * p;
}

/* Significant digits that tell ticks st apart up to |t| (%g's 6 when
 * those do, at most 15): a sweep over omega 1.37880 ... 1.37881 is
 * labelled 1.378801, 1.378802, ..., not 1.3788 ten times. */
static int tick_digits(const double *t, int n, double st)
{
    double mx = 0.0;
    for (int i = 0; i < n; i++)
        mx = fmax(mx, fabs(t[i]));
    if (!(mx > 0) || !(st > 0))
        return 6;
    int d = (int)floor(log10(mx)) - (int)floor(log10(st)) + 1;
    return d < 6 ? 6 : d > 15 ? 15 : d;
}

/* Each tick is k st, not a running sum: a step under the values' ulp
 * once made the sum stand still (a period-1 orbit's Poincare map, whose
 * range was 1e-15 wide, hung). */
int pd_ticks(double lo, double hi, double st, double t[PD_TICKS_MAX],
             char lab[PD_TICKS_MAX][PD_TICK_LABEL])
{
    int n = 0;
    if (!(st > 0) || !isfinite(st) || !isfinite(lo) || !isfinite(hi))
        return 0;
    double k0 = ceil(lo / st - 1e-9);
    for (int i = 0; n < PD_TICKS_MAX; i++) {
        double v = (k0 + i) * st;
        if (v > hi + 1e-9 * st || (n > 0 && v == t[n - 1]))
            break;
        t[n++] = v;
    }
    int dg = tick_digits(t, n, st);
    for (int i = 0; i < n; i++)
        snprintf(lab[i], PD_TICK_LABEL, "%.*g", dg, fabs(t[i]) < 1e-12 * st ? 0.0 : t[i]);
    return n;
}

/* An axis range [lo, hi] of data whose spread its tick labels cannot show
 * (under 1e-4 of its magnitude, magnitudes under 1 counted as 1: a
 * period-1 orbit's Poincare sections agree to ~1e-10 or to the bit) is
 * the unit window about its middle that data all equal always had; no
 * data at all gives [-0.5, 0.5]. */
void pd_min_span(double *lo, double *hi)
{
    if (!isfinite(*lo) || !isfinite(*hi)) {
        *lo = -0.5, *hi = 0.5;
        return;
    }
    double mid = 0.5 * (*lo + *hi);
    if (!(*hi - *lo >= 1e-4 * fmax(fmax(fabs(*lo), fabs(*hi)), 1.0)))
        *lo = mid - 0.5, *hi = mid + 0.5;
}

/* The widest of n y tick labels at *size (13 px), the size made smaller
 * (not under 8) when they would not fit between the page's left edge,
 * with the axis title's 22 px, and the frame at x0: a Poincare map of
 * velocities near -0.0008 labelled -0.00085, wider than the 52 px the
 * title left them, wrote its title over them. */
static double ylabel_room(cairo_t *cr, char lab[][PD_TICK_LABEL], int n, double x0,
                          double *size)
{
    double wide = 0.0;
    cairo_text_extents_t e;
    cairo_select_font_face(cr, PD_FONT, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, *size);
    for (int i = 0; i < n; i++) {
        cairo_text_extents(cr, lab[i], &e);
        wide = fmax(wide, e.x_advance);
    }
    double room = x0 - 6 - 8 - 22;
    if (wide > room) {
        double s0 = *size;
        *size = fmax(8.0, floor(s0 * room / wide));
        wide *= *size / s0;
    }
    return wide;
}

static void axes(cairo_t *cr, const frame *f, const char *xlabel, const char *ylabel,
                 int xnumbers)
{
    double t[PD_TICKS_MAX];
    char lab[PD_TICKS_MAX][PD_TICK_LABEL];
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1.0);
    cairo_rectangle(cr, f->x0, f->y0, f->w, f->h);
    cairo_stroke(cr);
    double sx = tick_step(f->xmin, f->xmax, 10), sy = tick_step(f->ymin, f->ymax, 6);
    for (int i = 0, n = pd_ticks(f->xmin, f->xmax, sx, t, lab); i < n; i++) {
        double x = t[i];
        cairo_move_to(cr, px(f, x), f->y0 + f->h);
        cairo_line_to(cr, px(f, x), f->y0 + f->h - 6);
        cairo_stroke(cr);
        if (xnumbers)
            text(cr, px(f, x), f->y0 + f->h + 18, 13, 0.5, lab[i]);
    }
    int ny = pd_ticks(f->ymin, f->ymax, sy, t, lab);
    double size = 13, wide = ylabel_room(cr, lab, ny, f->x0, &size);
    for (int i = 0; i < ny; i++) {
        double y = t[i];
        cairo_move_to(cr, f->x0, py(f, y));
        cairo_line_to(cr, f->x0 + 6, py(f, y));
        cairo_stroke(cr);
        text(cr, f->x0 - 6, py(f, y) + 5, size, 1.0, lab[i]);
    }
    if (xlabel && xnumbers)
        text(cr, f->x0 + f->w / 2, f->y0 + f->h + 40, 15, 0.5, xlabel);
    if (ylabel) /* left of the widest tick label, its glyphs (15 px) on the page */
        vtext(cr, fmax(fmin(f->x0 - 58, f->x0 - 6 - wide - 8), 15), f->y0 + f->h / 2, 15,
              ylabel);
}

/* A dashed grey guide line from (x0, y0) to (x1, y1) in device units. */
static void dashed(cairo_t *cr, double x0, double y0, double x1, double y1)
{
    double dash[] = {6.0, 4.0};
    cairo_save(cr);
    cairo_set_source_rgb(cr, 0.2, 0.2, 0.2);
    cairo_set_dash(cr, dash, 2, 0);
    cairo_set_line_width(cr, 1.2);
    cairo_move_to(cr, x0, y0);
    cairo_line_to(cr, x1, y1);
    cairo_stroke(cr);
    cairo_restore(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
}

/* Dashed horizontal guide at data y, labelled at the right on a pale box:
 * a curve running along the guide (min x_n just over +b) would cross the
 * label and make it unreadable, and still shows through the box. */
static void hguide(cairo_t *cr, const frame *f, double y, const char *label)
{
    if (y < f->ymin || y > f->ymax)
        return;
    dashed(cr, f->x0, py(f, y), f->x0 + f->w, py(f, y));
    cairo_text_extents_t e;
    cairo_select_font_face(cr, PD_FONT, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 12);
    cairo_text_extents(cr, label, &e);
    double right = f->x0 + f->w - 5, base = py(f, y) - 4;
    cairo_set_source_rgba(cr, 1, 1, 1, 0.8);
    cairo_rectangle(cr, right - e.x_advance - 2, base + e.y_bearing - 1, e.x_advance + 4,
                    e.height + 2);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(cr, right, base, 12, 1.0, label);
}

/* Dashed vertical guide at data x, labelled above. */
static void vguide(cairo_t *cr, const frame *f, double x, const char *label)
{
    if (x < f->xmin || x > f->xmax)
        return;
    dashed(cr, px(f, x), f->y0, px(f, x), f->y0 + f->h);
    text(cr, px(f, x) + 4, f->y0 + f->h - 8, 12, 0.0, label);
}

/* A second scale on an axis of f: where 0 on top, 1 a second row under
 * the x numbers, 2 on the right. Ticks at its own round values. */
static void scale2(cairo_t *cr, const frame *f, const plot_scale2 *sc, int where)
{
    if (!(sc->k > 0))
        return;
    int vert = where == 2;
    double lo = (vert ? f->ymin : f->xmin) * sc->k, hi = (vert ? f->ymax : f->xmax) * sc->k;
    double st = sc->step > 0 ? sc->step : tick_step(lo, hi, vert ? 6 : 8), bot = f->y0 + f->h, right = f->x0 + f->w;
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_set_line_width(cr, 1.0);
    double t[PD_TICKS_MAX];
    char lab[PD_TICKS_MAX][PD_TICK_LABEL];
    for (int i = 0, n = pd_ticks(lo, hi, st, t, lab); i < n; i++) {
        double u = t[i], d = u / sc->k;
        if (where == 0) {
            cairo_move_to(cr, px(f, d), f->y0), cairo_line_to(cr, px(f, d), f->y0 + 6);
            text(cr, px(f, d), f->y0 - 7, 13, 0.5, lab[i]);
        } else if (where == 1) {
            cairo_move_to(cr, px(f, d), bot), cairo_line_to(cr, px(f, d), bot + 5);
            text(cr, px(f, d), bot + 64, 13, 0.5, lab[i]);
        } else {
            cairo_move_to(cr, right, py(f, d)), cairo_line_to(cr, right - 6, py(f, d));
            text(cr, right + 6, py(f, d) + 5, 13, 0.0, lab[i]);
        }
        cairo_stroke(cr);
    }
    if (where == 0)
        text(cr, f->x0 + f->w / 2, f->y0 - 27, 15, 0.5, sc->label);
    else if (where == 1)
        text(cr, f->x0 + f->w / 2, bot + 86, 15, 0.5, sc->label);
    else
        vtext(cr, right + 66, f->y0 + f->h / 2, 15, sc->label);
}

void pd_scale2(cairo_t *cr, const frame *f, const plot_scale2 *sc, int where)
{
    scale2(cr, f, sc, where);
}

/* A note in the frame's top left corner, on a white box. */
static void note(cairo_t *cr, const frame *f, const char *s)
{
    cairo_text_extents_t e;
    cairo_select_font_face(cr, PD_FONT, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 14);
    cairo_text_extents(cr, s, &e);
    cairo_set_source_rgba(cr, 1, 1, 1, 0.85);
    cairo_rectangle(cr, f->x0 + 8, f->y0 + 8, e.x_advance + 12, 24);
    cairo_fill(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(cr, f->x0 + 14, f->y0 + 25, 14, 0.0, s);
}

/* ---- bifurcation diagram ---------------------------------------------------- */

/* Data ranges of the Poincare x_n of both sweeps. */
static void bif_range(const plot_bif *pb, double *lo, double *hi, double *xlo, double *xhi)
{
    *lo = INFINITY, *hi = -INFINITY, *xlo = INFINITY, *xhi = -INFINITY;
    const wg_point *sets[2] = {pb->up, pb->down};
    int ns[2] = {pb->nup, pb->ndown};
    for (int s = 0; s < 2; s++)
        for (int i = 0; i < ns[s]; i++) {
            const wg_point *p = &sets[s][i];
            *xlo = fmin(*xlo, p->value);
            *xhi = fmax(*xhi, p->value);
            for (int k = 0; k < p->nsec; k++) {
                *lo = fmin(*lo, p->xn[k]);
                *hi = fmax(*hi, p->xn[k]);
            }
        }
    if (!(*xhi > *xlo)) { /* one value (or none): a window about it, 5 % a side */
        double x = isfinite(*xlo) ? *xlo : 1.0, d = x != 0.0 ? 0.05 * fabs(x) : 0.5;
        *xlo = x - d, *xhi = x + d;
        return;
    }
    /* half a grid step beyond the first and last points, so their marks and
     * their regime cells are whole inside the frame (they were cut in half at
     * its edges); at most 2.5 % of the range */
    double step = INFINITY;
    for (int s = 0; s < 2; s++)
        if (ns[s] > 1)
            step = fmin(step, fabs(sets[s][1].value - sets[s][0].value));
    double pad = fmin(0.5 * step, 0.025 * (*xhi - *xlo));
    if (pad > 0) /* not for a first step of 0 or none */
        *xlo -= pad, *xhi += pad;
}

/* Shade cells of the points' regimes between y0 and y0 + h (pixels). */
static void shade(cairo_t *cr, const frame *f, const wg_point *pts, int n, double y0, double h)
{
    for (int i = 0; i < n; i++) {
        double rgb[3], v = pts[i].value;
        double a = i > 0 ? 0.5 * (v + pts[i - 1].value) : v;
        double b = i + 1 < n ? 0.5 * (v + pts[i + 1].value) : v;
        if (i == 0 && n > 1)
            a = v - (b - v);
        if (i + 1 == n && n > 1)
            b = v + (v - a);
        if (n == 1) /* a band of 2 % of the axis, not none */
            a = v - 0.01 * (f->xmax - f->xmin), b = v + 0.01 * (f->xmax - f->xmin);
        double xa = px(f, fmin(a, b)), xb = px(f, fmax(a, b));
        xa = fmax(xa, f->x0);
        xb = fmin(xb, f->x0 + f->w);
        plot_regime_colour(&pts[i], 0, rgb);
        set_rgb(cr, rgb, 1.0);
        cairo_rectangle(cr, xa, y0, xb - xa + 0.5, h);
        cairo_fill(cr);
    }
}

/* 1 if a mark at canvas height cy was drawn for this point already (the
 * point's marks share its x); else it is added to seen. Heights are one
 * when they round to the same 1/64 px: a period-n orbit's WG_POINT_NSEC
 * sections fall on n spots, and one fill or stroke of the path covers
 * circles at one spot as it covers one circle. NaN matches nothing. */
static int spot_seen(double *seen, int *nseen, double cy)
{
    double q = nearbyint(cy * 64.0);
    for (int j = 0; j < *nseen; j++)
        if (seen[j] == q)
            return 1;
    seen[(*nseen)++] = q;
    return 0;
}

/* Each point's Poincare spots as small squares, each spot once. */
static void dots(cairo_t *cr, const frame *f, const wg_point *pts, int n, const double c[3])
{
    set_rgb(cr, c, 0.7);
    double seen[WG_POINT_NSEC];
    for (int i = 0; i < n; i++) {
        int nseen = 0;
        for (int k = 0; k < pts[i].nsec; k++) {
            double cy = py(f, pts[i].xn[k]);
            if (!spot_seen(seen, &nseen, cy))
                cairo_rectangle(cr, px(f, pts[i].value) - 1.2, cy - 1.2, 2.4, 2.4);
        }
    }
    cairo_fill(cr);
}

/* The min x_n line; a point not measured (wg_point_measured) breaks it (it
 * was drawn at the panel's floor), and one measured alone is a dot. */
static void min_curve(cairo_t *cr, const frame *f, const wg_point *pts, int n, const double c[3])
{
    set_rgb(cr, c, 0.9);
    cairo_set_line_width(cr, 1.4);
    for (int i = 0, run = 0; i < n; i++) {
        if (!wg_point_measured(&pts[i])) {
            run = 0;
            continue;
        }
        double x = px(f, pts[i].value), y = py(f, fmax(f->ymin, pts[i].min_xn));
        int alone = (i == 0 || !wg_point_measured(&pts[i - 1])) &&
                    (i + 1 == n || !wg_point_measured(&pts[i + 1]));
        if (alone) { /* a line of one point draws nothing */
            cairo_stroke(cr);
            cairo_new_sub_path(cr);
            cairo_arc(cr, x, y, 2.5, 0, 2 * M_PI);
            cairo_fill(cr);
        } else if (!run++) {
            cairo_move_to(cr, x, y);
        } else {
            cairo_line_to(cr, x, y);
        }
    }
    cairo_stroke(cr);
}

static void legend_box(cairo_t *cr, double x, double y, const double rgb[3], const char *label)
{
    set_rgb(cr, rgb, 1.0);
    cairo_rectangle(cr, x, y - 11, 14, 14);
    cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.3, 0.3, 0.3);
    cairo_set_line_width(cr, 0.6);
    cairo_stroke(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(cr, x + 19, y, 12, 0.0, label);
}

/* The up sweep's Poincare x_n as filled dots, the down sweep's as rings
 * (a dot in a ring where they agree, either alone where they differ); at
 * the legend's (x, y) when f is NULL. */
static void sweep_marks(cairo_t *cr, const frame *f, const wg_point *pts, int n, int up,
                        double x, double y)
{
    set_rgb(cr, up ? C_UP : C_DOWN, up ? 0.85 : 0.8);
    cairo_set_line_width(cr, 1.1);
    double seen[WG_POINT_NSEC];
    for (int i = 0; i < (f ? n : 1); i++) {
        int nseen = 0;
        for (int k = 0; k < (f ? pts[i].nsec : 1); k++) {
            double cx = f ? px(f, pts[i].value) : x, cy = f ? py(f, pts[i].xn[k]) : y;
            if (spot_seen(seen, &nseen, cy))
                continue;
            cairo_new_sub_path(cr);
            cairo_arc(cr, cx, cy, up ? 1.6 : 3.6, 0, 2 * M_PI);
        }
    }
    if (up)
        cairo_fill(cr);
    else
        cairo_stroke(cr);
}

/* The legend; `other` adds the dark cells of points with no regime (a rig's
 * refused point, a ramp's aperiodic bin) or diverged (only when the figure
 * has some: the others' legend stays as it was). */
static void bif_legend(cairo_t *cr, double x, double y, const char *shading, int other)
{
    static const struct {
        int regime, period;
        const char *label;
    } items[] = {{WG_REGIME_PERIODIC, 1, "period 1"}, {WG_REGIME_PERIODIC, 2, "period 2"},
                 {WG_REGIME_PERIODIC, 4, "period 4"}, {WG_REGIME_PERIODIC, 8, "period 8-32"},
                 {WG_REGIME_PERIODIC, 3, "other period"},
                 {WG_REGIME_PERIODIC, 0, "P unresolved"},
                 {WG_REGIME_QUASIPERIODIC, 0, "quasi-periodic"},
                 {WG_REGIME_CHAOTIC, 0, "chaotic"}};
    for (unsigned i = 0; i < sizeof items / sizeof items[0]; i++) {
        wg_point p = {.regime = items[i].regime, .period = items[i].period};
        double rgb[3];
        plot_regime_colour(&p, 0, rgb);
        legend_box(cr, x + 118.0 * i, y, rgb, items[i].label);
    }
    double mx = x + 118.0 * (sizeof items / sizeof items[0]) + 20;
    if (other) {
        wg_point p = {.regime = WG_REGIME_DIVERGED};
        double rgb[3];
        plot_regime_colour(&p, 0, rgb);
        legend_box(cr, x + 640, y + 22, rgb,
                   "no regime (refused, or a ramp bin unclassified); diverged");
    }
    sweep_marks(cr, NULL, NULL, 0, 1, mx + 7, y - 4);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(cr, mx + 19, y, 12, 0.0, "up sweep");
    sweep_marks(cr, NULL, NULL, 0, 0, mx + 117, y - 4);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(cr, mx + 129, y, 12, 0.0, "down sweep");
    text(cr, x, y + 22, 12, 0.0, shading);
}

/* The guides x_n = +-b where b is the swept parameter itself (the x
 * axis): two dashed diagonals, clipped to the frame, the +b one labelled
 * (labelled != 0) under its rightmost point in the frame. */
static void b_swept(cairo_t *cr, const frame *f, int labelled)
{
    cairo_save(cr);
    cairo_rectangle(cr, f->x0, f->y0, f->w, f->h);
    cairo_clip(cr);
    for (int sgn = -1; sgn <= 1; sgn += 2)
        dashed(cr, px(f, f->xmin), py(f, sgn * f->xmin), px(f, f->xmax), py(f, sgn * f->xmax));
    cairo_restore(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    /* the label under the line's rightmost point inside the frame */
    for (int i = 20; labelled && i >= 0; i--) {
        double x = f->xmin + (f->xmax - f->xmin) * i / 20.0;
        if (x >= f->ymin && x <= f->ymax) {
            text(cr, px(f, x) - 4, fmin(py(f, x) + 16, f->y0 + f->h - 4), 12, 1.0,
                 "x_n = +b (b swept)");
            break;
        }
    }
}

/* The strips "up"/"down" and the main panel with shading, dots, guides. */
static void bif_main(cairo_t *cr, const plot_bif *pb, const frame *f, const char *ylabel)
{
    int up = pb->nup > 0;
    shade(cr, f, up ? pb->up : pb->down, up ? pb->nup : pb->ndown, f->y0, f->h);
    shade(cr, f, pb->up, pb->nup, f->y0 - 34, 14);
    shade(cr, f, pb->down, pb->ndown, f->y0 - 18, 14);
    cairo_set_source_rgb(cr, 0, 0, 0);
    text(cr, f->x0 - 6, f->y0 - 23, 11, 1.0, "up");
    text(cr, f->x0 - 6, f->y0 - 7, 11, 1.0, "down");
    sweep_marks(cr, f, pb->down, pb->ndown, 0, 0, 0);
    sweep_marks(cr, f, pb->up, pb->nup, 1, 0, 0);
    char lab[32];
    if (isnan(pb->b)) {
        b_swept(cr, f, 1);
    } else {
        snprintf(lab, sizeof lab, "+b = %g", pb->b);
        hguide(cr, f, pb->b, lab);
        snprintf(lab, sizeof lab, "-b = %g", -pb->b);
        if (-pb->b >= f->ymin)
            hguide(cr, f, -pb->b, lab);
        else
            text(cr, f->x0 + f->w - 5, f->y0 + f->h - 6, 12, 1.0, "(-b below)");
    }
    axes(cr, f, pb->xlabel, ylabel, 0);
    scale2(cr, f, &pb->y2, 2);
}

int plot_bifurcation(const char *path, const plot_bif *pb, char *why, size_t whylen)
{
    static const char ylab[] = "Poincaré x_n at ψ = 0  (b_c)", ylab2[] = "min x_n over the orbit  (b_c)";
    cairo_surface_t *s;
    cairo_t *cr = pd_canvas(path, pb->pg.format, 1400, 1030, &s);
    double lo, hi, xlo, xhi;
    bif_range(pb, &lo, &hi, &xlo, &xhi);
    if (!isfinite(lo)) {
        lo = pb->b - 1.0;
        hi = pb->b + 1.0;
    }
    lo = fmin(lo, pb->b); /* fmin, fmax: a swept b (NAN) adds nothing */
    hi = fmax(hi, pb->b);
    pd_min_span(&lo, &hi);
    double pad = 0.05 * (hi - lo + 1e-9), y = pd_page_head(cr, 1400, pb->title, &pb->pg);
    frame top = {90, y + 98, 1210, 560 - (y - 30), xlo, xhi, lo - pad, hi + pad};
    const char *shading = pb->nup ? "background: regime of the up sweep (the strips above the "
                                    "panel: up, then down)"
                                  : "background: regime of the down sweep (the strips above the "
                                    "panel: up, then down)";
    int other = 0;
    for (int i = 0; i < pb->nup + pb->ndown; i++) {
        const wg_point *p = i < pb->nup ? &pb->up[i] : &pb->down[i - pb->nup];
        other |= p->regime == WG_REGIME_NONE || p->regime == WG_REGIME_DIVERGED;
    }
    bif_legend(cr, 90, y + 30, shading, other);
    bif_main(cr, pb, &top, ylab);
    /* min x_n panel, spanning +-b (the data alone where b is swept) */
    double mlo = isnan(pb->b) ? INFINITY : -pb->b, mhi = isnan(pb->b) ? -INFINITY : pb->b;
    const wg_point *sets[2] = {pb->up, pb->down};
    int ns[2] = {pb->nup, pb->ndown};
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < ns[k]; i++)
            if (isfinite(sets[k][i].min_xn)) {
                mlo = fmin(mlo, sets[k][i].min_xn);
                mhi = fmax(mhi, sets[k][i].min_xn);
            }
    if (isnan(pb->b))
        pd_min_span(&mlo, &mhi);
    double mp = 0.06 * (mhi - mlo);
    frame bot = {90, top.y0 + top.h + 30, 1210, 200, xlo, xhi, mlo - mp, mhi + mp};
    min_curve(cr, &bot, pb->down, pb->ndown, C_DOWN);
    min_curve(cr, &bot, pb->up, pb->nup, C_UP);
    if (isnan(pb->b)) {
        b_swept(cr, &bot, 0); /* the lower panel's too narrow for the label */
    } else {
        hguide(cr, &bot, pb->b, "+b");
        hguide(cr, &bot, -pb->b, "-b");
    }
    axes(cr, &bot, pb->xlabel, ylab2, 1);
    scale2(cr, &bot, &pb->y2, 2);
    scale2(cr, &bot, &pb->x2, 1);
    pd_doc d;
    pd_doc_init(&d, pb->title, &pb->pg);
    pd_words(&d, NULL, shading);
    pd_words(&d, "x axis", pb->xlabel), pd_words(&d, "x axis, second scale", pb->x2.label);
    pd_words(&d, "y axis", ylab), pd_words(&d, "lower panel", ylab2);
    pd_words(&d, "y axis, second scale", pb->y2.label);
    return pd_finish(s, cr, path, pb->pg.format, &d, why, whylen);
}

/* ---- x-y plots -------------------------------------------------------------- */

/* Points [i0, i1) of p as a line (dots 0) or a cloud; marks 1: a dot at
 * each point, 2: a ring. */
static void xy_series(cairo_t *cr, const frame *f, const plot_xy *p, int i0, int i1,
                      const double rgb[3], int marks)
{
    set_rgb(cr, rgb, p->dots ? 0.8 : 0.9);
    cairo_set_line_width(cr, marks ? 1.5 : 1.0);
    for (int i = i0; i < i1; i++) {
        if (p->dots) {
            cairo_new_sub_path(cr);
            cairo_arc(cr, px(f, p->x[i]), py(f, p->y[i]), p->n < 100 ? 3.5 : 2.0, 0, 2 * M_PI);
        } else if (i == i0) {
            cairo_move_to(cr, px(f, p->x[i]), py(f, p->y[i]));
        } else {
            cairo_line_to(cr, px(f, p->x[i]), py(f, p->y[i]));
        }
    }
    if (p->dots)
        cairo_fill(cr);
    else
        cairo_stroke(cr);
    for (int i = i0; marks && i < i1; i++) {
        cairo_new_sub_path(cr);
        cairo_arc(cr, px(f, p->x[i]), py(f, p->y[i]), marks == 1 ? 2.5 : 4.5, 0, 2 * M_PI);
    }
    if (marks == 1)
        cairo_fill(cr);
    else if (marks == 2)
        cairo_stroke(cr);
}

static void xy_data(cairo_t *cr, const frame *f, const plot_xy *p)
{
    cairo_save(cr);
    cairo_rectangle(cr, f->x0, f->y0, f->w, f->h);
    cairo_clip(cr);
    if (p->split > 0 && p->split <= p->n) { /* the down sweep under the up one */
        xy_series(cr, f, p, p->split, p->n, C_DOWN, 2);
        xy_series(cr, f, p, 0, p->split, C_UP, 1);
    } else {
        xy_series(cr, f, p, 0, p->n, C_UP, 0);
    }
    cairo_restore(cr);
}

/* The legend of a split plot: one row from x, its text's baseline at y. */
static void xy_legend(cairo_t *cr, double x, double y)
{
    static const char *const name[2] = {"up sweep", "down sweep"};
    for (int k = 0; k < 2; k++, x += 150) {
        set_rgb(cr, k ? C_DOWN : C_UP, 0.9);
        cairo_set_line_width(cr, 1.5);
        cairo_move_to(cr, x, y - 4), cairo_line_to(cr, x + 32, y - 4);
        cairo_stroke(cr);
        cairo_new_sub_path(cr);
        cairo_arc(cr, x + 16, y - 4, k ? 4.5 : 2.5, 0, 2 * M_PI);
        if (k)
            cairo_stroke(cr);
        else
            cairo_fill(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        text(cr, x + 40, y, 12, 0.0, name[k]);
    }
}

int plot_xy_write(const char *path, const plot_xy *p, char *why, size_t whylen)
{
    cairo_surface_t *s;
    cairo_t *cr = pd_canvas(path, p->pg.format, 1000, 850, &s);
    double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
    for (int i = 0; i < p->n; i++) {
        xlo = fmin(xlo, p->x[i]), xhi = fmax(xhi, p->x[i]);
        ylo = fmin(ylo, p->y[i]), yhi = fmax(yhi, p->y[i]);
    }
    if (p->b > 0 && p->b_on_x && !p->dots) /* curves: show where +b is; clouds: zoom */
        xlo = fmin(xlo, p->b), xhi = fmax(xhi, p->b);
    if (p->b > 0 && !p->b_on_x && !p->dots)
        ylo = fmin(ylo, p->b), yhi = fmax(yhi, p->b);
    pd_min_span(&xlo, &xhi);
    pd_min_span(&ylo, &yhi);
    double mx = 0.05 * (xhi - xlo), my = 0.05 * (yhi - ylo);
    double y = pd_page_head(cr, 1000, p->title, &p->pg);
    int split = p->split > 0 && p->split <= p->n;
    if (split) /* a legend row above the frame, where it hides no data */
        xy_legend(cr, 105, y + 16), y += 22;
    double top = y + (p->x2.k > 0 ? 62 : 24);
    frame f = {105, top, p->y2.k > 0 ? 785 : 845, 790 - top, xlo - mx, xhi + mx, ylo - my,
               yhi + my};
    xy_data(cr, &f, p);
    if (p->b > 0) {
        for (int sgn = -1; sgn <= 1; sgn += 2) {
            char lab[32];
            snprintf(lab, sizeof lab, "%sb", sgn > 0 ? "+" : "-");
            if (p->b_on_x)
                vguide(cr, &f, sgn * p->b, lab);
            else
                hguide(cr, &f, sgn * p->b, lab);
        }
    }
    axes(cr, &f, p->xlabel, p->ylabel, 1);
    scale2(cr, &f, &p->x2, 0);
    scale2(cr, &f, &p->y2, 2);
    if (p->note)
        note(cr, &f, p->note);
    pd_doc d;
    pd_doc_init(&d, p->title, &p->pg);
    pd_words(&d, NULL, p->note);
    pd_words(&d, "x axis", p->xlabel), pd_words(&d, "x axis, second scale", p->x2.label);
    pd_words(&d, "y axis", p->ylabel), pd_words(&d, "y axis, second scale", p->y2.label);
    return pd_finish(s, cr, path, p->pg.format, &d, why, whylen);
}

/* ---- the helpers for other figures (plot_draw.h) ----------------------------- */

void pd_text(cairo_t *cr, double x, double y, double size, double align, const char *s)
{
    text(cr, x, y, size, align, s);
}

void pd_halo(cairo_t *cr, double x, double y, double size, double align, const char *s)
{
    cairo_new_path(cr);
    text_at(cr, x, y, size, align, s);
    cairo_text_path(cr, s);
    cairo_save(cr);
    cairo_set_dash(cr, NULL, 0, 0);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_set_line_width(cr, 2.0 * PD_HALO);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    cairo_stroke_preserve(cr);
    cairo_fill(cr);
    cairo_restore(cr);
}

void pd_axes(cairo_t *cr, const frame *f, const char *xlabel, const char *ylabel, int xnumbers)
{
    axes(cr, f, xlabel, ylabel, xnumbers);
}

void pd_hguide(cairo_t *cr, const frame *f, double y, const char *label)
{
    hguide(cr, f, y, label);
}

void pd_legend_box(cairo_t *cr, double x, double y, const double rgb[3], const char *label)
{
    legend_box(cr, x, y, rgb, label);
}

void pd_dots(cairo_t *cr, const frame *f, const wg_point *pts, int n, const double c[3])
{
    dots(cr, f, pts, n, c);
}

void pd_min_curve(cairo_t *cr, const frame *f, const wg_point *pts, int n, const double c[3])
{
    min_curve(cr, f, pts, n, c);
}

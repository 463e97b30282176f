/* plot_cont.c - the continuation figure (see plot_cont.h). */
#include "plot_cont.h"
#include "plot_draw.h"

#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

enum { W = 1400, H = 1040 };

/* Colour of a branch by its period. */
static void period_rgb(int n, double rgb[3])
{
    static const double c[4][3] = {{0.05, 0.05, 0.05}, {0.00, 0.50, 0.20}, {0.50, 0.15, 0.60},
                                   {0.85, 0.45, 0.00}};
    int k = n == 1 ? 0 : n == 2 ? 1 : n == 4 ? 2 : 3;
    memcpy(rgb, c[k], sizeof c[k]);
}

/* The value plotted for point p in panel `bot`: section k's x_n, or min x_n. */
static double yval(const wg_cont_point *p, int k, int bot)
{
    return bot ? p->qmin[WG_C_MESH] : p->xnsec[k];
}

/* Data range of a panel: branches and sweep. */
static void yrange(const plot_cont *pc, int bot, double *lo, double *hi)
{
    *lo = *hi = pc->b; /* +b always, -b once the data go below zero */
    for (int i = 0; i < pc->r->npt; i++)
        for (int k = 0; k < (bot ? 1 : pc->r->pt[i].period); k++) {
            double v = yval(&pc->r->pt[i], k, bot);
            if (isfinite(v))
                *lo = fmin(*lo, v), *hi = fmax(*hi, v);
        }
    const wg_point *sets[2] = {pc->up, pc->down};
    int ns[2] = {pc->nup, pc->ndown};
    for (int s = 0; s < 2; s++)
        for (int i = 0; i < ns[s]; i++) {
            const wg_point *p = &sets[s][i];
            for (int k = 0; k < (bot ? 1 : p->nsec); k++) {
                double v = bot ? p->min_xn : p->xn[k];
                if (isfinite(v))
                    *lo = fmin(*lo, v), *hi = fmax(*hi, v);
            }
        }
    if (*lo < 0.0)
        *lo = fmin(*lo, -pc->b);
    pd_min_span(lo, hi); /* no points (stopped in the transient): +b alone */
    double pad = 0.05 * (*hi - *lo + 1e-9);
    *lo -= pad, *hi += pad;
}

/* Where on segment (i, i + 1) its stability changes: the fraction of the
 * way to a located bifurcation of the branch between the two points, or
 * -1 (none located: the segment counts as unstable, as before). */
static double change_at(const cont_result *r, int i)
{
    const wg_cont_point *a = &r->pt[i], *b = &r->pt[i + 1];
    for (int j = 0; j < r->nbif; j++) {
        const wg_bif *f = &r->bif[j];
        if (f->branch != a->branch || f->kind == WG_BIF_GRAZING || b->value == a->value)
            continue;
        double t = (f->value - a->value) / (b->value - a->value);
        if (t > 0.0 && t < 1.0)
            return t;
    }
    return -1.0;
}

/* The point t of the way along segment (i, i + 1) of section k, device. */
static void seg_at(const frame *f, const cont_result *r, int i, int k, int bot, double t,
                   double *x, double *y)
{
    const wg_cont_point *a = &r->pt[i], *b = &r->pt[i + 1];
    *x = px(f, a->value + t * (b->value - a->value));
    *y = py(f, yval(a, k, bot) + t * (yval(b, k, bot) - yval(a, k, bot)));
}

/* Stroke one run of segments [i0, i1] of section k: solid or dashed. A
 * dashed run whose end segment has a stable end starts (or ends) at the
 * bifurcation located on that segment, and the piece up to it is solid:
 * the curve turned dashed at the last stable point, not at the doubling. */
static void run_stroke(cairo_t *cr, const frame *f, const cont_result *r, int i0, int i1, int k,
                       int bot, int stable)
{
    static const double dash[] = {7.0, 5.0};
    double rgb[3], x, y;
    period_rgb(r->pt[i1].period, rgb);
    cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
    double t0 = !stable && r->pt[i0].stable ? change_at(r, i0) : -1.0;
    double t1 = !stable && r->pt[i1].stable ? change_at(r, i1 - 1) : -1.0;
    cairo_set_dash(cr, dash, 0, 0); /* the solid pieces */
    if (t0 > 0.0) {
        cairo_move_to(cr, px(f, r->pt[i0].value), py(f, yval(&r->pt[i0], k, bot)));
        seg_at(f, r, i0, k, bot, t0, &x, &y);
        cairo_line_to(cr, x, y);
    }
    if (t1 > 0.0) {
        seg_at(f, r, i1 - 1, k, bot, t1, &x, &y);
        cairo_move_to(cr, x, y);
        cairo_line_to(cr, px(f, r->pt[i1].value), py(f, yval(&r->pt[i1], k, bot)));
    }
    cairo_stroke(cr);
    cairo_set_dash(cr, dash, stable ? 0 : 2, 0);
    if (t0 > 0.0) {
        seg_at(f, r, i0, k, bot, t0, &x, &y);
        cairo_move_to(cr, x, y);
    } else {
        cairo_move_to(cr, px(f, r->pt[i0].value), py(f, yval(&r->pt[i0], k, bot)));
    }
    for (int i = i0 + 1; i <= i1; i++) {
        if (i == i1 && t1 > 0.0)
            seg_at(f, r, i1 - 1, k, bot, t1, &x, &y);
        else
            x = px(f, r->pt[i].value), y = py(f, yval(&r->pt[i], k, bot));
        cairo_line_to(cr, x, y);
    }
    cairo_stroke(cr);
}

/* The branches: per section, runs of consecutive points of one branch
 * with the same stability (a segment is stable when both ends are), each
 * stroked as one path so the dashes run on across short segments. */
static void branches(cairo_t *cr, const frame *f, const cont_result *r, int bot)
{
    cairo_save(cr);
    cairo_rectangle(cr, f->x0, f->y0, f->w, f->h);
    cairo_clip(cr);
    cairo_set_line_width(cr, 2.0);
    cairo_set_line_join(cr, CAIRO_LINE_JOIN_ROUND);
    for (int i0 = 0; i0 + 1 < r->npt;) {
        const wg_cont_point *a = &r->pt[i0];
        int stable = a->stable && r->pt[i0 + 1].stable, i1 = i0;
        while (i1 + 1 < r->npt && r->pt[i1 + 1].branch == a->branch &&
               r->pt[i1 + 1].period == a->period &&
               (r->pt[i1].stable && r->pt[i1 + 1].stable) == stable)
            i1++;
        for (int k = 0; k < (bot ? 1 : a->period) && i1 > i0; k++)
            run_stroke(cr, f, r, i0, i1, k, bot, stable);
        i0 = i1 > i0 ? i1 : i0 + 1;
    }
    cairo_restore(cr);
}

static const char *code(int kind)
{
    static const char *const c[WG_NBIF] = {"F", "PD", "NS", "G", "BP"};
    return kind >= 0 && kind < WG_NBIF ? c[kind] : "?";
}

/* A marker of a bifurcation kind centred at (x, y). */
static void marker(cairo_t *cr, int kind, double x, double y)
{
    double r = 6.0;
    cairo_new_path(cr);
    switch (kind) {
    case WG_BIF_FOLD: cairo_rectangle(cr, x - r, y - r, 2 * r, 2 * r); break;
    case WG_BIF_PD:
        cairo_move_to(cr, x, y - r - 1);
        cairo_line_to(cr, x + r + 1, y + r);
        cairo_line_to(cr, x - r - 1, y + r);
        cairo_close_path(cr);
        break;
    case WG_BIF_TORUS:
        cairo_move_to(cr, x, y - r - 2);
        cairo_line_to(cr, x + r + 1, y);
        cairo_line_to(cr, x, y + r + 2);
        cairo_line_to(cr, x - r - 1, y);
        cairo_close_path(cr);
        break;
    case WG_BIF_GRAZING: cairo_arc(cr, x, y, r, 0, 2 * M_PI); break;
    default:
        cairo_move_to(cr, x - r, y - r);
        cairo_line_to(cr, x + r, y + r);
        cairo_move_to(cr, x + r, y - r);
        cairo_line_to(cr, x - r, y + r);
    }
    cairo_set_source_rgb(cr, 1, 1, 1);
    if (kind != WG_BIF_BP)
        cairo_fill_preserve(cr);
    cairo_set_source_rgb(cr, 0.75, 0.0, 0.0);
    cairo_set_line_width(cr, 2.0);
    cairo_stroke(cr);
}

/* Boxes taken so far (device coordinates): the markers', then the labels',
 * to keep new labels off them; and the labels placed, drawn once all are. */
enum { BOXES_MAX = 256 };
typedef struct label {
    double x, y;      /* the text's start and baseline */
    double lx[2], ly[2]; /* a leader line from the marker (lx[0] NAN: none) */
    char s[48];
} label;
typedef struct boxes {
    double x[BOXES_MAX][4];
    int n;
    label lab[BOXES_MAX];
    int nlab;
} boxes;

static int overlaps(const boxes *bx, double x0, double y0, double x1, double y1)
{
    for (int i = 0; i < bx->n; i++)
        if (x0 < bx->x[i][2] && bx->x[i][0] < x1 && y0 < bx->x[i][3] && bx->x[i][1] < y1)
            return 1;
    return 0;
}

/* A label near (x, y): the first of a few heights, right of the marker or
 * else left of it, that stays in the frame (one ran over the right axis's
 * numbers) and overlaps no earlier label and no marker; none if all do
 * (the marker stays, the CSV has every value). A label moved off its
 * marker's height gets a thin leader line to it (which label was whose
 * could not be told where they crowd). Kept in bx, drawn by draw_labels. */
static void place_label(cairo_t *cr, const frame *f, boxes *bx, double x, double y,
                        const char *lab)
{
    static const double dy[] = {-10, 6, -24, 20, -38, 34, -52, 48};
    cairo_text_extents_t e;
    cairo_select_font_face(cr, PD_FONT, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 10.5);
    cairo_text_extents(cr, lab, &e);
    for (unsigned k = 0; k < sizeof dy / sizeof dy[0] && bx->n < BOXES_MAX; k++) {
        double ly = fmin(fmax(y + dy[k], f->y0 + 12), f->y0 + f->h - 4);
        for (int side = 0; side < 2; side++) {
            double x0 = side ? x - 9 - e.x_advance : x + 9, y0 = ly - 10;
            double x1 = x0 + e.x_advance, y1 = ly + 2;
            if (x0 < f->x0 + 2 || x1 > f->x0 + f->w - 2 || overlaps(bx, x0, y0, x1, y1))
                continue;
            double *b = bx->x[bx->n++];
            b[0] = x0, b[1] = y0, b[2] = x1, b[3] = y1;
            label *l = &bx->lab[bx->nlab++];
            l->x = x0, l->y = ly, l->lx[0] = NAN;
            snprintf(l->s, sizeof l->s, "%s", lab);
            if (k >= 2) { /* from the marker's edge to the label's near end */
                double ex = side ? x1 + 1 : x0 - 1, ey = ly - 4, d = hypot(ex - x, ey - y);
                l->lx[0] = x + (ex - x) * 8 / d, l->ly[0] = y + (ey - y) * 8 / d;
                l->lx[1] = ex, l->ly[1] = ey;
            }
            return;
        }
    }
}

/* The labels placed: their leader lines, then every label's halo, then
 * every label's text, so that a halo clears the curves and leaders under
 * its label but never another label's letters. */
static void draw_labels(cairo_t *cr, const boxes *bx)
{
    cairo_set_source_rgb(cr, 0.55, 0.0, 0.0);
    cairo_set_line_width(cr, 0.7);
    for (int i = 0; i < bx->nlab; i++)
        if (!isnan(bx->lab[i].lx[0])) {
            cairo_move_to(cr, bx->lab[i].lx[0], bx->lab[i].ly[0]);
            cairo_line_to(cr, bx->lab[i].lx[1], bx->lab[i].ly[1]);
            cairo_stroke(cr);
        }
    for (int i = 0; i < bx->nlab; i++)
        pd_halo(cr, bx->lab[i].x, bx->lab[i].y, 10.5, 0.0, bx->lab[i].s);
    cairo_set_source_rgb(cr, 0.55, 0.0, 0.0);
    for (int i = 0; i < bx->nlab; i++)
        pd_text(cr, bx->lab[i].x, bx->lab[i].y, 10.5, 0.0, bx->lab[i].s);
}

/* Markers in both panels; then labels in the top one, one per event (a
 * body's bearing axes grazing together share a label): no marker drawn
 * later covers a label, and a curve under a label does not cross its
 * letters (draw_labels). */
static void bifurcations(cairo_t *cr, const frame *top, const frame *bot, const cont_result *r)
{
    char lab[48];
    boxes *bx = calloc(1, sizeof *bx);
    /* every marker first, its top-panel box kept so that no label covers
     * it (half the boxes at most: the rest are the labels') */
    for (int i = 0; i < r->nbif; i++) {
        const wg_bif *b = &r->bif[i];
        if (!(b->value >= top->xmin && b->value <= top->xmax)) /* NaN too */
            continue;
        double x = px(top, b->value), y = py(top, b->xn);
        if (bx && bx->n < BOXES_MAX / 2) {
            double *m = bx->x[bx->n++];
            m[0] = x - 8, m[1] = y - 9, m[2] = x + 8, m[3] = y + 9;
        }
        marker(cr, b->kind, x, y);
        marker(cr, b->kind, x, py(bot, fmax(bot->ymin, b->min_xn)));
    }
    for (int i = 0; i < r->nbif && bx; i++) {
        const wg_bif *b = &r->bif[i];
        if (!(b->value >= top->xmin && b->value <= top->xmax)) /* NaN too */
            continue;
        if (i > 0 && r->bif[i - 1].kind == b->kind && fabs(r->bif[i - 1].value - b->value) < 1e-6)
            continue;
        if (b->kind == WG_BIF_GRAZING)
            snprintf(lab, sizeof lab, "G %s %.5f", wg_contact_name(b->contact), b->value);
        else
            snprintf(lab, sizeof lab, "%s P%d %.5f", code(b->kind), b->period, b->value);
        place_label(cr, top, bx, px(top, b->value), py(top, b->xn), lab);
    }
    if (bx)
        draw_labels(cr, bx);
    free(bx);
}

static void legend(cairo_t *cr, const plot_cont *pc, double y)
{
    static const int per[4] = {1, 2, 4, 8};
    static const char *const pl[4] = {"period 1", "period 2", "period 4", "period 8+"};
    double x = 90;
    if (pc->nup || pc->ndown) {
        pd_legend_box(cr, x, y, PD_UP, "sweep up");
        pd_legend_box(cr, x + 105, y, PD_DOWN, "sweep down");
        x += 225;
    }
    for (int k = 0; k < 4; k++) {
        double rgb[3];
        period_rgb(per[k], rgb);
        pd_legend_box(cr, x + 95.0 * k, y, rgb, pl[k]);
    }
    x += 390;
    cairo_set_source_rgb(cr, 0, 0, 0);
    pd_text(cr, x, y, 12, 0.0, "solid: stable, dashed: unstable");
    x += 205;
    for (int k = 0; k < WG_NBIF; k++) { /* "PD doubling": the code the labels use, and what */
        char lab[40];
        const char *name = wg_bif_name(k) + (k == WG_BIF_PD ? 7 : 0);
        snprintf(lab, sizeof lab, "%s %s", code(k), k == WG_BIF_BP ? "branch point" : name);
        marker(cr, k, x + 6, y - 4);
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_text_extents_t e;
        cairo_set_font_size(cr, 11);
        cairo_text_extents(cr, lab, &e);
        pd_text(cr, x + 16, y, 11, 0.0, lab);
        x += 16 + e.x_advance + 14;
    }
}

int plot_continuation(const char *path, const plot_cont *pc, char *why, size_t whylen)
{
    cairo_surface_t *s;
    /* a second x scale takes a row of numbers and its label under the axis */
    cairo_t *cr = pd_canvas(path, pc->format, W, H + (pc->x2.k > 0 ? 46 : 0), &s);
    plot_page pg = {pc->format, {pc->caption[0], pc->caption[1], pc->caption[2], NULL}};
    pd_page_head(cr, W, pc->title, &pg);
    legend(cr, pc, 118);
    double lo, hi;
    yrange(pc, 0, &lo, &hi);
    frame top = {90, 140, 1210, 540, pc->xlo, pc->xhi, lo, hi};
    yrange(pc, 1, &lo, &hi);
    frame bot = {90, 730, 1210, 230, pc->xlo, pc->xhi, lo, hi};
    pd_dots(cr, &top, pc->down, pc->ndown, PD_DOWN);
    pd_dots(cr, &top, pc->up, pc->nup, PD_UP);
    pd_min_curve(cr, &bot, pc->down, pc->ndown, PD_DOWN);
    pd_min_curve(cr, &bot, pc->up, pc->nup, PD_UP);
    branches(cr, &top, pc->r, 0);
    branches(cr, &bot, pc->r, 1);
    pd_hguide(cr, &top, pc->b, "+b");
    pd_hguide(cr, &top, -pc->b, "-b");
    pd_hguide(cr, &bot, pc->b, "+b");
    pd_hguide(cr, &bot, -pc->b, "-b");
    bifurcations(cr, &top, &bot, pc->r);
    static const char yt[] = "x_n at the section ψ = 0  (units of b_c)",
                      yb[] = "min x_n over the orbit  (b_c)";
    pd_axes(cr, &top, pc->xlabel, yt, 0);
    pd_axes(cr, &bot, pc->xlabel, yb, 1);
    pd_scale2(cr, &bot, &pc->x2, 1);
    pd_scale2(cr, &top, &pc->y2, 2);
    pd_scale2(cr, &bot, &pc->y2, 2);
    pd_doc d;
    pd_doc_init(&d, pc->title, &pg);
    pd_words(&d, "x axis", pc->xlabel), pd_words(&d, "x axis, second scale", pc->x2.label);
    pd_words(&d, "y axis", yt), pd_words(&d, "lower panel", yb);
    pd_words(&d, "y axis, second scale", pc->y2.label);
    return pd_finish(s, cr, path, pc->format, &d, why, whylen);
}

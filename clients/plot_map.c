/* plot_map.c - the 2-D regime map (plot_regime_map, plot.h): one cell per
 * point, coloured by its regime or its motion class. */
#include "plot.h"
#include "plot_draw.h"

#include <math.h>
#include <string.h>

static void map_cell_colour(const wg_point *p, int mode, double rgb[3])
{
    static const double mot[3][3] = {{0.85, 0.90, 0.97}, {0.99, 0.75, 0.30}, {0.80, 0.10, 0.25}};
    if (mode == PLOT_MAP_MOTION && wg_point_measured(p)) { /* else dark: none, diverged */
        memcpy(rgb, mot[p->motion < 0 || p->motion > 2 ? 0 : p->motion], sizeof(double) * 3);
        return;
    }
    plot_regime_colour(p, 1, rgb);
}

/* The legend; other (the map has cells not measured or diverged) adds their
 * dark one. */
static void map_legend(cairo_t *cr, int mode, double x, double y, int other)
{
    if (other) {
        wg_point p = {.regime = WG_REGIME_DIVERGED};
        double rgb[3];
        plot_regime_colour(&p, 1, rgb);
        pd_legend_box(cr, x, y + 22, rgb, "no regime (not measured); diverged");
    }
    if (mode == PLOT_MAP_MOTION) {
        static const char *lab[3] = {"no impact", "single-sided", "double-sided"};
        for (int m = 0; m < 3; m++) {
            wg_point p = {.regime = WG_REGIME_PERIODIC, .motion = m};
            double rgb[3];
            map_cell_colour(&p, mode, rgb);
            pd_legend_box(cr, x + 150.0 * m, y, rgb, lab[m]);
        }
        return;
    }
    static const int per[] = {1, 2, 4, 8, 3, 0};
    static const char *lab[] = {"P1", "P2", "P4", "P8-32", "other P", "P unresolved"};
    for (int i = 0; i < 6; i++) {
        wg_point p = {.regime = WG_REGIME_PERIODIC, .period = per[i]};
        double rgb[3];
        plot_regime_colour(&p, 1, rgb);
        pd_legend_box(cr, x + 110.0 * i, y, rgb, lab[i]);
    }
    wg_point q = {.regime = WG_REGIME_QUASIPERIODIC}, c = {.regime = WG_REGIME_CHAOTIC};
    double rgb[3];
    plot_regime_colour(&q, 1, rgb);
    pd_legend_box(cr, x + 660, y, rgb, "quasi-periodic");
    plot_regime_colour(&c, 1, rgb);
    pd_legend_box(cr, x + 790, y, rgb, "chaotic");
}

int plot_regime_map(const char *path, const plot_map *pm, char *why, size_t whylen)
{
    cairo_surface_t *s;
    cairo_t *cr = pd_canvas(path, pm->pg.format, 1200, 860, &s);
    double xlo = INFINITY, xhi = -INFINITY, ylo = INFINITY, yhi = -INFINITY;
    for (int r = 0; r < pm->nrows; r++) {
        const wg_chain *c = &pm->rows[r];
        xlo = fmin(xlo, fmin(c->v0, c->v1));
        xhi = fmax(xhi, fmax(c->v0, c->v1));
        ylo = fmin(ylo, c->base.v[c->param2]);
        yhi = fmax(yhi, c->base.v[c->param2]);
    }
    int nr = pm->nrows, nx = pm->nrows ? pm->rows[0].npts : 1;
    /* one row (or column): a cell 10 % of its value wide, so the axis
     * keeps the parameter's sign (xi_p 0.05 spanned -0.45 ... 0.55) */
    double dx = nx > 1 ? (xhi - xlo) / (nx - 1) : xhi != 0.0 ? 0.1 * fabs(xhi) : 1.0;
    double dy = nr > 1 ? (yhi - ylo) / (nr - 1) : yhi != 0.0 ? 0.1 * fabs(yhi) : 1.0;
    double y = pd_page_head(cr, 1200, pm->title, &pm->pg);
    frame f = {110, y + 95, 960, 790 - (y + 95), xlo - dx / 2, xhi + dx / 2, ylo - dy / 2,
               yhi + dy / 2};
    for (int r = 0; r < nr; r++) {
        const wg_chain *c = &pm->rows[r];
        double yv = c->base.v[c->param2];
        for (int i = 0; i < c->ndone; i++) {
            double rgb[3];
            map_cell_colour(&c->pts[i], pm->mode, rgb);
            cairo_set_source_rgb(cr, rgb[0], rgb[1], rgb[2]);
            double xa = px(&f, c->pts[i].value - dx / 2), xb = px(&f, c->pts[i].value + dx / 2);
            double ya = py(&f, yv + dy / 2), yb = py(&f, yv - dy / 2);
            cairo_rectangle(cr, xa, ya, xb - xa + 0.6, yb - ya + 0.6);
            cairo_fill(cr);
        }
    }
    int other = 0;
    for (int r = 0; r < nr; r++)
        for (int i = 0; i < pm->rows[r].ndone; i++)
            other |= !wg_point_measured(&pm->rows[r].pts[i]);
    map_legend(cr, pm->mode, 110, y + 30, other);
    pd_axes(cr, &f, pm->xlabel, pm->ylabel, 1);
    pd_scale2(cr, &f, &pm->x2, 0);
    pd_scale2(cr, &f, &pm->y2, 2);
    pd_doc d;
    pd_doc_init(&d, pm->title, &pm->pg);
    pd_words(&d, "x axis", pm->xlabel), pd_words(&d, "x axis, second scale", pm->x2.label);
    pd_words(&d, "y axis", pm->ylabel), pd_words(&d, "y axis, second scale", pm->y2.label);
    return pd_finish(s, cr, path, pm->pg.format, &d, why, whylen);
}

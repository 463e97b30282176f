/* bench_plot.h - a log-log work-precision plot with cairo (error on x,
 * run time on y, one polyline with markers per method, a legend). Static
 * functions only: included by bench_wp.c. */
#ifndef WG_BENCH_PLOT_H
#define WG_BENCH_PLOT_H

#include <cairo.h>
#include <math.h>
#include <stdio.h>

typedef struct plot_series {
    const char *label;
    int n;
    const double *x, *y; /* positive values; non-finite points skipped */
    double rgb[3];
    int dashed;
} plot_series;

typedef struct plot_box {
    double x0, x1, y0, y1;           /* decades shown: 10^x0 .. 10^x1 */
    double left, right, top, bottom; /* pixel frame */
} plot_box;

static double plot_px(const plot_box *b, double x)
{
    return b->left + (log10(x) - b->x0) / (b->x1 - b->x0) * (b->right - b->left);
}

static double plot_py(const plot_box *b, double y)
{
    return b->bottom - (log10(y) - b->y0) / (b->y1 - b->y0) * (b->bottom - b->top);
}

static void plot_decade_label(cairo_t *cr, double x, double y, int e, int right_align)
{
    char buf[16];
    snprintf(buf, sizeof buf, "1e%d", e);
    cairo_text_extents_t te;
    cairo_text_extents(cr, buf, &te);
    cairo_move_to(cr, right_align ? x - te.width - 6 : x - te.width / 2, y);
    cairo_show_text(cr, buf);
}

/* Write a PNG of width x height, with the caption's lines (NULL-ended, at
 * most PLOT_CAPTION_MAX) under the title; returns 0 or -1. */
enum { PLOT_CAPTION_MAX = 3 };
static int plot_wp(const char *path, const char *title, const char *const *caption,
                   const char *xlabel, const char *ylabel, const plot_series *s, int ns,
                   int width, int height)
{
    int ncap = 0;
    while (caption && ncap < PLOT_CAPTION_MAX && caption[ncap])
        ncap++;
    double xmin = INFINITY, xmax = -INFINITY, ymin = INFINITY, ymax = -INFINITY;
    for (int i = 0; i < ns; i++)
        for (int j = 0; j < s[i].n; j++)
            if (isfinite(s[i].x[j]) && s[i].x[j] > 0 && isfinite(s[i].y[j]) && s[i].y[j] > 0) {
                xmin = fmin(xmin, s[i].x[j]);
                xmax = fmax(xmax, s[i].x[j]);
                ymin = fmin(ymin, s[i].y[j]);
                ymax = fmax(ymax, s[i].y[j]);
            }
    if (!(xmin < xmax) || !(ymin < ymax))
        return -1;
    plot_box b = {floor(log10(xmin)), ceil(log10(xmax)), floor(log10(ymin)), ceil(log10(ymax)),
                  90, width - 230, 50 + 16 * ncap, height - 60};
    cairo_surface_t *sf = cairo_image_surface_create(CAIRO_FORMAT_RGB24, width, height);
    cairo_t *cr = cairo_create(sf);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_select_font_face(cr, "sans-serif", CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, 12);
    /* grid and decade labels */
    cairo_set_line_width(cr, 1);
    for (int e = (int)b.x0; e <= (int)b.x1; e++) {
        double x = plot_px(&b, pow(10, e));
        cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
        cairo_move_to(cr, x, b.top);
        cairo_line_to(cr, x, b.bottom);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        plot_decade_label(cr, x, b.bottom + 16, e, 0);
    }
    for (int e = (int)b.y0; e <= (int)b.y1; e++) {
        double y = plot_py(&b, pow(10, e));
        cairo_set_source_rgb(cr, 0.88, 0.88, 0.88);
        cairo_move_to(cr, b.left, y);
        cairo_line_to(cr, b.right, y);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        plot_decade_label(cr, b.left, y + 4, e, 1);
    }
    cairo_set_source_rgb(cr, 0, 0, 0);
    cairo_rectangle(cr, b.left, b.top, b.right - b.left, b.bottom - b.top);
    cairo_stroke(cr);
    cairo_set_font_size(cr, 14);
    cairo_move_to(cr, b.left, 26);
    cairo_show_text(cr, title);
    cairo_set_font_size(cr, 11);
    for (int i = 0; i < ncap; i++) {
        cairo_move_to(cr, b.left, 46 + 16 * i);
        cairo_show_text(cr, caption[i]);
    }
    cairo_set_font_size(cr, 12);
    cairo_move_to(cr, (b.left + b.right) / 2 - 80, height - 18);
    cairo_show_text(cr, xlabel);
    cairo_save(cr);
    cairo_move_to(cr, 22, (b.top + b.bottom) / 2 + 80);
    cairo_rotate(cr, -M_PI / 2);
    cairo_show_text(cr, ylabel);
    cairo_restore(cr);
    /* series */
    for (int i = 0; i < ns; i++) {
        cairo_set_source_rgb(cr, s[i].rgb[0], s[i].rgb[1], s[i].rgb[2]);
        cairo_set_line_width(cr, 2);
        double dash[] = {6, 4};
        cairo_set_dash(cr, dash, s[i].dashed ? 2 : 0, 0);
        int pen = 0;
        for (int j = 0; j < s[i].n; j++) {
            if (!(s[i].x[j] > 0 && isfinite(s[i].x[j]) && s[i].y[j] > 0)) {
                pen = 0;
                continue;
            }
            double x = plot_px(&b, s[i].x[j]), y = plot_py(&b, s[i].y[j]);
            if (pen)
                cairo_line_to(cr, x, y);
            else
                cairo_move_to(cr, x, y);
            pen = 1;
        }
        cairo_stroke(cr);
        cairo_set_dash(cr, dash, 0, 0);
        for (int j = 0; j < s[i].n; j++)
            if (s[i].x[j] > 0 && isfinite(s[i].x[j]) && s[i].y[j] > 0) {
                cairo_arc(cr, plot_px(&b, s[i].x[j]), plot_py(&b, s[i].y[j]), 3.5, 0, 2 * M_PI);
                cairo_fill(cr);
            }
        double ly = b.top + 10 + 22 * i;
        cairo_move_to(cr, b.right + 15, ly);
        cairo_line_to(cr, b.right + 45, ly);
        cairo_stroke(cr);
        cairo_set_source_rgb(cr, 0, 0, 0);
        cairo_move_to(cr, b.right + 52, ly + 4);
        cairo_show_text(cr, s[i].label);
    }
    cairo_destroy(cr);
    int rc = cairo_surface_write_to_png(sf, path) == CAIRO_STATUS_SUCCESS ? 0 : -1;
    cairo_surface_destroy(sf);
    return rc;
}

#endif

/* plot_page.c - a figure's page (plot_draw.h): its surface by format
 * (PNG, SVG, PDF), its title and caption lines, and what it says in words
 * (an SVG's <title> and <desc>, a PDF's metadata), written at the end. */
#include "plot.h"
#include "plot_draw.h"

#include <cairo-pdf.h>
#include <cairo-svg.h>
#include <cairo.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int plot_format_ok(const char *format)
{
    return !format || !strcmp(format, "png") || !strcmp(format, "svg") || !strcmp(format, "pdf");
}

static const char *fmt(const char *format) { return format ? format : "png"; }

cairo_t *pd_canvas(const char *path, const char *format, int w, int h, cairo_surface_t **s)
{
    format = fmt(format);
    if (!strcmp(format, "svg"))
        *s = cairo_svg_surface_create(path, w, h);
    else if (!strcmp(format, "pdf"))
        *s = cairo_pdf_surface_create(path, w, h);
    else
        *s = cairo_image_surface_create(CAIRO_FORMAT_RGB24, w, h);
    cairo_t *cr = cairo_create(*s);
    cairo_set_source_rgb(cr, 1, 1, 1);
    cairo_paint(cr);
    cairo_set_source_rgb(cr, 0, 0, 0);
    return cr;
}

/* A caption line centred at (x, y): 12.5 pt, smaller where that would not
 * fit in width w less a margin (a long scene name or N range). */
static void caption_line(cairo_t *cr, double x, double y, double w, const char *s)
{
    cairo_text_extents_t e;
    double size = 12.5;
    cairo_select_font_face(cr, PD_FONT, CAIRO_FONT_SLANT_NORMAL, CAIRO_FONT_WEIGHT_NORMAL);
    cairo_set_font_size(cr, size);
    cairo_text_extents(cr, s, &e);
    if (e.x_advance > w - 80) /* 40 px a side */
        size *= (w - 80) / e.x_advance;
    pd_text(cr, x, y, size, 0.5, s);
}

double pd_page_head(cairo_t *cr, double w, const char *title, const plot_page *pg)
{
    cairo_set_source_rgb(cr, 0, 0, 0);
    pd_text(cr, w / 2, 30, 20, 0.5, title ? title : "");
    double y = 30;
    for (int i = 0; i < 4 && pg->caption[i]; i++)
        caption_line(cr, w / 2, y += 18, w, pg->caption[i]);
    return y;
}

void pd_words(pd_doc *d, const char *what, const char *s)
{
    size_t n = strlen(d->desc);
    if (s && *s)
        snprintf(d->desc + n, sizeof d->desc - n, "%s%s%s%s", n ? "\n" : "", what ? what : "",
                 what ? ": " : "", s);
}

void pd_doc_init(pd_doc *d, const char *title, const plot_page *pg)
{
    snprintf(d->title, sizeof d->title, "%s", title ? title : "");
    d->desc[0] = 0;
    for (int i = 0; i < 4 && pg->caption[i]; i++)
        pd_words(d, NULL, pg->caption[i]);
}

/* s into f with XML's special characters escaped. */
static void xml_put(FILE *f, const char *s)
{
    for (; *s; s++) {
        if (*s == '&')
            fputs("&amp;", f);
        else if (*s == '<')
            fputs("&lt;", f);
        else if (*s == '>')
            fputs("&gt;", f);
        else if (*s == '"')
            fputs("&quot;", f);
        else
            fputc(*s, f);
    }
}

/* cairo draws an SVG's text as glyph outlines: give it <title> and <desc>
 * (what a reader, a screen reader or grep finds) after the <svg> tag. */
static int svg_describe(const char *path, const pd_doc *d)
{
    FILE *f = fopen(path, "rb");
    char *buf = NULL;
    long n = -1;
    if (f && fseek(f, 0, SEEK_END) == 0 && (n = ftell(f)) > 0 && fseek(f, 0, SEEK_SET) == 0 &&
        (buf = malloc((size_t)n + 1)) && fread(buf, 1, (size_t)n, f) != (size_t)n)
        n = -1;
    if (f)
        fclose(f);
    char *tag = n > 0 ? (buf[n] = 0, strstr(buf, "<svg")) : NULL, *end = tag ? strchr(tag, '>') : NULL;
    int rc = -1;
    if (end && (f = fopen(path, "wb"))) {
        fwrite(buf, 1, (size_t)(end + 1 - buf), f);
        fputs("\n<title>", f), xml_put(f, d->title), fputs("</title>\n<desc>", f);
        xml_put(f, d->desc), fputs("</desc>", f);
        fwrite(end + 1, 1, (size_t)(n - (end + 1 - buf)), f);
        rc = fclose(f) ? -1 : 0;
    }
    free(buf);
    return rc;
}

int pd_finish(cairo_surface_t *s, cairo_t *cr, const char *path, const char *format,
              const pd_doc *d, char *why, size_t whylen)
{
    format = fmt(format);
    cairo_destroy(cr);
    cairo_status_t st = CAIRO_STATUS_SUCCESS;
    if (!strcmp(format, "png")) {
        st = cairo_surface_write_to_png(s, path);
    } else if (!strcmp(format, "pdf") && d) {
        char sub[sizeof d->desc];
        snprintf(sub, sizeof sub, "%s", d->desc);
        for (char *c = sub; (c = strchr(c, '\n'));)
            *c = '|'; /* one line: the lines apart by | */
        cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_TITLE, d->title);
        cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_SUBJECT, sub);
        cairo_pdf_surface_set_metadata(s, CAIRO_PDF_METADATA_CREATOR, "wormgear");
    }
    cairo_surface_finish(s);
    if (st == CAIRO_STATUS_SUCCESS)
        st = cairo_surface_status(s);
    cairo_surface_destroy(s);
    if (st != CAIRO_STATUS_SUCCESS) {
        snprintf(why, whylen, "cannot write %s: %s", path, cairo_status_to_string(st));
        return -1;
    }
    if (!strcmp(format, "svg") && d && svg_describe(path, d)) {
        snprintf(why, whylen, "cannot write %s", path);
        return -1;
    }
    return 0;
}

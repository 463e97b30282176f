/* mon_text.c - wgmon's frame text (see mon_text.h). */
#include "mon_text.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void mon_text_begin(mon_text *f, int cols, int plain)
{
    f->len = 0;
    if (f->buf)
        f->buf[0] = 0;
    f->cols = cols, f->plain = plain, f->col = 0, f->lines = 0, f->wrap = 1, f->indent = 8;
}

void mon_text_raw(mon_text *f, const char *s, size_t n)
{
    if (f->len + n + 1 > f->cap) {
        size_t cap = (f->cap + n + 1) * 2;
        char *b = realloc(f->buf, cap);
        if (!b)
            return;
        f->buf = b, f->cap = cap;
    }
    memcpy(f->buf + f->len, s, n);
    f->len += n;
    f->buf[f->len] = 0;
}

int mon_text_width(const char *s)
{
    int w = 0;
    for (; *s; s++)
        w += ((unsigned char)*s & 0xC0) != 0x80;
    return w;
}

/* Bytes of the first `cols` characters of s. */
static size_t cut_bytes(const char *s, int cols)
{
    size_t i = 0;
    for (int w = 0; s[i]; i++) {
        if (((unsigned char)s[i] & 0xC0) != 0x80 && w++ == cols)
            break;
    }
    return i;
}

static void put_text(mon_text *f, int colour, const char *t)
{
    char sgr[16];
    int room = f->cols - f->col, w = mon_text_width(t);
    if (room <= 0 || !*t)
        return;
    if (w > room)
        w = room;
    if (colour && !f->plain)
        mon_text_raw(f, sgr, (size_t)snprintf(sgr, sizeof sgr, "\033[%dm", colour));
    mon_text_raw(f, t, cut_bytes(t, w));
    if (colour && !f->plain)
        mon_text_raw(f, "\033[0m", 4);
    f->col += w;
}

void mon_text_put(mon_text *f, int colour, const char *fmt, ...)
{
    char t[1024];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(t, sizeof t, fmt, ap);
    va_end(ap);
    const char *s = t;
    if (f->wrap && f->col > f->indent && mon_text_width(t) > f->cols - f->col) {
        mon_text_nl(f);
        while (*s == ' ')
            s++;
        char pad[256];
        int n = f->indent < (int)sizeof pad - 1 ? f->indent : (int)sizeof pad - 1;
        memset(pad, ' ', (size_t)n);
        pad[n] = 0;
        put_text(f, 0, pad);
    }
    put_text(f, colour, s);
}

void mon_text_nl(mon_text *f)
{
    if (!f->plain)
        mon_text_raw(f, "\033[K", 3);
    mon_text_raw(f, "\n", 1);
    f->col = 0;
    f->lines++;
}

void mon_text_free(mon_text *f)
{
    free(f->buf);
    f->buf = NULL;
    f->len = f->cap = 0;
}

const char *mon_text_age(double s, char *buf, size_t len)
{
    s = fabs(s);
    if (s < 120)
        snprintf(buf, len, "%.1f s", s);
    else if (s < 7200)
        snprintf(buf, len, "%.1f min", s / 60);
    else if (s < 172800)
        snprintf(buf, len, "%.1f h", s / 3600);
    else
        snprintf(buf, len, "%.1f d", s / 86400);
    return buf;
}

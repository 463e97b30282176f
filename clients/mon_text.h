/* mon_text.h - wgmon's frame: the text of one screen, built field by field
 * and line by line, never wider than the terminal. A field that does not
 * fit on the current line wraps to a new one, indented under the line's
 * label (wrap on) or is cut at the edge (wrap off: plots). Colours are SGR
 * codes, dropped in plain mode. */
#ifndef WG_MON_TEXT_H
#define WG_MON_TEXT_H

#include <stddef.h>

typedef struct mon_text {
    char *buf;
    size_t len, cap;
    int cols;         /* width in characters */
    int plain;        /* no escape sequences */
    int col;          /* visible columns used on the current line */
    int lines;        /* lines ended so far */
    int wrap;         /* 1: fields wrap; 0: they are cut */
    int indent;       /* columns a wrapped field starts at (default 8) */
} mon_text;

/* Start a frame of cols columns: empty, wrap on, indent 8. The buffer is
 * kept (free it with mon_text_free). */
void mon_text_begin(mon_text *f, int cols, int plain);

/* Bytes as they are (escape sequences): no width. */
void mon_text_raw(mon_text *f, const char *s, size_t n);

/* A visible field; colour an SGR code or 0. Wraps or is cut (see above).
 * Counts columns by characters (UTF-8 continuation bytes take none). */
void mon_text_put(mon_text *f, int colour, const char *fmt, ...)
    __attribute__((format(printf, 3, 4)));

/* End the line (clearing to its end on a terminal). */
void mon_text_nl(mon_text *f);

/* Visible columns of a UTF-8 string. */
int mon_text_width(const char *s);

/* A span of seconds as a reader takes it: "3.2 s", "4.1 min", "3.2 h",
 * "2.1 d" (its magnitude), into buf; returns buf. */
const char *mon_text_age(double s, char *buf, size_t len);

void mon_text_free(mon_text *f);

#endif

/* web_json.h - a growable JSON text buffer for wgweb's outgoing messages.
 *
 * Appending never fails visibly: on allocation failure the buffer sets `oom`
 * and ignores further appends, so a caller checks once at the end. Commas
 * between members and items are inserted automatically (jb_key, jb_item). */
#ifndef WEB_JSON_H
#define WEB_JSON_H

#include <stddef.h>
#include <stdint.h>

typedef struct jbuf {
    char *s;      /* NUL-terminated text (NULL until the first append) */
    size_t len;   /* bytes used, without the NUL */
    size_t cap;
    size_t start; /* bytes reserved in front of the text (jb_init_pre) */
    int oom;      /* an allocation failed: the text is incomplete */
} jbuf;

/* An empty buffer. */
void jb_init(jbuf *b);

/* An empty buffer whose text starts `pre` zero bytes into s (room for a
 * transport header, e.g. LWS_PRE). jb_text() returns s + pre. */
void jb_init_pre(jbuf *b, size_t pre);

/* Free the memory; the buffer is empty again. */
void jb_free(jbuf *b);

/* Forget the text, keep the memory. */
void jb_reset(jbuf *b);

/* The text (after the reserved prefix); "" when empty. Length: jb_len(). */
const char *jb_text(const jbuf *b);
size_t jb_len(const jbuf *b);

/* Append raw bytes / a raw NUL-terminated string / printf-formatted text. */
void jb_mem(jbuf *b, const void *p, size_t n);
void jb_raw(jbuf *b, const char *s);
void jb_fmt(jbuf *b, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

/* Append s as a JSON string literal (quotes, escapes; bytes < 0x20 as
 * \u00XX; invalid UTF-8 passes through: our strings are ASCII). NULL: "". */
void jb_str(jbuf *b, const char *s);

/* Append a number: %.17g for full doubles (jb_num), %.9g (jb_numf);
 * non-finite values become null (JSON has no NaN). */
void jb_num(jbuf *b, double v);
void jb_numf(jbuf *b, double v);
void jb_int(jbuf *b, int64_t v);
void jb_bool(jbuf *b, int v);

/* Start a member "key": (a comma first unless right after { or [). */
void jb_key(jbuf *b, const char *key);

/* Start an array item (a comma first unless right after [). */
void jb_item(jbuf *b);

#endif

/* web_json.c - the JSON text buffer. */
#include "web_json.h"
#include "cli.h"

#include <math.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

void jb_init(jbuf *b) { memset(b, 0, sizeof *b); }

void jb_init_pre(jbuf *b, size_t pre)
{
    jb_init(b);
    b->start = pre;
}

void jb_free(jbuf *b)
{
    size_t pre = b->start;
    free(b->s);
    jb_init_pre(b, pre);
}

void jb_reset(jbuf *b)
{
    b->len = 0;
    b->oom = 0;
    if (b->s)
        b->s[b->start] = '\0';
}

const char *jb_text(const jbuf *b) { return b->s ? b->s + b->start : ""; }

size_t jb_len(const jbuf *b) { return b->len; }

/* Room for n more bytes and the NUL. */
static int reserve(jbuf *b, size_t n)
{
    if (b->oom)
        return -1;
    size_t need = b->start + b->len + n + 1;
    if (need <= b->cap)
        return 0;
    size_t cap = b->cap ? b->cap : 1024;
    while (cap < need)
        cap *= 2;
    char *s = realloc(b->s, cap);
    if (!s) {
        b->oom = 1;
        return -1;
    }
    if (!b->s)
        memset(s, 0, b->start);
    b->s = s;
    b->cap = cap;
    return 0;
}

void jb_mem(jbuf *b, const void *p, size_t n)
{
    if (reserve(b, n) != 0)
        return;
    memcpy(b->s + b->start + b->len, p, n);
    b->len += n;
    b->s[b->start + b->len] = '\0';
}

void jb_raw(jbuf *b, const char *s) { jb_mem(b, s, strlen(s)); }

void jb_fmt(jbuf *b, const char *fmt, ...)
{
    char small[128];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(small, sizeof small, fmt, ap);
    va_end(ap);
    if (n < 0)
        return;
    if ((size_t)n < sizeof small) {
        jb_mem(b, small, (size_t)n);
        return;
    }
    if (reserve(b, (size_t)n) != 0)
        return;
    va_start(ap, fmt);
    vsnprintf(b->s + b->start + b->len, (size_t)n + 1, fmt, ap);
    va_end(ap);
    b->len += (size_t)n;
}

/* A JSON string: quotes, backslashes and control characters escaped, and a
 * byte that is not part of well-formed UTF-8 (strings off the bus are
 * whatever a sender put there) as U+FFFD, so the text is always UTF-8. */
void jb_str(jbuf *b, const char *s)
{
    jb_mem(b, "\"", 1);
    for (const char *p = s ? s : ""; *p; p++) {
        unsigned char c = (unsigned char)*p;
        int n;
        if (c == '"' || c == '\\') {
            char e[2] = {'\\', (char)c};
            jb_mem(b, e, 2);
        } else if (c < 0x20 || c == 0x7F) {
            jb_fmt(b, "\\u%04x", c);
        } else if (c < 0x80) {
            jb_mem(b, p, 1);
        } else if ((n = cli_utf8_len(p)) > 0) {
            jb_mem(b, p, (size_t)n);
            p += n - 1;
        } else {
            jb_raw(b, "\\ufffd");
        }
    }
    jb_mem(b, "\"", 1);
}

void jb_num(jbuf *b, double v)
{
    if (isfinite(v))
        jb_fmt(b, "%.17g", v);
    else
        jb_raw(b, "null");
}

void jb_numf(jbuf *b, double v)
{
    if (isfinite(v))
        jb_fmt(b, "%.9g", v);
    else
        jb_raw(b, "null");
}

void jb_int(jbuf *b, int64_t v) { jb_fmt(b, "%lld", (long long)v); }

void jb_bool(jbuf *b, int v) { jb_raw(b, v ? "true" : "false"); }

static char last(const jbuf *b) { return b->len ? b->s[b->start + b->len - 1] : '\0'; }

void jb_key(jbuf *b, const char *key)
{
    char c = last(b);
    if (c != '{' && c != '[' && c != '\0')
        jb_mem(b, ",", 1);
    jb_str(b, key);
    jb_mem(b, ":", 1);
}

void jb_item(jbuf *b)
{
    char c = last(b);
    if (c != '[' && c != '\0')
        jb_mem(b, ",", 1);
}

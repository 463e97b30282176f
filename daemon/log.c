/* log.c - stderr logging with syslog prefixes and per-call-site rate limits. */
#include "log.h"

#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

int64_t log_now_ns(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

const char *log_escape(const char *s, char *out, size_t n)
{
    size_t k = 0;
    for (; *s && k + 5 < n; s++) {
        unsigned char c = (unsigned char)*s;
        if (c < 0x20 || c == 0x7f)
            k += (size_t)snprintf(out + k, n - k, "\\x%02x", c);
        else
            out[k++] = (char)c;
    }
    out[k] = 0;
    return out;
}

static const char *prio_word(int prio)
{
    static const char *const w[] = {"emergency", "alert", "critical", "error",
                                    "warning",   "notice", "info",   "debug"};
    return w[prio & 7];
}

static void emit(const log_ctx *l, int prio, const char *text)
{
    if (l->prefix)
        fprintf(stderr, "<%d>%s\n", prio & 7, text);
    else
        fprintf(stderr, "wormgeard: %s: %s\n", prio_word(prio), text);
}

void log_init(log_ctx *l, int verbose)
{
    memset(l, 0, sizeof *l);
    log_configure(l, verbose, 0);
    l->window_ns = 10 * (int64_t)1000000000;
}

void log_configure(log_ctx *l, int verbose, int prefix)
{
    l->prefix = prefix || getenv("JOURNAL_STREAM") != NULL;
    l->max_prio = verbose ? LOG_DEBUG : LOG_INFO;
}

static void flush_slot(log_ctx *l, log_slot *s)
{
    if (s->suppressed) {
        char text[160];
        snprintf(text, sizeof text, "%u similar messages suppressed (rate limit)",
                 s->suppressed);
        emit(l, s->prio, text);
    }
    s->suppressed = 0;
}

void log_fini(log_ctx *l)
{
    for (int i = 0; i < LOG_SLOTS; i++)
        flush_slot(l, &l->slot[i]);
    fflush(stderr);
}

/* The slot of call site fmt: found, or the stalest one recycled. */
static log_slot *slot_of(log_ctx *l, const char *fmt)
{
    log_slot *old = &l->slot[0];
    for (int i = 0; i < LOG_SLOTS; i++) {
        if (l->slot[i].fmt == fmt)
            return &l->slot[i];
        if (l->slot[i].window_ns < old->window_ns)
            old = &l->slot[i];
    }
    flush_slot(l, old);
    *old = (log_slot){.fmt = fmt, .window_ns = 0};
    return old;
}

/* 1: the call site fmt is over its burst in this window (counted). */
static int limited(log_ctx *l, int prio, const char *fmt)
{
    int64_t now = log_now_ns();
    log_slot *s = slot_of(l, fmt);
    if (now - s->window_ns >= l->window_ns) {
        flush_slot(l, s);
        s->window_ns = now;
        s->count = 0;
    }
    s->prio = prio;
    if (++s->count > LOG_BURST) {
        s->suppressed++;
        l->suppressed++;
        return 1;
    }
    return 0;
}

static void vemit(const log_ctx *l, int prio, const char *fmt, va_list ap)
{
    char text[1024], safe[4 * sizeof text];
    vsnprintf(text, sizeof text, fmt, ap);
    emit(l, prio, log_escape(text, safe, sizeof safe));
}

void log_msg(log_ctx *l, int prio, const char *fmt, ...)
{
    if (prio > l->max_prio || limited(l, prio, fmt))
        return;
    va_list ap;
    va_start(ap, fmt);
    vemit(l, prio, fmt, ap);
    va_end(ap);
}

void log_change(log_ctx *l, int prio, const char *what, const char *fmt, ...)
{
    if (prio > l->max_prio)
        return;
    uint32_t h = 2166136261u; /* FNV-1a of what: a repeat of the last change? */
    for (const unsigned char *p = (const unsigned char *)what; *p; p++)
        h = (h ^ *p) * 16777619u;
    int repeat = l->changes && h == l->last_change;
    l->last_change = h, l->changes = 1;
    if (repeat && limited(l, prio, fmt))
        return;
    va_list ap;
    va_start(ap, fmt);
    vemit(l, prio, fmt, ap);
    va_end(ap);
}

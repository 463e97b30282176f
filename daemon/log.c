/* log.c - stderr logging with syslog prefixes and per-call-site rate
 * limits, written by a thread of its own once started. */
#include "log.h"

#include "wormgear/wg_writer.h"

#include <errno.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* ---- the writer ------------------------------------------------------------- */

/* Lines queued for the writer: 64 KiB, about 600 log lines. A line longer
 * than REC_MAX is cut. */
enum { QUEUE = 65536, REC_MAX = 5000 };

static const char *lost_fmt(const log_ctx *l);

int log_start(log_ctx *l)
{
    wg_writer *w = wg_writer_start(QUEUE);
    if (!w)
        return -1;
    if (wg_writer_note(w, STDERR_FILENO, lost_fmt(l))) {
        wg_writer_stop(w, 0);
        errno = ENOMEM;
        return -1;
    }
    fflush(stdout), fflush(stderr); /* what was written in place comes first */
    l->out = w;
    return 0;
}

/* ---- lines ------------------------------------------------------------------ */

static int64_t clock_ns(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

int64_t log_now_ns(void) { return clock_ns(CLOCK_MONOTONIC); }

int64_t log_cpu_ns(void) { return clock_ns(CLOCK_THREAD_CPUTIME_ID); }

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

/* The bytes snprintf wrote into a buffer of cap (n its return). */
static size_t written(int n, size_t cap) { return n < 0 ? 0 : (size_t)n < cap ? (size_t)n : cap - 1; }

/* The line counting dropped ones, in l's format: one %lu. */
static const char *lost_fmt(const log_ctx *l)
{
    return l->prefix ? "<4>%lu lines not written: stdout or stderr took nothing (a stopped "
                       "terminal, a pipe no one reads)\n"
                     : "wormgeard: warning: %lu lines not written: stdout or stderr took nothing "
                       "(a stopped terminal, a pipe no one reads)\n";
}

/* Queue a line for fd: 0 (dropped and counted when the queue is full),
 * or the errno of an earlier failed write to fd. */
static int out_put(const log_ctx *l, int fd, const char *s, size_t n)
{
    int e = wg_writer_put(l->out, fd, s, n);
    return e == ENOBUFS || e == ENOMEM ? 0 : e;
}

static void emit(const log_ctx *l, int prio, const char *text)
{
    char line[REC_MAX];
    size_t n = written(l->prefix ? snprintf(line, sizeof line, "<%d>%s\n", prio & 7, text)
                                 : snprintf(line, sizeof line, "wormgeard: %s: %s\n",
                                            prio_word(prio), text),
                       sizeof line);
    if (l->out)
        out_put(l, STDERR_FILENO, line, n);
    else
        fwrite(line, 1, n, stderr);
}

int log_stdout(log_ctx *l, const char *line)
{
    char buf[REC_MAX];
    size_t n = written(snprintf(buf, sizeof buf, "%s\n", line), sizeof buf);
    if (l->out)
        return out_put(l, STDOUT_FILENO, buf, n);
    if (fwrite(buf, 1, n, stdout) != n || fflush(stdout) != 0)
        return errno ? errno : EIO;
    return 0;
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
    if (l->out) /* the note in the lines' new form (none if out of memory: the old one stays) */
        wg_writer_note(l->out, STDERR_FILENO, lost_fmt(l));
}

static void flush_slot(log_ctx *l, log_slot *s)
{
    if (s->suppressed) { /* which kind: "9 similar messages suppressed" said nothing */
        char text[200];
        snprintf(text, sizeof text, "%u similar messages suppressed (rate limit), like: %s%s",
                 s->suppressed, s->like, strlen(s->like) == sizeof s->like - 1 ? "..." : "");
        emit(l, s->prio, text);
    }
    s->suppressed = 0;
}

void log_fini(log_ctx *l)
{
    for (int i = 0; i < LOG_SLOTS; i++)
        flush_slot(l, &l->slot[i]);
    if (l->out) /* 2 s, else left (with what it holds) to end with the process */
        wg_writer_stop(l->out, 2.0);
    l->out = NULL;
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

/* 1: the call site fmt is over its burst in this window (counted); its
 * slot in *slot. */
static int limited(log_ctx *l, int prio, const char *fmt, log_slot **slot)
{
    int64_t now = log_now_ns();
    log_slot *s = *slot = slot_of(l, fmt);
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

static void vemit(const log_ctx *l, int prio, const char *fmt, va_list ap, log_slot *s)
{
    char text[1024], safe[4 * sizeof text];
    vsnprintf(text, sizeof text, fmt, ap);
    const char *line = log_escape(text, safe, sizeof safe);
    if (s) /* what its suppressed ones are like */
        snprintf(s->like, sizeof s->like, "%s", line);
    emit(l, prio, line);
}

void log_vmsg(log_ctx *l, int prio, const char *fmt, va_list ap)
{
    log_slot *s;
    if (prio > l->max_prio || limited(l, prio, fmt, &s))
        return;
    vemit(l, prio, fmt, ap, s);
}

void log_msg(log_ctx *l, int prio, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    log_vmsg(l, prio, fmt, ap);
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
    log_slot *s = NULL;
    if (repeat && limited(l, prio, fmt, &s))
        return;
    va_list ap;
    va_start(ap, fmt);
    vemit(l, prio, fmt, ap, s);
    va_end(ap);
}

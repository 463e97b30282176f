/* log.c - stderr logging with syslog prefixes and per-call-site rate
 * limits, written by a thread of its own once started. */
#include "log.h"

#include "wormgear/wg_file.h"

#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

/* ---- the writer: records "fd, 2-byte length, bytes" in a ring -------------- */

enum { RING = 65536, REC_MAX = 5000 };

struct log_out {
    pthread_t th;
    pthread_mutex_t mu; /* guards what follows */
    pthread_cond_t more, idle;
    unsigned char ring[RING];
    size_t head, used;  /* the oldest record's offset; bytes queued */
    int busy;           /* a record taken and being written */
    int err[3];         /* [fd]: errno of a failed write to stdout (1) or stderr (2) */
    unsigned long lost; /* records dropped (the ring full) and not yet told */
    int quit, abandoned;
    unsigned char rec[REC_MAX]; /* the writer's record being written */
};

static void ring_copy(log_out *o, size_t at, const void *src, size_t n)
{
    for (size_t i = 0; i < n; i++)
        o->ring[(at + i) % RING] = ((const unsigned char *)src)[i];
}

static void out_free(log_out *o)
{
    pthread_cond_destroy(&o->idle);
    pthread_cond_destroy(&o->more);
    pthread_mutex_destroy(&o->mu);
    free(o);
}

static void *writer(void *arg)
{
    log_out *o = arg;
    pthread_mutex_lock(&o->mu);
    for (;;) {
        while (!o->used && !o->quit)
            pthread_cond_wait(&o->more, &o->mu);
        if (!o->used || o->abandoned)
            break;
        int fd = o->ring[o->head];
        size_t n = o->ring[(o->head + 1) % RING] | (size_t)o->ring[(o->head + 2) % RING] << 8;
        for (size_t i = 0; i < n; i++)
            o->rec[i] = o->ring[(o->head + 3 + i) % RING];
        o->head = (o->head + 3 + n) % RING;
        o->used -= 3 + n;
        int skip = o->err[fd];
        o->busy = 1;
        pthread_mutex_unlock(&o->mu);
        int e = skip ? 0 : wg_file_write_all(fd, o->rec, n); /* blocks as long as the reader likes */
        pthread_mutex_lock(&o->mu);
        o->busy = 0;
        if (e)
            o->err[fd] = e;
        if (!o->used)
            pthread_cond_broadcast(&o->idle);
    }
    int gone = o->abandoned;
    pthread_mutex_unlock(&o->mu);
    if (gone) /* log_fini gave up on it: its memory is its own */
        out_free(o);
    return 0;
}

/* Queue n bytes for fd: 0, the fd's write error, or 0 with the line
 * dropped and counted when the ring is full. A count of dropped lines is
 * queued first, on stderr, once there is room for it and the line. */
static int out_put(log_out *o, int fd, const char *s, size_t n, const char *lost_fmt)
{
    if (n > REC_MAX)
        n = REC_MAX;
    pthread_mutex_lock(&o->mu);
    int e = o->err[fd];
    if (!e && o->lost) {
        char note[200];
        size_t k = (size_t)snprintf(note, sizeof note, lost_fmt, o->lost);
        k = k < sizeof note ? k : sizeof note - 1;
        if (RING - o->used >= 3 + k + 3 + n) {
            unsigned char h[3] = {2, (unsigned char)(k & 0xff), (unsigned char)(k >> 8)};
            ring_copy(o, o->head + o->used, h, 3);
            ring_copy(o, o->head + o->used + 3, note, k);
            o->used += 3 + k;
            o->lost = 0;
        }
    }
    if (!e && RING - o->used >= 3 + n) {
        unsigned char h[3] = {(unsigned char)fd, (unsigned char)(n & 0xff), (unsigned char)(n >> 8)};
        ring_copy(o, o->head + o->used, h, 3);
        ring_copy(o, o->head + o->used + 3, s, n);
        o->used += 3 + n;
        pthread_cond_signal(&o->more);
    } else if (!e) {
        o->lost++;
    }
    pthread_mutex_unlock(&o->mu);
    return e;
}

int log_start(log_ctx *l)
{
    log_out *o = calloc(1, sizeof *o);
    if (!o)
        return -1;
    pthread_mutex_init(&o->mu, NULL);
    pthread_cond_init(&o->more, NULL);
    pthread_cond_init(&o->idle, NULL);
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    int rc = pthread_create(&o->th, NULL, writer, o);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (rc) {
        out_free(o);
        errno = rc;
        return -1;
    }
    fflush(stdout), fflush(stderr); /* what was written in place comes first */
    l->out = o;
    return 0;
}

/* End the writer once the ring is written, wait_s at most; else leave it. */
static void out_stop(log_out *o, double wait_s)
{
    struct timespec end;
    clock_gettime(CLOCK_REALTIME, &end);
    end.tv_sec += (time_t)wait_s;
    end.tv_nsec += (long)((wait_s - (double)(time_t)wait_s) * 1e9);
    if (end.tv_nsec >= 1000000000)
        end.tv_sec++, end.tv_nsec -= 1000000000;
    pthread_mutex_lock(&o->mu);
    int left = 0;
    while ((o->used || o->busy) && !left)
        left = pthread_cond_timedwait(&o->idle, &o->mu, &end) == ETIMEDOUT;
    left = o->used || o->busy;
    o->quit = 1;
    o->abandoned = left;
    if (left)
        pthread_detach(o->th);
    pthread_cond_signal(&o->more);
    pthread_mutex_unlock(&o->mu); /* abandoned: o is the writer's from here */
    if (left)
        return;
    pthread_join(o->th, NULL);
    out_free(o);
}

/* ---- lines ------------------------------------------------------------------ */

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

static void emit(const log_ctx *l, int prio, const char *text)
{
    char line[REC_MAX];
    size_t n = written(l->prefix ? snprintf(line, sizeof line, "<%d>%s\n", prio & 7, text)
                                 : snprintf(line, sizeof line, "wormgeard: %s: %s\n",
                                            prio_word(prio), text),
                       sizeof line);
    if (l->out)
        out_put(l->out, 2, line, n, lost_fmt(l));
    else
        fwrite(line, 1, n, stderr);
}

int log_stdout(log_ctx *l, const char *line)
{
    char buf[REC_MAX];
    size_t n = written(snprintf(buf, sizeof buf, "%s\n", line), sizeof buf);
    if (l->out)
        return out_put(l->out, 1, buf, n, lost_fmt(l));
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
    if (l->out)
        out_stop(l->out, 2.0);
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

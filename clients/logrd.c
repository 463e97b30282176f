/* logrd.c - an LCM log read with every length checked (logrd.h). */
#include "logrd.h"

#include "msg_check.h"
#include "wormgear/wg_file.h"

#include <stdint.h>
#include <stdlib.h>
#include <sys/stat.h>

enum { LOG_MAGIC = (int)0xEDA1DA01, LOG_CHANNEL_MAX = 1000, LOG_HEADER = 28 };

/* Open path (quiet: nothing said on failure). */
int logrd_open(logrd *l, const char *path, int quiet)
{
    char why[600];
    struct stat st;
    *l = (logrd){.bad_at = -1};
    /* a directory read as "0 events", exit 0; a FIFO blocked the open */
    if (!(l->f = wg_file_fopen(path, "log", 0, -1, &st, why, sizeof why))) {
        if (!quiet)
            fprintf(stderr, "wglog: %s\n", why);
        return -1;
    }
    l->size = (long long)st.st_size;
    return 0;
}

/* An event header at the current position whose channel and data fit in
 * the file: 0 (positioned after it), else -1. */
static int logrd_header(logrd *l, int64_t *num, int64_t *ts, int64_t *clen, int64_t *dlen)
{
    unsigned char h[LOG_HEADER];
    if (fread(h, 1, sizeof h, l->f) != sizeof h ||
        (int32_t)(uint32_t)msg_be(h, 4) != LOG_MAGIC)
        return -1;
    *num = (int64_t)msg_be(h + 4, 8);
    *ts = (int64_t)msg_be(h + 12, 8);
    *clen = (int32_t)(uint32_t)msg_be(h + 20, 4);
    *dlen = (int32_t)(uint32_t)msg_be(h + 24, 4);
    return *clen < 1 || *clen > LOG_CHANNEL_MAX || *dlen < 0 ||
                   *clen + *dlen > l->size - ftello(l->f)
               ? -1
               : 0;
}

/* The next sync word after byte from that starts an event that fits, or
 * -1 (none up to the end). */
static long long logrd_resync(logrd *l, long long from)
{
    unsigned char buf[16384];
    int64_t num, ts, clen, dlen;
    for (long long pos = from; pos + LOG_HEADER <= l->size;) {
        if (fseeko(l->f, pos, SEEK_SET) != 0)
            return -1;
        size_t n = fread(buf, 1, sizeof buf, l->f);
        if (n < 4)
            return -1;
        for (size_t i = 0; i + 4 <= n; i++) {
            if ((int32_t)(uint32_t)msg_be(buf + i, 4) != LOG_MAGIC)
                continue;
            if (fseeko(l->f, pos + (long long)i, SEEK_SET) == 0 &&
                logrd_header(l, &num, &ts, &clen, &dlen) == 0)
                return pos + (long long)i;
        }
        pos += (long long)n - 3; /* a sync word across the buffer's end */
    }
    return -1;
}

/* The next event (free it with lcm_eventlog_free_event), or NULL at the
 * end; a damaged stretch on the way is counted and skipped. */
lcm_eventlog_event_t *logrd_next(logrd *l)
{
    for (;;) {
        long long at = ftello(l->f);
        int64_t num, ts, clen, dlen;
        if (at < 0 || at >= l->size)
            return NULL;
        if (logrd_header(l, &num, &ts, &clen, &dlen) == 0) {
            lcm_eventlog_event_t *ev = calloc(1, sizeof *ev);
            char *ch = ev ? malloc((size_t)clen + 1) : NULL;
            char *data = ch ? malloc((size_t)dlen + 1) : NULL;
            if (data && fread(ch, 1, (size_t)clen, l->f) == (size_t)clen &&
                fread(data, 1, (size_t)dlen, l->f) == (size_t)dlen) {
                ch[clen] = 0;
                *ev = (lcm_eventlog_event_t){num, ts, (int32_t)clen, (int32_t)dlen, ch, data};
                return ev;
            }
            free(data), free(ch), free(ev);
        }
        long long next = logrd_resync(l, at + 1);
        if (l->bad_at < 0)
            l->bad_at = at;
        l->regions++;
        l->skipped += (next < 0 ? l->size : next) - at;
        if (next < 0 || fseeko(l->f, next, SEEK_SET) != 0)
            return NULL;
    }
}

/* Closed; 1 (said once) if any of it was damaged. */
int logrd_close(logrd *l, const char *path, long events)
{
    if (l->f)
        fclose(l->f);
    if (l->bad_at < 0)
        return 0;
    if (events == 0 && l->skipped == l->size) { /* README.md given for a log, say */
        fprintf(stderr, "wglog: %s: not an LCM log: no event in its %lld bytes (lcm-logger "
                "writes one: lcm-logger --lcm-url=URL FILE)\n", path, l->size);
        return 1;
    }
    fprintf(stderr, "wglog: %s: damaged: %lld of %lld bytes skipped in %ld stretch%s, the first "
                    "at byte %lld; the %ld whole events around them are read\n", path,
            l->skipped, l->size, l->regions, l->regions == 1 ? "" : "es", l->bad_at, events);
    return 1;
}


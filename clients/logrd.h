/* logrd.h - an LCM log read with every length checked (wglog's reader).
 *
 * LCM's own reader (lcm_eventlog_read_next_event) trusts an event's data
 * length: 0x7fffffff made its allocation fail and it read into NULL
 * (wglog died on a damaged log), and where it gave up it said so only on
 * stderr, wglog then exiting 0 on a part of the log. This one reads the
 * same format (a sync word, event number, timestamp, channel and data
 * lengths, big-endian, then the channel and the data) with every length
 * checked against the file. Where an event does not fit, it looks for the
 * next sync word that starts one that does (as LCM's reader does) and
 * reads on from there; the bytes skipped are counted and said at the end,
 * and a log with any is exit 1. */
#ifndef WG_LOGRD_H
#define WG_LOGRD_H

#include <lcm/eventlog.h>
#include <stdio.h>

typedef struct logrd {
    FILE *f;
    long long size;
    long long bad_at;   /* where the first damage began (-1: none) */
    long long skipped;  /* bytes in damaged stretches, not read as events */
    long regions;       /* damaged stretches */
} logrd;

/* Open the log at path, a regular file (wg_file_fopen): 0, or -1 said on
 * stderr unless quiet (another pass will say it). */
int logrd_open(logrd *l, const char *path, int quiet);

/* The next event (free it with lcm_eventlog_free_event), or NULL at the
 * end; a damaged stretch on the way is counted and skipped. */
lcm_eventlog_event_t *logrd_next(logrd *l);

/* Close; 1 if any of the log was damaged, said once on stderr with the
 * bytes skipped and the events read (events), else 0. */
int logrd_close(logrd *l, const char *path, long events);

#endif

/* log_rec.h - record an LCM bus to a log file (wglog record).
 *
 * The same file format as lcm-logger's (LCM's eventlog, written with LCM's
 * own lcm_eventlog_write_event), so lcm-logplayer plays it and `wglog
 * summary` / `export` read it. What lcm-logger lacks: its receive socket
 * is filtered (wg_mcast_guard), so a datagram that LCM 1.3.1 would copy
 * 4 GB past its buffer never reaches LCM (one such datagram on the group
 * ends lcm-logger with SIGSEGV). */
#ifndef WG_LOG_REC_H
#define WG_LOG_REC_H

#include <regex.h>

typedef struct log_rec_opts {
    const char *url;       /* LCM URL (udpm://GROUP:PORT?ttl=0 ...) */
    const char *path;      /* the log file */
    const regex_t *re;     /* channels to keep (anchored), or NULL for all */
    double duration_s;     /* stop after this long; 0: until SIGINT or SIGTERM */
    int force;             /* overwrite an existing file */
    int quiet;             /* no line at the start and the end */
} log_rec_opts;

/* Record until SIGINT, SIGTERM or the duration: 0; CLI_EUSAGE (2) after
 * saying why on stderr for a URL LCM refuses or one with port 0; else 1
 * after saying why (the file exists and --force is not given, it cannot be
 * written, no route to the group, the socket cannot be filtered, a write
 * failed: a full disk). What was written before a failure stays in the
 * file, flushed at least every 0.25 s while recording. */
int log_rec_run(const log_rec_opts *o);

#endif

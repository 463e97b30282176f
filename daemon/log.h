/* log.h - wormgeard logging: one call, syslog priorities, rate-limited.
 *
 * Messages go to stderr. Under journald (JOURNAL_STREAM set) or when asked
 * (log_prefix), each line starts with "<N>" (sd-daemon(3) priority prefix);
 * otherwise, on a terminal or in a pipe alike, with "wormgeard: warning: ". Each call site (its format
 * string) may log `burst` messages per `window` seconds; further ones are
 * counted and reported once the window ends ("... N similar messages
 * suppressed"), so a client spamming bad commands cannot flood the journal.
 *
 * Once log_start has run, lines (and the foreground status line, on
 * stdout) are written by a thread of their own from a 64 KiB queue: a
 * stderr or stdout that takes nothing (a terminal stopped with Ctrl-S, a
 * pipe no one reads, a stalled journal) never stops the daemon's loop. It
 * did: the loop blocked in write() and stepped, paced and answered nothing.
 * A line that finds the queue full is dropped and counted; the next one
 * that fits is preceded by "N lines not written". */
#ifndef WGD_LOG_H
#define WGD_LOG_H

#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <syslog.h>

enum { LOG_SLOTS = 16, LOG_BURST = 5 };

typedef struct log_slot {
    const char *fmt;      /* call site key */
    int64_t window_ns;    /* start of the current window */
    unsigned count;       /* messages in the window */
    unsigned suppressed;  /* of which not printed */
    int prio;
    char like[64];        /* the start of the last line printed from it */
} log_slot;

typedef struct wg_writer wg_writer; /* the writer thread (wormgear/wg_writer.h) */

typedef struct log_ctx {
    int prefix;           /* 1: "<N>" prefixes */
    int max_prio;         /* drop messages less severe than this (LOG_INFO) */
    int64_t window_ns;    /* rate-limit window (10 s) */
    log_slot slot[LOG_SLOTS];
    uint64_t suppressed;  /* total, for STATUS/tests */
    uint32_t last_change; /* hash of the last log_change's what */
    int changes;          /* log_change called yet */
    wg_writer *out;       /* the writer, once log_start ran; 0: written in place */
} log_ctx;

/* Set up: prefix chosen from the environment, max_prio LOG_INFO or LOG_DEBUG. */
void log_init(log_ctx *l, int verbose);

/* Debug messages on or off; "<N>" prefixes when prefix or under journald. */
void log_configure(log_ctx *l, int verbose, int prefix);

/* Write from a thread of its own from now on (see above); it inherits the
 * caller's scheduling and blocks every signal. 0, or -1 (errno set: lines
 * are then written in place, as before). */
int log_start(log_ctx *l);

/* One line on stdout (the foreground status line), through the writer
 * once started. 0, or the errno of a write to stdout that failed (every
 * later line is then refused with it). */
int log_stdout(log_ctx *l, const char *line);

/* Report suppressed counts still pending; end the writer once it has
 * written what is queued, 2 s at most (a stdout or stderr that still takes
 * nothing: it is left, with what it holds, to end with the process). */
void log_fini(log_ctx *l);

/* CLOCK_MONOTONIC in nanoseconds: the daemon's one clock (the rate limit
 * here, pacing, step costs, STATUS intervals). */
int64_t log_now_ns(void);

/* CPU time of the calling thread (the loop's), ns: what the loop used of a
 * tick's interval, not counting the time it was not scheduled. A system
 * call here (1.6 us on this VM, against 32 ns for log_now_ns): once a
 * tick, never per chunk of steps. */
int64_t log_cpu_ns(void);

/* s with every control byte (newline, tab, escape, DEL ...) written as
 * \xNN into out (n bytes, 4x the input suffices), so text from the bus can
 * never make a line of its own or drive a terminal. log_msg applies it. */
const char *log_escape(const char *s, char *out, size_t n);

/* Log one line at syslog priority prio (LOG_ERR ... LOG_DEBUG), rate-limited
 * per format string. */
void log_msg(log_ctx *l, int prio, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* log_msg with its arguments in ap (limited per fmt as log_msg is). */
void log_vmsg(log_ctx *l, int prio, const char *fmt, va_list ap)
    __attribute__((format(printf, 3, 0)));

/* Log an accepted state change: never rate-limited, except a repeat of the
 * change just logged (the same `what`, e.g. op and result), which is
 * limited per format string as log_msg is. */
void log_change(log_ctx *l, int prio, const char *what, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

#endif

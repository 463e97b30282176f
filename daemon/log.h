/* log.h - wormgeard logging: one call, syslog priorities, rate-limited.
 *
 * Messages go to stderr. Under journald (JOURNAL_STREAM set) or when asked
 * (log_prefix), each line starts with "<N>" (sd-daemon(3) priority prefix);
 * otherwise, on a terminal or in a pipe alike, with "wormgeard: warning: ". Each call site (its format
 * string) may log `burst` messages per `window` seconds; further ones are
 * counted and reported once the window ends ("... N similar messages
 * suppressed"), so a client spamming bad commands cannot flood the journal. */
#ifndef WGD_LOG_H
#define WGD_LOG_H

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
} log_slot;

typedef struct log_ctx {
    int prefix;           /* 1: "<N>" prefixes */
    int max_prio;         /* drop messages less severe than this (LOG_INFO) */
    int64_t window_ns;    /* rate-limit window (10 s) */
    log_slot slot[LOG_SLOTS];
    uint64_t suppressed;  /* total, for STATUS/tests */
    uint32_t last_change; /* hash of the last log_change's what */
    int changes;          /* log_change called yet */
} log_ctx;

/* Set up: prefix chosen from the environment, max_prio LOG_INFO or LOG_DEBUG. */
void log_init(log_ctx *l, int verbose);

/* Debug messages on or off; "<N>" prefixes when prefix or under journald. */
void log_configure(log_ctx *l, int verbose, int prefix);

/* Report suppressed counts still pending. */
void log_fini(log_ctx *l);

/* CLOCK_MONOTONIC in nanoseconds: the daemon's one clock (the rate limit
 * here, pacing, step costs, STATUS intervals). */
int64_t log_now_ns(void);

/* s with every control byte (newline, tab, escape, DEL ...) written as
 * \xNN into out (n bytes, 4x the input suffices), so text from the bus can
 * never make a line of its own or drive a terminal. log_msg applies it. */
const char *log_escape(const char *s, char *out, size_t n);

/* Log one line at syslog priority prio (LOG_ERR ... LOG_DEBUG), rate-limited
 * per format string. */
void log_msg(log_ctx *l, int prio, const char *fmt, ...) __attribute__((format(printf, 3, 4)));

/* Log an accepted state change: never rate-limited, except a repeat of the
 * change just logged (the same `what`, e.g. op and result), which is
 * limited per format string as log_msg is. */
void log_change(log_ctx *l, int prio, const char *what, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

#endif

/* log_rows.h - wglog's state, and its CSV rows: one writer per wormgear type,
 * found by the message's fingerprint (wglog.c reads the log and keeps the
 * channels; log_rows.c decodes each message, checked first, and writes its
 * rows in the shortest form that reads back exactly). */
#ifndef WG_LOG_ROWS_H
#define WG_LOG_ROWS_H

#include "bus.h"
#include "units.h"

#include <lcm/eventlog.h>
#include <regex.h>
#include <stdint.h>
#include <stdio.h>

enum { T_UNKNOWN = -1 };

typedef struct chan {
    char *name;
    char shown[96];           /* the name as text for the terminal (cli_text) */
    int type;                 /* index in types[], or T_UNKNOWN */
    int64_t hash;
    long msgs, samples, bad;
    long long bytes;
    int64_t t0, t1;           /* log timestamps, us */
    bus_streams seq;          /* senders: gaps, missing (messages lost), restarts */
    char notes[600];          /* the senders after the first, as they appeared */
    FILE *csv;                /* its CSV while open (export; log_rows writes none if NULL) */
    char *file;               /* its CSV's path (export) */
    int wbad;                 /* a write to its CSV failed (said): no more rows */
    int ncols;                /* params_t / poincare_t: columns fixed by the first message */
} chan;

/* Export: at most this many CSVs open at once (and half the descriptors the
 * process may have). One per channel ran out of descriptors (1,024) in a log
 * of more channels; past it, all are closed and each reopened (appending)
 * at its channel's next message. */
enum { CSV_OPEN_MAX = 256 };

typedef struct log_run {
    const char *path, *out, *pattern;
    int export_, quiet, also_summary;
    int physical;             /* --units physical */
    units_scale scale;        /* of the latest PARAMS (the first one before it) */
    regex_t re;
    int has_re;
    chan *ch;
    int nch, cap;
    int *hix, hcap;           /* the channels by name: open addressing, index + 1 (0: empty) */
    long events;
    int64_t t0, t1;
    int damaged;              /* the log stopped being readable before its end: exit 1 */
    char others[64][96];      /* the first channels --channel left out, as text */
    int nothers, more;        /* how many; more: others past those */
    int open_ix[CSV_OPEN_MAX]; /* export: the channels whose CSV is open now */
    int nopen, open_max;      /* how many; the most at once (csv_open_max) */
    int wfail;                /* a CSV's write failed (said): exit 1 */
} log_run;

/* The type of a message whose fingerprint is hash: an index for
 * log_rows_type_name and log_rows, or T_UNKNOWN. */
int log_rows_type(int64_t hash);

/* "state_t", ... of a type log_rows_type gave. */
const char *log_rows_type_name(int type);

/* Decode ev, a message of c's type, and write its rows to c->csv when one
 * is open (the header with the first message that decodes; --units
 * physical with the latest PARAMS's scale, which a PARAMS message sets):
 * the samples it holds, or -1 for bytes that are not a whole message. */
int log_rows(log_run *r, chan *c, const lcm_eventlog_event_t *ev);

#endif

/* rig_opt.h - wgrig's options: their defaults, parsing and checks. */
#ifndef WG_RIG_OPT_H
#define WG_RIG_OPT_H

enum { RIG_REC_CAP = 8192 }; /* the most periods a point records */

typedef struct rig_opts {
    const char *url, *prefix, *param, *out, *unit, *key_file;
    double from, to, ramp, tol, timeout_s, stall_s;
    int have_from, have_to, points, up, down, settle, record, extend, bins, lle, fast, keep;
    int quiet, retries;
} rig_opts;

/* Parse argv into o (defaults first): 0, or CLI_EUSAGE after one
 * message; --help prints the usage and exits 0. */
int rig_parse_opts(int argc, char **argv, rig_opts *o);

#endif

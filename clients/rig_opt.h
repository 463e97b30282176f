/* rig_opt.h - wgrig's options: their defaults, parsing and checks. */
#ifndef WG_RIG_OPT_H
#define WG_RIG_OPT_H

#include <stddef.h>

#include "wormgear/wg_sweep.h"

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

/* The swept parameter (*pid) and the analysis options (so: the library's
 * defaults, then o's transient, record, extension and tolerance; no early
 * stop, as the daemon runs the whole transient) from o: 0, or CLI_EUSAGE
 * after one message. */
int rig_check_opts(const rig_opts *o, wg_sweep_opts *so, int *pid);

/* What a ramp run (o->ramp > 0) does, for the captions and the .md: "ramp ω 0.5 → 1 and
 * back over 2 s simulated each way (≈ 5600 mesh periods), every section binned onto 25
 * values". pid: the parameter ramped; omega: the daemon's ω (the periods of a ramp of
 * another parameter); omega_n_rad_s: its scale (for a duration in s). Returns buf. */
const char *rig_ramp_text(const rig_opts *o, int pid, double omega, double omega_n_rad_s,
                          char *buf, size_t len);

#endif

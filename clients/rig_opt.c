/* rig_opt.c - wgrig's command line (rig_opt.h). */
#include "rig_opt.h"

#include "bus.h"
#include "cli.h"
#include "plot_text.h"
#include "wormgear/wg_sweep.h"

#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

static void usage(FILE *f)
{
    fprintf(f,
        "usage: wgrig --from A --to B [options]\n"
        "Automated rig sweep of a running wormgeard over LCM: set a parameter point by point\n"
        "(or ramp it), read POINCARE and CONTACT, and write the bifurcation diagram.\n\n"
        "  --url URL           LCM URL (default $WORMGEAR_URL or %s)\n"
        "  --prefix P          channel prefix (default $WORMGEAR_PREFIX or %s)\n"
        "  --key-file FILE     sign commands with this key (default $WORMGEAR_KEY_FILE):\n"
        "                      needed when the daemon has command_key_file\n"
        "  --param NAME        parameter driven (default omega; `wgctl params` lists them)\n"
        "  --from A --to B     range A < B, parameter's unit (required; within its range)\n"
        "  --points N          stepwise: points per direction (default 21; [2, 10000])\n"
        "  --dir up|down|both  sweep directions (default both)\n"
        "  --settle P          mesh periods discarded after each step (default 300; [0, 1e6])\n"
        "  --record R          mesh periods recorded per point (default 128; [64, %d])\n"
        "  --extend E          extra settle+record rounds while no period is found (default 3)\n"
        "  --ramp DURATION     slow ramp instead of steps: over DURATION simulated time per\n"
        "                      direction, e.g. 2s, 500ms, 20000tau (default: stepwise)\n"
        "  --bins N            ramp: parameter bins of the diagram (default --points)\n"
        "  --tol X             period tolerance, max norm, in [1e-13, 1e-4] (default: as\n"
        "                      wgsweep, max(1e-9, 10 x the one-period error of N vs 2N steps))\n"
        "  --no-lle            skip the Lyapunov exponent of aperiodic points (local twin run)\n"
        "  --fast              switch the daemon to fast mode for the sweep, restore after\n"
        "  --keep              leave the parameter at the last point (default: restore it)\n"
        "  --out PREFIX        outputs (default rig): PREFIX.png PREFIX.csv PREFIX-poincare.csv\n"
        "                      PREFIX.json PREFIX.md PREFIX-sections.csv PREFIX-impacts.csv/.png\n"
        "  --timeout SEC       wait for each ACK (default 3 s; (0, 600])\n"
        "  --stall SEC         give up when no section arrives for this long (default 10 s)\n"
        "  --retries N         per point: re-sends after no ACK, re-records after drops (default 5)\n"
        "  --quiet             no progress bar on stderr\n"
        "  -h, --help          this text\n\n"
        "Exit status: 0 ok, 1 runtime error, 2 usage error, 130 interrupted (partial outputs).\n",
        BUS_DEFAULT_URL, BUS_DEFAULT_PREFIX, RIG_REC_CAP);
}

#define PROG "wgrig"

const char *rig_ramp_text(const rig_opts *o, int pid, double omega, double omega_n_rad_s,
                          char *buf, size_t len)
{
    double a = fmin(o->from, o->to), b = fmax(o->from, o->to), k = 1, om = omega;
    int tau = !strcmp(o->unit, "tau"), both = o->up && o->down;
    if (!tau)
        k = omega_n_rad_s;
    if (pid == WG_P_OMEGA)
        om = (a + b) / 2; /* a linear ramp of ω: its mean ω */
    snprintf(buf, len, "ramp %s %g → %g%s over %g %s%s (≈ %.0f mesh periods), every section "
             "binned onto %d values", plot_text_psym(pid), o->up ? a : b,
             o->up ? b : a, both ? " and back" : "", o->ramp, tau ? "τ" : "s simulated",
             both ? " each way" : "", o->ramp * k * om / (2 * M_PI), o->bins);
    return buf;
}

/* --ramp: a duration > 0 (cli_duration). */
static int opt_ramp(rig_opts *o, const char *a)
{
    if (cli_duration(a, &o->ramp, &o->unit) || !isfinite(o->ramp) || !(o->ramp > 0))
        return cli_usage_error(PROG, "--ramp '%s': %s", a,
                               "a positive duration: 2s, 500ms, 1min, 20000tau");
    return 0;
}

static int opt_dir(rig_opts *o, const char *a)
{
    o->up = !strcmp(a, "up") || !strcmp(a, "both");
    o->down = !strcmp(a, "down") || !strcmp(a, "both");
    return o->up || o->down ? 0 : cli_usage_error(PROG, "--dir '%s': one of up, down, both", a);
}

static int opt_one(void *ctx, int c, const char *a)
{
    rig_opts *o = ctx;
    switch (c) {
    case 'u': o->url = a; return 0;
    case 'p': o->prefix = a; return 0;
    case 'k': o->key_file = a; return 0;
    case 'P': o->param = a; return 0;
    case 'o': o->out = a; return 0;
    case 'f':
        o->have_from = 1;
        return cli_opt_num(PROG, "--from", a, -1e300, 1e300, "a number", &o->from);
    case 't': o->have_to = 1; return cli_opt_num(PROG, "--to", a, -1e300, 1e300, "a number", &o->to);
    case 'n': return cli_opt_int(PROG, "--points", a, 2, 10000, "an integer in [2, 10000]", &o->points);
    case 'd': return opt_dir(o, a);
    case 's':
        return cli_opt_int(PROG, "--settle", a, 0, 1000000,
                           "mesh periods, an integer in [0, 1000000]", &o->settle);
    case 'r':
        return cli_opt_int(PROG, "--record", a, 64, RIG_REC_CAP,
                           "mesh periods, an integer in [64, 8192]", &o->record);
    case 'e': return cli_opt_int(PROG, "--extend", a, 0, 100, "an integer in [0, 100]", &o->extend);
    case 'R': return opt_ramp(o, a);
    case 'b': return cli_opt_int(PROG, "--bins", a, 2, 10000, "an integer in [2, 10000]", &o->bins);
    case 'T': { /* the range of wgsweep's --tol-floor: the library's */
        char allowed[80];
        snprintf(allowed, sizeof allowed, "a tolerance in [%g, %g] (as wgsweep's --tol-floor)",
                 WG_TOL_MIN, WG_TOL_FLOOR_MAX);
        return cli_opt_num(PROG, "--tol", a, WG_TOL_MIN, WG_TOL_FLOOR_MAX, allowed, &o->tol);
    }
    case 'L': o->lle = 0; return 0;
    case 'F': o->fast = 1; return 0;
    case 'K': o->keep = 1; return 0;
    case 'w': return cli_opt_num(PROG, "--timeout", a, 1e-3, 600, "seconds in (0, 600]", &o->timeout_s);
    case 'S': return cli_opt_num(PROG, "--stall", a, 0.1, 3600, "seconds in [0.1, 3600]", &o->stall_s);
    case 'x': return cli_opt_int(PROG, "--retries", a, 0, 1000, "an integer in [0, 1000]", &o->retries);
    case 'q': o->quiet = 1; return 0;
    case 'h': usage(stdout); exit(0);
    default: return -1;
    }
}

int rig_parse_opts(int argc, char **argv, rig_opts *o)
{
    static const struct option lo[] = {
        {"url", 1, 0, 'u'}, {"prefix", 1, 0, 'p'}, {"param", 1, 0, 'P'}, {"out", 1, 0, 'o'},
        {"from", 1, 0, 'f'}, {"to", 1, 0, 't'}, {"points", 1, 0, 'n'}, {"dir", 1, 0, 'd'},
        {"settle", 1, 0, 's'}, {"record", 1, 0, 'r'}, {"extend", 1, 0, 'e'}, {"ramp", 1, 0, 'R'},
        {"bins", 1, 0, 'b'}, {"tol", 1, 0, 'T'}, {"no-lle", 0, 0, 'L'}, {"fast", 0, 0, 'F'},
        {"keep", 0, 0, 'K'}, {"timeout", 1, 0, 'w'}, {"stall", 1, 0, 'S'},
        {"retries", 1, 0, 'x'}, {"quiet", 0, 0, 'q'}, {"key-file", 1, 0, 'k'},
        {"help", 0, 0, 'h'}, {0, 0, 0, 0}};
    *o = (rig_opts){.param = "omega", .out = "rig", .unit = "s", .points = 21, .up = 1, .down = 1,
                .settle = 300, .record = 128, .extend = 3, .lle = 1, .timeout_s = 3,
                .stall_s = 10, .retries = 5};
    int rc = cli_getopt(PROG, argc, argv, "h", lo, opt_one, o);
    if (rc)
        return rc;
    if (optind < argc)
        return cli_usage_error(PROG, "argument '%s': wgrig takes options only", argv[optind]);
    if (!o->have_from || !o->have_to)
        return cli_usage_error(PROG, "%s is required (the range of the sweep)",
                               o->have_from ? "--to" : "--from");
    if (o->from == o->to)
        return cli_usage_error(PROG, "--to %g: must differ from --from", o->to);
    if (o->from > o->to) /* was swapped silently, as wgsweep's was */
        return cli_usage_error(PROG, "--from %.15g --to %.15g: --from must be below --to (give "
                               "the range's lower end as --from; --dir up, down or both chooses "
                               "which way it is swept)", o->from, o->to);
    if (!o->bins)
        o->bins = o->points;
    return cli_opt_outdir(PROG, "--out", o->out);
}

int rig_check_opts(const rig_opts *o, wg_sweep_opts *so, int *pid)
{
    char why[256];
    wg_sweep_opts_default(so);
    so->transient = o->settle, so->record = o->record, so->extend = o->extend;
    so->settle = 0; /* the daemon runs the whole transient: no early stop */
    if (o->tol > 0)
        so->tol_floor = o->tol, so->tol_factor = 0;
    if ((*pid = cli_vary_param(o->param)) < 0)
        return cli_vary_param_error("wgrig", "--param", o->param, *pid);
    if (wg_param_check(*pid, o->from, why, sizeof why) ||
        wg_param_check(*pid, o->to, why, sizeof why))
        return fprintf(stderr, "wgrig: --from/--to: %s\n", why), CLI_EUSAGE;
    if (o->ramp > 0 && !(wg_param_info_get(*pid)->flags & WG_PF_RAMP))
        return cli_usage_error("wgrig", "--param '%s': not rampable: use the stepwise sweep",
                               o->param);
    return 0;
}

/* wgsweep - bifurcation analysis offline: 1-D sweeps (up and down, with
 * continuation) of omega or any table parameter, optionally for several
 * values of a second parameter; 2-D regime maps; single-point views.
 * Exit 0 ok, 1 runtime error, 2 usage error, 130 interrupted (partial
 * results written). */
#include "cli.h"
#include "cont_out.h"
#include "plot.h"
#include "plot_text.h"
#include "sweep_at.h"
#include "sweep_load.h"
#include "sweep_md.h"
#include "sweep_out.h"
#include "sweep_par.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_status.h"

#include <fcntl.h>
#include <float.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

static volatile sig_atomic_t g_stop; /* set by the signal handler only */

/* The first Ctrl-C (or SIGTERM) asks a sweep to stop after its current
 * points and write them; the second ends wgsweep at once. */
static void on_signal(int sig)
{
    g_stop = 1;
    signal(sig, SIG_DFL);
}

typedef struct opts {
    const char *scene, *out;
    const char *sets[64];
    int nsets;
    int param;
    double from, to, step;
    int points, points_set, up, down;
    int gparam, ngvals;
    double gvals[STUDY_MAX_GROUPS];
    int mparam, mrows;      /* --map NAME=A:B:M */
    double mfrom, mto;
    int threads, png, json, quiet;
    int at_set, at_periods;
    const char *table_from;
    const char *at_state;   /* --at-state FILE: a snapshot to start --at from */
    const char *exact[STUDY_MAX_GROUPS]; /* --exact: wgcont's bifurcations per group */
    int nexact;
    double at;
    const char *format;     /* figures: png, svg or pdf */
    wg_params scene_p;      /* the scene's own values, before --set */
    units_scale us;         /* its scale, for the figures' Hz and µm */
    wg_sweep_opts so;
} opts;

static void usage(FILE *f)
{
    fprintf(f,
        "usage: wgsweep [options]\n"
        "Bifurcation analysis of the worm-gear model: sweeps with continuation, regime\n"
        "detection (period, Lyapunov exponent, Floquet multipliers), transitions table.\n\n"
        "  --scene NAME|FILE       scene (default table3)\n"
        "  --set key=value         override a parameter (repeatable)\n"
        "  --param NAME            parameter swept (default omega; any table parameter)\n"
        "  --from A --to B         sweep range, A below B (default: omega 0.1 .. 2.5)\n"
        "  --points N | --step D   grid: N points (2 or more; 1 if A = B) or spacing D\n"
        "                          dividing the range (one of the two; default 241 points)\n"
        "  --dir up|down|both      sweep directions (default both): down runs B to A\n"
        "  --values NAME=v1,v2..   one up/down pair per value of another parameter\n"
        "  --map NAME=A:B:M        2-D regime map: M rows of NAME, each an up sweep\n"
        "  --transient T           periods before recording, per point (default 300)\n"
        "  --settle W              end the transient early once the last W Poincare\n"
        "                          sections repeat with a period <= min(W/2, W-8, 32)\n"
        "                          within the period tolerance (16..4096; 24 keeps every\n"
        "                          robust point's class; off by default: where attractors\n"
        "                          coexist a chain may then follow another one)\n"
        "  --full-transient        the whole transient, no early stop (the default)\n"
        "  --record R              periods recorded for the period test (64..4096, default 128)\n"
        "  --extend E              extra transients while no period is found (default 3)\n"
        "  --lle-periods L         twin-trajectory periods for aperiodic points (default 300)\n"
        "  --lle-tol X             |LLE| per period below X: quasi-periodic (default 0.01;\n"
        "                          %g to %g)\n"
        "  --tol-factor F          period tolerance = max(floor, F x one-period error)\n"
        "                          (default 10; %g to %g)\n"
        "  --tol-floor X           (default 1e-9; %g to %g: states in b_c, the upper end\n"
        "                          the tolerance of a slowly converging point)\n"
        "  --steps-per-period N    RK4 steps per mesh period (default 256; raised to 1.25x\n"
        "                          the RK4 stability limit where needed)\n"
        "  --stepper default|rk4|rk4-event (default: rk4-event; the printed form: rk4)\n"
        "  --floquet               Floquet multipliers of every periodic point\n"
        "  --verify-steps          re-analyse every point's attractor with 2N steps per\n"
        "                          period (step-halving check, run beside the sweep;\n"
        "                          about 1.5x the sweep's time)\n"
        "  --threads K             chains in parallel (default: online CPUs)\n"
        "  --pair K                chains each thread advances at once (default 8; 1: one\n"
        "                          at a time; the results are the same): two runs' steps\n"
        "                          in one instruction stream, or, with AVX2 or AVX-512,\n"
        "                          three or more in one loop, a run per vector lane\n"
        "  --out PREFIX            output prefix (default sweep): PREFIX.csv,\n"
        "                          PREFIX-poincare.csv, PREFIX.json, PREFIX.md, PREFIX.png\n"
        "                          (--values: PREFIX-NAME-V.png per value); the files\n"
        "                          written are listed on stderr at the end (not with\n"
        "                          --quiet); PREFIX's directory must exist (checked\n"
        "                          before the sweep)\n"
        "  --format png|svg|pdf    figure format (default png): every figure has a\n"
        "                          caption (scene, parameters set, N, transient and\n"
        "                          recorded periods) and axes with units (omega and\n"
        "                          mesh frequency in Hz, x_n in b_c and um)\n"
        "  --no-png, --no-json     skip the figures (any format), the JSON\n"
        "  --at V                  single point: summary, LLE, Floquet, phase portrait,\n"
        "                          Poincare map and time trace (PREFIX-at-NAME-V-*)\n"
        "  --at-periods P          Poincare periods for --at (default 2000)\n"
        "  --at-state FILE         start --at from a saved state (`wgctl save NAME` writes\n"
        "                          NAME.wgstate in the daemon's state dir), with its\n"
        "                          parameters, then --set and --at (default: the scene's\n"
        "                          initial state, [initial] in the scene file)\n"
        "  --table-from CSV        recompute the transitions table (PREFIX.md) from a\n"
        "                          points CSV of an earlier run, without integrating\n"
        "  --exact CSV             wgcont's PREFIX-bifurcations.csv: the table gains an\n"
        "                          \"exact (continuation)\" column (repeat once per --values\n"
        "                          group, in order)\n"
        "  --quiet                 no progress bar, no list of the files written\n"
        "  -h, --help              this text\n\n"
        "Ctrl-C stops a sweep after the current points and writes what is done (exit\n"
        "130); a second Ctrl-C, or one during --at, ends it at once.\n"
        "Exit status: 0 ok, 1 runtime error, 2 usage error (an option, or a file one names:\n"
        "--scene, --table-from, --exact), 130 interrupted.\n",
        WG_LLE_TOL_MIN, WG_LLE_TOL_MAX, WG_TOL_FACTOR_MIN, WG_TOL_FACTOR_MAX, WG_TOL_MIN,
        WG_TOL_FLOOR_MAX);
}

#define PROG "wgsweep"

/* The parameter NAME of "NAME=..." for option opt into *id, refused with
 * its reason. */
static int vary_name(const char *opt, const char *arg, char *name, int *id)
{
    if (!*name)
        return cli_usage_error(PROG, "%s '%s': need NAME=... (a parameter of the equations)",
                               opt, arg);
    int rc = cli_vary_param(name);
    if (rc < 0)
        return cli_vary_param_error(PROG, opt, name, rc);
    *id = rc;
    return 0;
}

/* A value of parameter id for option opt, in the table's range. */
static int vary_value(const char *opt, const char *arg, const char *t, int id, double *v)
{
    char why[160];
    if (cli_num(t, -DBL_MAX, DBL_MAX, v))
        return cli_usage_error(PROG, "%s '%s': '%s' is not a number", opt, arg, t);
    if (wg_param_check(id, *v, why, sizeof why))
        return cli_usage_error(PROG, "%s '%s': %s", opt, arg, why);
    return 0;
}

/* NAME=v1,v2,... (no empty item: "0.1,,0.2" was read as two values) */
static int parse_values(const char *arg, opts *o)
{
    char buf[1024];
    snprintf(buf, sizeof buf, "%s", arg);
    char *eq = strchr(buf, '=');
    if (!eq)
        return cli_usage_error(PROG, "--values '%s': need NAME=v1,v2,... (a parameter of the "
                               "equations, up to %d values)", arg, STUDY_MAX_GROUPS);
    *eq = 0;
    if (vary_name("--values", arg, buf, &o->gparam))
        return 2;
    o->ngvals = 0;
    for (char *t = eq + 1, *end;; t = end + 1) {
        if ((end = strchr(t, ',')))
            *end = 0;
        if (!*t)
            return cli_usage_error(PROG, "--values '%s': an empty value (need NAME=v1,v2,...)",
                                   arg);
        if (o->ngvals == STUDY_MAX_GROUPS)
            return cli_usage_error(PROG, "--values '%s': at most %d values", arg,
                                   STUDY_MAX_GROUPS);
        if (vary_value("--values", arg, t, o->gparam, &o->gvals[o->ngvals]))
            return 2;
        o->ngvals++;
        if (!end)
            return 0;
    }
}

/* NAME=A:B:M */
static int parse_map(const char *arg, opts *o)
{
    char buf[256];
    snprintf(buf, sizeof buf, "%s", arg);
    char *eq = strchr(buf, '='), *c1 = eq ? strchr(eq + 1, ':') : NULL;
    char *c2 = c1 ? strchr(c1 + 1, ':') : NULL;
    if (!c2)
        return cli_usage_error(PROG, "--map '%s': need NAME=A:B:M (a parameter of the "
                               "equations from A to B in M rows, 1..100000)", arg);
    *eq = *c1 = *c2 = 0;
    if (vary_name("--map", arg, buf, &o->mparam) ||
        vary_value("--map", arg, eq + 1, o->mparam, &o->mfrom) ||
        vary_value("--map", arg, c1 + 1, o->mparam, &o->mto))
        return 2;
    if (cli_int(c2 + 1, 1, 100000, &o->mrows))
        return cli_usage_error(PROG, "--map '%s': M, the rows, need 1..100000, got '%s'", arg,
                               c2 + 1);
    return 0;
}

/* Options that set analysis numbers (wg_sweep_opts). "> 0": from
 * DBL_TRUE_MIN up. */
static int parse_numeric(int c, const char *a, opts *o)
{
    wg_sweep_opts *s = &o->so;
    int bad = 0;
    const char *need = "unknown option";
    switch (c) {
    case 'T': bad = cli_int(a, 0, 100000000, &s->transient), need = "--transient: need 0..1e8, got"; break;
    case 'w': bad = cli_int(a, 16, 4096, &s->settle), need = "--settle: need 16..4096, got"; break;
    case 'R': bad = cli_int(a, 64, 4096, &s->record), need = "--record: need 64..4096, got"; break;
    case 'E': bad = cli_int(a, 0, 1000, &s->extend), need = "--extend: need 0..1000, got"; break;
    case 'L': bad = cli_int(a, 1, 100000000, &s->lle_periods), need = "--lle-periods: need 1..1e8, got"; break;
    /* the tolerances' ranges: wg_sweep_opts_check, once all are read */
    case 'l': bad = cli_double(a, &s->lle_tol), need = "--lle-tol: not a number:"; break;
    case 'F': bad = cli_double(a, &s->tol_factor), need = "--tol-factor: not a number:"; break;
    case 'f': bad = cli_double(a, &s->tol_floor), need = "--tol-floor: not a number:"; break;
    case 'N':
        bad = cli_int(a, WG_STEPS_MIN, WG_STEPS_MAX, &s->steps);
        need = "--steps-per-period: need 8..65536, got";
        break;
    case 'k':
        bad = (s->stepper = wg_stepper_lookup(a)) < WG_STEPPER_DEFAULT;
        need = "--stepper: default, rk4 or rk4-event, got";
        break;
    default: bad = 1;
    }
    return bad ? cli_usage_error(PROG, "%s '%s'", need, a) : 0;
}

static int parse_dir(const char *a, opts *o)
{
    if (strcmp(a, "both") && strcmp(a, "up") && strcmp(a, "down"))
        return cli_usage_error(PROG, "--dir: up, down or both, got '%s'", a);
    o->up = strcmp(a, "down") != 0;
    o->down = strcmp(a, "up") != 0;
    return 0;
}

static int parse_range(int c, const char *a, opts *o)
{
    int bad = 0;
    const char *need = NULL;
    switch (c) {
    case 'a': bad = cli_num(a, -DBL_MAX, DBL_MAX, &o->from), need = "--from: not a number:"; break;
    case 'b': bad = cli_num(a, -DBL_MAX, DBL_MAX, &o->to), need = "--to: not a number:"; break;
    case 'n':
        bad = cli_int(a, 1, 1000000, &o->points), need = "--points: need 1..1e6, got";
        o->points_set = 1;
        break;
    case 'd': bad = cli_num(a, DBL_TRUE_MIN, DBL_MAX, &o->step), need = "--step: need > 0, got"; break;
    case 'D': return parse_dir(a, o);
    case 'p':
        return (o->param = cli_vary_param(a)) < 0 ? cli_vary_param_error(PROG, "--param", a, o->param)
                                                   : 0;
    case 'V': return parse_values(a, o);
    case 'M': return parse_map(a, o);
    case 'Z': o->at_state = a; return 0;
    case 'A':
        o->at_set = 1, bad = cli_num(a, -DBL_MAX, DBL_MAX, &o->at), need = "--at: not a number:";
        break;
    case 'P': bad = cli_int(a, 1, 10000000, &o->at_periods), need = "--at-periods: need 1..1e7, got"; break;
    case 'j': bad = cli_int(a, 1, 256, &o->threads), need = "--threads: need 1..256, got"; break;
    case 'I': bad = cli_int(a, 1, 8, &o->so.pair), need = "--pair: need 1..8, got"; break;
    default: return parse_numeric(c, a, o);
    }
    return bad ? cli_usage_error(PROG, "%s '%s'", need, a) : 0;
}

/* What the options mean together, refused before anything runs: a range
 * out of the parameter's (found only when the chain reached it, exit 1
 * with the files marked complete), --values or --map of the swept
 * parameter itself (its values were lost), both at once (--values was
 * dropped). */
static int check_combination(const opts *o)
{
    const char *pn = wg_param_info_get(o->param)->name;
    char why[160];
    if (o->gparam >= 0 && o->mparam >= 0)
        return cli_usage_error(PROG, "--values and --map: give one (--values sweeps once per "
                               "value, --map once per row)");
    int other = o->gparam >= 0 ? o->gparam : o->mparam;
    if (other == o->param && !o->at_set && !o->table_from)
        return cli_usage_error(PROG, "%s %s: the parameter swept (--param %s); give another "
                               "(--param NAME chooses the swept one)",
                               o->gparam >= 0 ? "--values" : "--map", pn, pn);
    const char *opt[3] = {"--at", "--from", "--to"};
    double v[3] = {o->at, o->from, o->to};
    for (int i = o->at_set ? 0 : 1; i < (o->at_set ? 1 : 3) && !o->table_from; i++)
        if (wg_param_check(o->param, v[i], why, sizeof why))
            return cli_usage_error(PROG, "%s: %s", opt[i], why);
    return 0;
}

static void opts_default(opts *o)
{
    memset(o, 0, sizeof *o);
    o->scene = "table3", o->out = "sweep", o->param = WG_P_OMEGA, o->from = 0.1, o->to = 2.5;
    o->points = 241, o->up = o->down = 1, o->gparam = -1, o->mparam = -1, o->png = o->json = 1;
    o->at_periods = 2000, o->format = "png";
    long nc = sysconf(_SC_NPROCESSORS_ONLN);
    o->threads = nc < 1 ? 1 : nc > 256 ? 256 : (int)nc;
    wg_sweep_opts_default(&o->so);
}

/* The grid of a 1-D sweep, checked before anything runs: --from below --to
 * (a reversed range was swapped silently), N points or a step D dividing
 * the range, its two ends at least (equal ends: --points 1). 0, or 2. */
static int check_grid(opts *o)
{
    double range = o->to - o->from;
    if (o->at_set || o->table_from)
        return 0;
    if (range < 0)
        return cli_usage_error(PROG, "--from %.15g --to %.15g: --from must be below --to (give "
                               "the range's lower end as --from; --dir up, down or both chooses "
                               "which way it is swept)", o->from, o->to);
    if (o->step > 0 && o->step > range * (1 + 1e-12) && range > 0) /* it gave --from alone */
        return cli_usage_error(PROG, "--step %g: more than the range %g (--from %g --to %g); "
                               "need a step up to the range", o->step, range, o->from, o->to);
    if (o->step > 0 && o->points_set)
        return cli_usage_error(PROG, "--points %d and --step %g: give one (N points from --from "
                               "to --to, or their spacing)", o->points, o->step);
    if (range == 0 && (o->points > 1 || o->step > 0))
        return cli_usage_error(PROG, "--from and --to are both %g: no range to sweep (--at %g "
                               "analyses that one point)", o->from, o->from);
    if (range > 0 && o->points < 2)
        return cli_usage_error(PROG, "--points %d: a range (--from %.15g --to %.15g) needs 2 "
                               "points or more, its two ends at least (one point: --from V "
                               "--to V --points 1, or --at V)", o->points, o->from, o->to);
    if (o->step > 0) {
        double k = range / o->step, n = floor(k + 0.5);
        if (fabs(k - n) > 1e-5 * fmax(1.0, k)) { /* not the grid asked for (6 digits: taken) */
            double lo = floor(k), hi = ceil(k);
            return cli_usage_error(PROG, "--step %g: the range %g (--from %g --to %g) is %.4g "
                                   "steps of it, not a whole number; give --step %.6g (%g "
                                   "points) or %.6g (%g points), or --points N", o->step, range,
                                   o->from, o->to, k, range / lo, lo + 1, range / hi, hi + 1);
        }
        o->points = (int)n + 1;
    }
    return 0;
}

/* 0, 2 (a usage error, said), or -1: --help was asked for and printed. */
static int parse_opts(int argc, char **argv, opts *o)
{
    static const struct option lo[] = {
        {"scene", 1, 0, 's'}, {"set", 1, 0, 'S'}, {"param", 1, 0, 'p'}, {"from", 1, 0, 'a'},
        {"to", 1, 0, 'b'}, {"points", 1, 0, 'n'}, {"step", 1, 0, 'd'}, {"dir", 1, 0, 'D'},
        {"values", 1, 0, 'V'}, {"map", 1, 0, 'M'}, {"transient", 1, 0, 'T'},
        {"settle", 1, 0, 'w'}, {"full-transient", 0, 0, 'U'},
        {"record", 1, 0, 'R'}, {"extend", 1, 0, 'E'}, {"lle-periods", 1, 0, 'L'},
        {"lle-tol", 1, 0, 'l'}, {"tol-factor", 1, 0, 'F'}, {"tol-floor", 1, 0, 'f'},
        {"steps-per-period", 1, 0, 'N'}, {"stepper", 1, 0, 'k'}, {"floquet", 0, 0, 'Q'}, {"verify-steps", 0, 0, 'W'},
        {"threads", 1, 0, 'j'}, {"pair", 1, 0, 'I'}, {"out", 1, 0, 'o'}, {"no-png", 0, 0, 'G'}, {"no-json", 0, 0, 'J'},
        {"at", 1, 0, 'A'}, {"at-periods", 1, 0, 'P'}, {"at-state", 1, 0, 'Z'}, {"quiet", 0, 0, 'q'}, {"table-from", 1, 0, 'Y'},
        {"exact", 1, 0, 'X'}, {"format", 1, 0, 'O'},
        {"help", 0, 0, 'h'}, {0, 0, 0, 0}};
    opts_default(o);
    int c, rc;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "h", lo, NULL)) != -1) {
        switch (c) {
        case 's': o->scene = optarg; break;
        case 'S':
            if (o->nsets == 64)
                return cli_usage_error(PROG, "too many --set options, at most '%s'", "64");
            o->sets[o->nsets++] = optarg;
            break;
        case 'o': o->out = optarg; break;
        case 'Q': o->so.floquet = 1; break;
        case 'W': o->so.verify = 1; break;
        case 'U': o->so.settle = 0; break;
        case 'G': o->png = 0; break;
        case 'J': o->json = 0; break;
        case 'q': o->quiet = 1; break;
        case 'Y': o->table_from = optarg; break;
        case 'O':
            if (!plot_format_ok(optarg))
                return cli_usage_error(PROG, "--format: png, svg or pdf, got '%s'", optarg);
            o->format = optarg;
            break;
        case 'X':
            if (o->nexact == STUDY_MAX_GROUPS)
                return cli_usage_error(PROG, "too many --exact files, at most %d", STUDY_MAX_GROUPS);
            o->exact[o->nexact++] = optarg;
            break;
        case 'h': usage(stdout); return -1;
        case '?': return cli_getopt_error(PROG, argv, "h", lo);
        default:
            if ((rc = parse_range(c, optarg, o)))
                return rc;
        }
    }
    if (optind < argc)
        return cli_usage_error(PROG, "unexpected argument '%s'", argv[optind]);
    if (o->at_state && !o->at_set)
        return cli_usage_error(PROG, "--at-state needs --at V (the point to analyse)");
    const char *field = "";
    char why[160], opt[16];
    if (wg_sweep_opts_check(&o->so, &field, why, sizeof why)) { /* tol_floor: --tol-floor */
        for (int i = snprintf(opt, sizeof opt, "--%s", field); i > 2; i--)
            opt[i] = opt[i] == '_' ? '-' : opt[i];
        return cli_usage_error(PROG, "%s: %s", opt, why);
    }
    if ((rc = check_combination(o)))
        return rc;
    return check_grid(o);
}

/* ---- progress ---------------------------------------------------------- */

typedef struct progress {
    long total, done;
    double t0, last;
    int tty, quiet, lastpct;
} progress;

static void on_progress(void *ctx, long done)
{
    progress *p = ctx;
    p->done = done;
    if (p->quiet)
        return;
    double t = cli_mono_s(), el = t - p->t0;
    int pct = (int)(100 * p->done / (p->total ? p->total : 1));
    if (p->tty ? (t - p->last < 0.2 && p->done < p->total) : pct / 10 == p->lastpct / 10)
        return;
    p->last = t;
    p->lastpct = pct;
    double eta = p->done ? el * (p->total - p->done) / p->done : 0.0;
    char bar[41];
    int w = (int)(40 * p->done / (p->total ? p->total : 1));
    for (int i = 0; i < 40; i++)
        bar[i] = i < w ? '#' : '.';
    bar[40] = 0;
    fprintf(stderr, "%s[%s] %3d%% %ld/%ld points, %.0f s, eta %.0f s%s", p->tty ? "\r" : "", bar,
            pct, p->done, p->total, el, eta, p->tty ? "" : "\n");
    if (p->tty && p->done == p->total)
        fputc('\n', stderr);
}

/* ---- building and running ------------------------------------------------ */

static int new_chain(wg_chain *c, const wg_params *base, const opts *o, int dir, int param2)
{
    memset(c, 0, sizeof *c);
    c->base = *base;
    c->param = o->param;
    c->v0 = fmin(o->from, o->to);
    c->v1 = fmax(o->from, o->to);
    c->npts = o->points;
    c->dir = dir;
    c->param2 = param2;
    c->pts = calloc((size_t)o->points, sizeof(wg_point));
    return c->pts ? 0 : -1;
}

static int run_all(wg_chain *cs, int n, const opts *o, double *wall)
{
    long total = 0;
    for (int i = 0; i < n; i++)
        total += cs[i].npts;
    progress pg = {total, 0, cli_mono_s(), 0.0, isatty(2), o->quiet, -1};
    int rc = par_run(cs, n, &o->so, o->threads, &g_stop, on_progress, &pg);
    *wall = cli_mono_s() - pg.t0;
    return rc;
}

/* Write one output with fn(path, ...): 0 and its path on the list, or -1. */
#define WRITE(files, fn, path, ...)                                                       \
    (fn(path, __VA_ARGS__) ? -1 : (out_files_add(files, path), 0))

static int write_study(const opts *o, sweep_study *st, out_files *files)
{
    char why[2048];
    int rc = out_study(o->out, st, o->json, o->png, o->threads, files, why, sizeof why);
    if (rc)
        fprintf(stderr, "wgsweep: %s\n", why);
    return rc ? 1 : 0;
}

static int write_map(const opts *o, const char *scene, const wg_chain *rows, int n, int partial,
                     out_files *files)
{
    char path[1024], why[512], title[256];
    int rc = 0;
    snprintf(path, sizeof path, "%s-map.csv", o->out);
    rc |= WRITE(files, out_map_csv, path, rows, n, why, sizeof why);
    char xl[96], yl[96], x2[96], y2[96], cap[2][400], what[200];
    plot_scale2 sx = plot_text_pscale(o->param, &rows[0].base, &o->us, x2, sizeof x2);
    plot_scale2 sy = plot_text_pscale(o->mparam, &rows[0].base, &o->us, y2, sizeof y2);
    plot_text_caption(cap, scene, &rows[0].base, &o->scene_p, o->param, o->mparam, &o->so, 0, 0);
    if (n == 1) /* the one row is at mfrom: "1 rows ... in [0.05, 0.1]" said otherwise */
        snprintf(what, sizeof what, "1 row, %s = %g, an up sweep of %d points in %s",
                 plot_text_psym(o->mparam), o->mfrom, o->points, plot_text_psym(o->param));
    else
        snprintf(what, sizeof what, "%d rows of %s in [%g, %g], each an up sweep of %d points "
                 "in %s", n, plot_text_psym(o->mparam), o->mfrom, o->mto, o->points,
                 plot_text_psym(o->param));
    for (int mode = 0; o->png && mode < 2 && !rc; mode++) {
        snprintf(path, sizeof path, "%s-map%s.%s", o->out, mode ? "-motion" : "", o->format);
        snprintf(title, sizeof title, "%s: %s over (%s, %s), up sweeps%s", scene,
                 mode ? "motion class" : "regime", plot_text_psym(o->param),
                 plot_text_psym(o->mparam), partial ? " (partial)" : "");
        plot_map pm = {title, plot_text_plabel(o->param, xl, sizeof xl),
                       plot_text_plabel(o->mparam, yl, sizeof yl), rows, n, mode, sx, sy,
                       {o->format, {cap[0], cap[1], what, NULL}}};
        rc |= WRITE(files, plot_regime_map, path, &pm, why, sizeof why);
    }
    if (rc)
        fprintf(stderr, "wgsweep: %s\n", why);
    return rc ? 1 : 0;
}

/* Points measured over n chains: with none, nothing is written (a sweep
 * of a1 stopped at its first point wrote a1.csv, .md and .png empty). */
static int none_measured(const wg_chain *cs, int n)
{
    long done = 0;
    for (int i = 0; cs && i < n; i++)
        done += cs[i].ndone;
    if (!done)
        fprintf(stderr, "wgsweep: no point was measured: nothing written\n");
    return !done;
}

/* 2-D map: one up chain per row value. */
static int do_map(const opts *o, const wg_scene *sc, int rank)
{
    wg_chain *rows = calloc((size_t)o->mrows, sizeof *rows);
    int rc = rows ? 0 : 1;
    for (int r = 0; r < o->mrows && !rc; r++) {
        wg_params p = sc->p;
        p.v[o->mparam] = o->mrows > 1 ? o->mfrom + (o->mto - o->mfrom) * r / (o->mrows - 1) : o->mfrom;
        rc = new_chain(&rows[r], &p, o, +1, o->mparam);
    }
    double wall = 0.0;
    if (!rc)
        rc = run_all(rows, o->mrows, o, &wall);
    int partial = par_any(g_stop);
    if (rank == 0 && rows) {
        for (int r = 0; r < o->mrows; r++)
            if (rows[r].rc)
                fprintf(stderr, "wgsweep: row %d: %s\n", r, rows[r].why);
        out_files files = {"", 0};
        int none = none_measured(rows, o->mrows);
        rc = none || write_map(o, sc->name, rows, o->mrows, partial, &files) || rc;
        if (!o->quiet && !none)
            fprintf(stderr, "wgsweep: %d rows x %d points in %.1f s; wrote %s\n", o->mrows,
                    o->points, wall, files.list);
    }
    for (int r = 0; rows && r < o->mrows; r++)
        free(rows[r].pts);
    free(rows);
    return partial ? 130 : rc ? 1 : 0;
}

/* The up/down chains of every group of st into cs[n]: 0, or -1 (out of
 * memory). */
static int study_chains(sweep_study *st, wg_chain *cs, const opts *o, const wg_scene *sc)
{
    int per = o->up + o->down, rc = 0;
    for (int k = 0; k < st->ngroups && !rc; k++) {
        wg_params p = sc->p;
        if (o->gparam >= 0)
            p.v[o->gparam] = st->g[k].gval = o->gvals[k];
        wg_chain *c = &cs[k * per];
        if (o->up && !(rc = new_chain(c, &p, o, +1, o->gparam)))
            st->g[k].up = c++;
        if (o->down && !rc && !(rc = new_chain(c, &p, o, -1, o->gparam)))
            st->g[k].down = c;
    }
    return rc;
}

/* Attach --exact files to the study's groups: 0, or 2 (said). */
static int attach_exact(const opts *o, sweep_study *st, cont_bifs *ex)
{
    char why[640];
    if (!load_exact(o->exact, o->nexact, st, ex, why, sizeof why))
        return 0;
    fprintf(stderr, "wgsweep: %s\n", why);
    return 2;
}

/* 1-D study: up/down chains per group value. */
static int do_study(const opts *o, const wg_scene *sc, const char *cmd, int rank, int size)
{
    sweep_study st = {.scene = sc->name, .command = cmd, .param = o->param, .gparam = o->gparam,
                      .ngroups = o->gparam >= 0 ? o->ngvals : 1, .b = sc->p.v[WG_P_B],
                      .o = &o->so, .threads = o->threads, .pair = o->so.pair, .ranks = size,
                      .scene_p = &o->scene_p, .us = o->us, .format = o->format};
    int n = st.ngroups * (o->up + o->down), rc = 0;
    cont_bifs ex[STUDY_MAX_GROUPS];
    memset(ex, 0, sizeof ex);
    if ((rc = attach_exact(o, &st, ex)))
        return rc;
    wg_chain *cs = calloc((size_t)n, sizeof *cs);
    if (cs)
        rc = study_chains(&st, cs, o, sc);
    if (!cs || rc) {
        fprintf(stderr, "wgsweep: out of memory\n");
        rc = 1;
    } else {
        rc = run_all(cs, n, o, &st.wall_s);
    }
    st.partial = par_any(g_stop);
    if (rank == 0 && cs) {
        for (int i = 0; i < n; i++)
            if (cs[i].rc)
                fprintf(stderr, "wgsweep: chain %d stopped: %s\n", i, cs[i].why);
        out_files files = {"", 0};
        int none = none_measured(cs, n);
        rc = none || write_study(o, &st, &files) || rc;
        if (!o->quiet && !none)
            fprintf(stderr, "wgsweep: %d chains x %d points in %.1f s%s; wrote %s\n", n,
                    o->points, st.wall_s, st.partial ? " (interrupted)" : "", files.list);
    }
    for (int i = 0; cs && i < n; i++)
        free(cs[i].pts);
    free(cs);
    load_exact_free(ex, o->nexact);
    return st.partial ? 130 : rc ? 1 : 0;
}

/* Transitions table from an earlier run's points CSV. */
static int do_table(const opts *o, const wg_scene *sc, const char *cmd)
{
    sweep_study st;
    char why[512], path[1024];
    memset(&st, 0, sizeof st);
    st.scene = sc->name;
    st.command = cmd;
    st.source = o->table_from;
    st.b = sc->p.v[WG_P_B];
    st.o = &o->so;
    cont_bifs ex[STUDY_MAX_GROUPS];
    memset(ex, 0, sizeof ex);
    /* a points file that cannot be used is 2, as a scene or --exact file is */
    int lrc = load_points_csv(o->table_from, &st, why, sizeof why);
    int xrc = lrc == -1 ? 2 : lrc ? 1 : 0, rc = 0;
    if (xrc)
        fprintf(stderr, "wgsweep: %s\n", why);
    else if ((xrc = attach_exact(o, &st, ex)) == 0) {
        snprintf(path, sizeof path, "%s.md", o->out);
        if ((rc = md_write(path, &st, why, sizeof why)))
            fprintf(stderr, "wgsweep: %s\n", why);
    }
    load_exact_free(ex, o->nexact);
    load_free(&st);
    return xrc ? xrc : rc ? 1 : 0;
}

static int do_at(const opts *o, const wg_scene *sc)
{
    wg_params p = sc->p;
    char why[256];
    if (wg_param_check(o->param, o->at, why, sizeof why)) {
        fprintf(stderr, "wgsweep: --at: %s\n", why);
        return 2;
    }
    double y[WG_NSTATE_MAX] = {0};
    if (o->at_state) { /* the snapshot's parameters and state, then --set and --at */
        char w[640];
        if (at_state_load(o->at_state, sc->name, sc->model, &p, y, w, sizeof w)) {
            fprintf(stderr, "wgsweep: --at-state %s\n", w);
            return 1;
        }
        printf("start       %s: its parameters and state, run on to the next section\n",
               o->at_state);
        for (int i = 0; i < o->nsets; i++)
            if (wg_param_assign(&p, o->sets[i], why, sizeof why)) {
                fprintf(stderr, "wgsweep: --set %s\n", why);
                return 2;
            }
    } else {
        wg_scene_initial(sc, y);
    }
    p.v[o->param] = o->at;
    at_opts ao = {o->out, wg_param_info_get(o->param)->name, o->at, o->at_periods, 20, o->png,
                  o->format, sc->name, &o->scene_p, o->us};
    return at_view(&p, y, &o->so, &ao, stdout);
}

/* Under MPI every rank parses the same arguments and opens the same scene:
 * only rank 0 prints --help or says what is wrong with them, once (the
 * others' stdout and stderr go to /dev/null until they are checked). */
typedef struct hush {
    int saved[2]; /* copies of stdout and stderr (-1: not hushed) */
} hush;

static const int hush_fd[2] = {STDOUT_FILENO, STDERR_FILENO};

static hush hush_other_ranks(int rank)
{
    hush h = {{-1, -1}};
    if (rank == 0)
        return h;
    fflush(stdout);
    fflush(stderr);
    int nul = open("/dev/null", O_WRONLY);
    for (int i = 0; i < 2 && nul >= 0; i++) {
        h.saved[i] = dup(hush_fd[i]);
        if (h.saved[i] >= 0)
            dup2(nul, hush_fd[i]);
    }
    if (nul >= 0)
        close(nul);
    return h;
}

static void unhush(hush h)
{
    fflush(stdout);
    fflush(stderr);
    for (int i = 0; i < 2; i++)
        if (h.saved[i] >= 0) {
            dup2(h.saved[i], hush_fd[i]);
            close(h.saved[i]);
        }
}

int main(int argc, char **argv)
{
    int rank, size;
    if (par_init(&argc, &argv, &rank, &size)) {
        fprintf(stderr, "wgsweep: MPI initialisation failed\n");
        return 1;
    }
    hush hushed = hush_other_ranks(rank);
    opts o;
    int rc = parse_opts(argc, argv, &o), help = rc < 0;
    wg_scene sc;
    char why[640];
    if (!rc && (rc = wg_scene_open(&sc, o.scene, why, sizeof why))) {
        fprintf(stderr, "wgsweep: %s\n", why);
        rc = 2;
    }
    if (!rc) {
        o.scene_p = sc.p;
        o.us = plot_text_scale(sc.scale.omega_n_rad_s, sc.scale.length_m,
                               sc.scale.mesh_stiffness_N_m);
    }
    if (!rc && wg_scene_apply_sets(&sc, o.sets, o.nsets, why, sizeof why)) {
        fprintf(stderr, "wgsweep: --set %s\n", why);
        rc = 2;
    }
    if (!rc && wg_stepper_choose(sc.model, o.so.stepper, &o.so.stepper, why, sizeof why)) {
        fprintf(stderr, "wgsweep: --stepper: %s\n", why);
        rc = 2;
    }
    unhush(hushed);
    /* Only rank 0 writes, so only its --out is checked. Every rank learns
     * whether any refused the run (all take part, whatever rc is): a rank
     * on a host without the scene file would otherwise wait for the others
     * forever, its message hushed. */
    int bad_out = !rc && !help && rank == 0 && cli_opt_outdir(PROG, "--out", o.out) != 0;
    if (par_any(rc > 0 || bad_out) && !rc) {
        rc = 2;
        if (!bad_out)
            fprintf(stderr, "wgsweep: another MPI rank refused the run (its scene or --set: "
                            "every host needs the same build, scenes and paths)\n");
    }
    if (!rc) {
        o.so.model = sc.model;
        if (!o.table_from && !o.at_set) /* --at and --table-from stop at once */
            cli_on_stop_signals(on_signal);
        char *cmd = cli_join_args(argc, argv);
        if (o.table_from)
            rc = rank == 0 ? do_table(&o, &sc, cmd) : 0;
        else if (o.at_set)
            rc = rank == 0 ? do_at(&o, &sc) : 0;
        else if (o.mparam >= 0)
            rc = do_map(&o, &sc, rank);
        else
            rc = do_study(&o, &sc, cmd, rank, size);
        free(cmd);
    }
    plot_fini();
    par_fini();
    return cli_stdout_close(PROG, help ? 0 : rc);
}

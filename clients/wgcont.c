/* wgcont - continuation of periodic orbits with impacts: the branch of a
 * period-n orbit in any table parameter, stable and unstable, with its
 * folds, period doublings (and the period-2n branches born there), tori,
 * branch points and grazings located, over a sweep's bifurcation diagram.
 * Exit 0 ok, 1 runtime error, 2 usage error, 130 interrupted (what is done
 * is written). */
#include "cli.h"
#include "cont_out.h"
#include "plot.h"
#include "plot_cont.h"
#include "plot_text.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_status.h"
#include "wormgear/wg_sweep.h"

#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

static volatile sig_atomic_t g_stop; /* set by the signal handler only */

/* The first Ctrl-C (or SIGTERM) asks the run to stop after its current
 * point and write what is done; the second ends wgcont at once. */
static void on_signal(int sig)
{
    g_stop = 1;
    signal(sig, SIG_DFL);
}

typedef struct opts {
    const char *scene, *out, *format;
    const char *sets[64];
    int nsets;
    int start_set, sweep_points, quiet, threads;
    wg_params scene_p;  /* the scene's own values, before --set */
    wg_cont_opts co;
} opts;

static void usage(FILE *f)
{
    fprintf(f,
        "usage: wgcont --scene NAME [--set k=v]... [--param omega] --from A --to B [--start V]\n"
        "              [--period n] [--steps-per-period N] [--max-step D] --out PREFIX\n"
        "Continuation of a periodic orbit of the worm-gear model (rk4-event Poincare map,\n"
        "Newton with the variational monodromy, pseudo-arclength): the branch, stable and\n"
        "unstable, its folds, period doublings, tori, branch points and grazings located.\n\n"
        "  --scene NAME|FILE       scene (default table3)\n"
        "  --set key=value         override a parameter (repeatable)\n"
        "  --param NAME            parameter continued (default omega; any table parameter)\n"
        "  --from A --to B         range; a branch ends where it leaves it\n"
        "  --start V               first point (default A): the attractor reached there from\n"
        "                          the scene's initial state, refined by Newton; inside the\n"
        "                          range the branch is followed both ways\n"
        "  --period n              period of the orbit in mesh periods (default 1)\n"
        "  --steps-per-period N    RK4 steps per mesh period (default 256, as wgsweep;\n"
        "                          raised to 1.25x the RK4 stability limit over the range)\n"
        "  --max-step D            largest arclength step (default 0.01: parameter units,\n"
        "                          the state by its RMS)\n"
        "  --depth K               period-doubling branch switches (default 1, 0: none)\n"
        "  --tol X                 Newton residual |P^n(x) - x|, max norm, states in b_c\n"
        "                          (default 1e-10; %g to %g: under it double precision\n"
        "                          cannot reach it, over it the orbit is too rough)\n"
        "  --loc-tol X             location: arclength bracket, parameter units (default\n"
        "                          1e-9; %g to %g)\n"
        "  --transient T           periods run before the first Newton (default 500)\n"
        "  --monodromy map|flow    derivative used (default map: of the Poincare map itself)\n"
        "  --sweep-points K        background sweep, up and down, K points (default 101;\n"
        "                          0: none)\n"
        "  --threads K             threads for the sweep (default: online CPUs, at most 2)\n"
        "  --format png|svg|pdf    figure format (default png)\n"
        "  --out PREFIX            PREFIX-branch.csv, PREFIX-bifurcations.csv, PREFIX.png\n"
        "  --quiet                 no progress on stderr\n"
        "  -h, --help              this text\n\n"
        "Ctrl-C stops after the current point and writes what is done (exit\n"
        "130); a second Ctrl-C ends wgcont at once.\n"
        "Exit status: 0 ok, 1 runtime error, 2 usage error, 130 interrupted.\n",
        WG_TOL_MIN, WG_CONT_TOL_MAX, WG_TOL_MIN, WG_CONT_LOC_TOL_MAX);
}

static int bad(const char *what, const char *arg)
{
    fprintf(stderr, arg ? "wgcont: %s '%s'\n(try wgcont --help)\n" : "wgcont: %s\n(try wgcont "
            "--help)\n", what, arg);
    return 2;
}

static int num(const char *s, double *v)
{
    char *end;
    *v = strtod(s, &end);
    return end != s && !*end && isfinite(*v) ? 0 : -1;
}

static int inum(const char *s, long lo, long hi, int *v)
{
    char *end;
    long x = strtol(s, &end, 10);
    if (end == s || *end || x < lo || x > hi)
        return -1;
    *v = (int)x;
    return 0;
}

static int parse_numbers(int c, const char *a, opts *o)
{
    wg_cont_opts *co = &o->co;
    switch (c) {
    case 'a': return num(a, &co->from) ? bad("--from: not a number:", a) : 0;
    case 'b': return num(a, &co->to) ? bad("--to: not a number:", a) : 0;
    case 'S': o->start_set = 1; return num(a, &co->start) ? bad("--start: not a number:", a) : 0;
    case 'n': return inum(a, 1, WG_SHOOT_NMAX, &co->period) ? bad("--period: need 1..32, got", a) : 0;
    case 'N': return inum(a, WG_STEPS_MIN, WG_STEPS_MAX, &co->steps) ? bad("--steps-per-period: need 8..65536, got", a) : 0;
    case 'm': return num(a, &co->ds_max) || !(co->ds_max > 0) ? bad("--max-step: need > 0, got", a) : 0;
    case 'd': return inum(a, 0, 8, &co->depth) ? bad("--depth: need 0..8, got", a) : 0;
    case 't': return num(a, &co->tol) ? bad("--tol: not a number:", a) : 0; /* range: check_range */
    case 'l': return num(a, &co->loc_tol) ? bad("--loc-tol: not a number:", a) : 0;
    case 'T': return inum(a, 0, 100000000, &co->transient) ? bad("--transient: need 0..1e8, got", a) : 0;
    case 'k': return inum(a, 0, 100000, &o->sweep_points) || o->sweep_points == 1 ? bad("--sweep-points: need 0 or 2..1e5, got", a) : 0;
    case 'j': return inum(a, 1, 256, &o->threads) ? bad("--threads: need 1..256, got", a) : 0;
    default: return bad("unknown option", a);
    }
}

/* The options as the library checks them (wg_cont_check), a refusal said
 * with the option that sets the field at fault: a usage error. */
static int check_range(opts *o)
{
    static const struct {
        const char *field, *opt;
    } flag[] = {{"from", "--from"},       {"to", "--to"},           {"range", "--from and --to"},
                {"start", "--start"},     {"period", "--period"},   {"ds_max", "--max-step"},
                {"tol", "--tol"},         {"loc_tol", "--loc-tol"}, {"depth", "--depth"},
                {"transient", "--transient"}, {"model", "--scene"}, {"param", "--param"}};
    wg_cont_opts *co = &o->co;
    if (!o->start_set)
        co->start = co->from;
    if (co->ds0 > co->ds_max)
        co->ds0 = co->ds_max; /* a --max-step below the first step: it starts there (one
                               * below ds_min is refused as --max-step, checked first) */
    const char *field = "", *opt = NULL;
    char why[200];
    if (!wg_cont_check(co, &field, why, sizeof why))
        return 0;
    for (unsigned i = 0; i < sizeof flag / sizeof flag[0]; i++)
        if (strcmp(field, flag[i].field) == 0)
            opt = flag[i].opt;
    return cli_usage_error("wgcont", "%s: %s", opt ? opt : field, why);
}

static int parse_word(int c, const char *a, opts *o)
{
    switch (c) {
    case 'p':
        return (o->co.param = cli_vary_param(a)) < 0 ? cli_vary_param_error("wgcont", "--param", a,
                                                                             o->co.param)
                                                      : 0;
    case 'M':
        if (strcmp(a, "map") && strcmp(a, "flow"))
            return bad("--monodromy: map or flow, got", a);
        o->co.monodromy = strcmp(a, "map") ? WG_MONODROMY_FLOW : WG_MONODROMY_MAP;
        return 0;
    case 'F':
        if (strcmp(a, "png") && strcmp(a, "svg") && strcmp(a, "pdf"))
            return bad("--format: png, svg or pdf, got", a);
        o->format = a;
        return 0;
    case 's': o->scene = a; return 0;
    case 'o': o->out = a; return 0;
    case 'e':
        if (o->nsets == 64)
            return bad("too many --set options, at most", "64");
        o->sets[o->nsets++] = a;
        return 0;
    default: return parse_numbers(c, a, o);
    }
}

static int parse_opts(int argc, char **argv, opts *o)
{
    static const struct option lo[] = {
        {"scene", 1, 0, 's'}, {"set", 1, 0, 'e'}, {"param", 1, 0, 'p'}, {"from", 1, 0, 'a'},
        {"to", 1, 0, 'b'}, {"start", 1, 0, 'S'}, {"period", 1, 0, 'n'},
        {"steps-per-period", 1, 0, 'N'}, {"max-step", 1, 0, 'm'}, {"depth", 1, 0, 'd'},
        {"tol", 1, 0, 't'}, {"loc-tol", 1, 0, 'l'}, {"transient", 1, 0, 'T'},
        {"monodromy", 1, 0, 'M'},
        {"sweep-points", 1, 0, 'k'}, {"threads", 1, 0, 'j'}, {"format", 1, 0, 'F'},
        {"out", 1, 0, 'o'}, {"quiet", 0, 0, 'q'}, {"help", 0, 0, 'h'}, {0, 0, 0, 0}};
    memset(o, 0, sizeof *o);
    o->scene = "table3", o->out = "cont", o->format = "png", o->sweep_points = 101;
    long nc = sysconf(_SC_NPROCESSORS_ONLN);
    o->threads = nc < 2 ? 1 : 2;
    wg_cont_opts_default(&o->co);
    int c, rc, have_from = 0, have_to = 0;
    opterr = 0;
    while ((c = getopt_long(argc, argv, "h", lo, NULL)) != -1) {
        if (c == 'h') {
            usage(stdout);
            exit(0);
        }
        if (c == 'q') {
            o->quiet = 1;
            continue;
        }
        if (c == '?')
            return cli_getopt_error("wgcont", argv, "h", lo);
        have_from |= c == 'a', have_to |= c == 'b';
        if ((rc = parse_word(c, optarg, o)))
            return rc;
    }
    if (optind < argc)
        return bad("unexpected argument", argv[optind]);
    if (!have_from || !have_to)
        return bad("--from and --to are required (the range to continue over)", NULL);
    if ((rc = check_range(o)))
        return rc;
    return cli_opt_outdir("wgcont", "--out", o->out);
}

/* ---- progress (stderr) and collection -------------------------------------------- */

typedef struct ctx {
    cont_result r;
    const char *pname;
    int quiet, oom;
    long shown_branch;
    double t0;
} ctx;

static double now_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

static void on_point(void *vc, const wg_cont_point *p)
{
    ctx *c = vc;
    c->oom |= cont_add_point(&c->r, p);
    if (c->quiet || (p->index % 50 && p->index))
        return;
    fprintf(stderr, "wgcont: branch %d (period %d): point %d at %s = %.6f, %s, %.1f s\n",
            p->branch, p->period, p->index, c->pname, p->value, p->stable ? "stable" : "unstable",
            now_s() - c->t0);
}

static void on_bif(void *vc, const wg_bif *b)
{
    ctx *c = vc;
    c->oom |= cont_add_bif(&c->r, b);
    if (c->quiet)
        return;
    fprintf(stderr, "wgcont: %s at %s = %.9f (branch %d, period %d", wg_bif_name(b->kind),
            c->pname, b->value, b->branch, b->period);
    if (b->kind == WG_BIF_GRAZING)
        fprintf(stderr, ", %s %s %c%s", b->extreme < 0 ? "min" : "max",
                wg_contact_name(b->contact), b->side > 0 ? '+' : '-',
                b->contact == WG_C_MESH ? "b" : "b_j");
    else
        fprintf(stderr, ", multiplier %+.6f%+.6fi", b->mu_re, b->mu_im);
    fprintf(stderr, ", bracket %.1e)\n", b->bracket);
}

static void on_note(void *vc, int code, int branch, double v, const char *msg)
{
    ctx *c = vc;
    c->r.newton_fails += code == WG_NOTE_NEWTON;
    if (!c->quiet && code != WG_NOTE_ANGLE) /* step control, not news */
        fprintf(stderr, "wgcont: branch %d, %s = %.8f: %s\n", branch, c->pname, v, msg);
}

/* ---- the sweep behind the figure ----------------------------------------------- */

static int run_sweep(const wg_params *p, const wg_cont_opts *co, const opts *o, wg_chain c[2])
{
    wg_sweep_opts so;
    wg_sweep_opts_default(&so);
    so.steps = co->steps;
    for (int k = 0; k < 2; k++) {
        memset(&c[k], 0, sizeof c[k]);
        c[k].base = *p;
        c[k].param = co->param;
        c[k].v0 = fmin(co->from, co->to);
        c[k].v1 = fmax(co->from, co->to);
        c[k].npts = o->sweep_points;
        c[k].dir = k ? -1 : +1;
        c[k].param2 = -1;
        if (!(c[k].pts = calloc((size_t)o->sweep_points, sizeof(wg_point))))
            return -1;
    }
    return wg_chains_run(c, 2, &so, o->threads, &g_stop, NULL, NULL);
}

/* ---- outputs ------------------------------------------------------------------- */

/* Caption: scene, damping, N, the run; the parameters set away from the
 * scene; what the figure holds. */
static void captions(const opts *o, const wg_scene *sc, const ctx *c, const wg_chain *sw,
                     char cap[3][400])
{
    const wg_cont_opts *co = &o->co;
    char xi[32];
    if (co->param == WG_P_XI_P)
        snprintf(xi, sizeof xi, "ξ_p continued");
    else
        snprintf(xi, sizeof xi, "ξ_p = %g", sc->p.v[WG_P_XI_P]);
    snprintf(cap[0], 400, "scene %s, %s, N = %d steps per mesh period; period-%d orbit from %s "
             "= %g, continued over [%g, %g]", sc->name, xi, co->steps, co->period, c->pname,
             co->start, fmin(co->from, co->to), fmax(co->from, co->to));
    int n = snprintf(cap[1], 400, "set away from the scene:"), shown = 0;
    for (int id = 0; id < WG_NPARAM && n < 340; id++)
        if (sc->p.v[id] != o->scene_p.v[id] && id != co->param)
            n += snprintf(cap[1] + n, (size_t)(400 - n), "%s %s = %g (scene: %g)",
                          shown++ ? "," : "", wg_param_info_get(id)->name, sc->p.v[id],
                          o->scene_p.v[id]);
    if (!shown)
        snprintf(cap[1], 400, "every other parameter as in the scene");
    snprintf(cap[2], 400, "%d branch points, %d bifurcations, %d Newton failures (step "
             "halved)%s%s", c->r.npt, c->r.nbif, c->r.newton_fails,
             sw && (sw[0].ndone || sw[1].ndone) ? "; dots: sweep with continuation, up and "
                                                  "down" : "",
             g_stop ? "; INTERRUPTED" : "");
}

static int write_all(const opts *o, const wg_scene *sc, const ctx *c, const wg_chain *sw)
{
    char path[1024], why[512], cap[3][400], xl[96], x2l[96], title[160];
    int nstate = wg_model_nstate(sc->model), rc = 0;
    snprintf(path, sizeof path, "%s-branch.csv", o->out);
    rc |= cont_write_branch(path, &c->r, o->co.param, nstate, why, sizeof why);
    snprintf(path, sizeof path, "%s-bifurcations.csv", o->out);
    rc |= cont_write_bifs(path, &c->r, o->co.param, nstate, why, sizeof why);
    captions(o, sc, c, sw, cap);
    plot_text_plabel(o->co.param, xl, sizeof xl);
    snprintf(title, sizeof title, "Continuation of periodic orbits in %s: scene %s", c->pname,
             sc->name);
    plot_cont pc = {title, {cap[0], cap[1], cap[2]}, xl, fmin(o->co.from, o->co.to),
                    fmax(o->co.from, o->co.to), sc->p.v[WG_P_B], &c->r,
                    sw ? sw[0].pts : NULL, sw ? sw[1].pts : NULL, sw ? sw[0].ndone : 0,
                    sw ? sw[1].ndone : 0, o->format, {0, NULL, 0}, {0, NULL, 0}};
    units_scale us = plot_text_scale(sc->scale.omega_n_rad_s, sc->scale.length_m,
                                     sc->scale.mesh_stiffness_N_m);
    pc.x2 = plot_text_pscale(o->co.param, &sc->p, &us, x2l, sizeof x2l); /* Hz for omega */
    if (units_scale_ok(&us))
        pc.y2 = (plot_scale2){units_um_per_x(&us), PLOT_XN_UM, 0};
    snprintf(path, sizeof path, "%s.%s", o->out, o->format);
    if (!rc)
        rc |= plot_continuation(path, &pc, why, sizeof why);
    if (rc)
        fprintf(stderr, "wgcont: %s\n", why);
    else if (!o->quiet)
        fprintf(stderr, "wgcont: wrote %s-branch.csv, %s-bifurcations.csv, %s\n", o->out,
                o->out, path);
    return rc ? 1 : 0;
}

static int load_scene(opts *o, wg_scene *sc)
{
    char why[640];
    if (wg_scene_open(sc, o->scene, why, sizeof why)) {
        fprintf(stderr, "wgcont: %s\n", why);
        return 2;
    }
    o->scene_p = sc->p;
    if (wg_scene_apply_sets(sc, o->sets, o->nsets, why, sizeof why)) {
        fprintf(stderr, "wgcont: --set %s\n", why);
        return 2;
    }
    if (sc->model != WG_MODEL_CONSISTENT) {
        fprintf(stderr, "wgcont: scene %s: continuation needs the consistent model\n", sc->name);
        return 2;
    }
    return 0;
}

static int run(opts *o, const wg_scene *sc)
{
    ctx c = {{0}, wg_param_info_get(o->co.param)->name, o->quiet, 0, -1, now_s()};
    wg_cont_sink sink = {&c, on_point, on_bif, on_note};
    double y[WG_NSTATE_MAX];
    char why[640];
    o->co.steps = wg_cont_steps(&sc->p, &o->co);
    wg_scene_initial(sc, y);
    int rc = wg_cont_run(&sc->p, y, &o->co, &sink, &g_stop, why, sizeof why), out = 0;
    if (rc)
        fprintf(stderr, "wgcont: %s\n", why);
    if (!rc && !o->quiet)
        fprintf(stderr, "wgcont: %d points, %d bifurcations in %.1f s%s\n", c.r.npt, c.r.nbif,
                now_s() - c.t0, g_stop ? " (interrupted: the rest and the sweep not run)" : "");
    wg_chain sw[2];
    memset(sw, 0, sizeof sw);
    double t1 = now_s();
    int have_sweep = !rc && o->sweep_points && !g_stop && run_sweep(&sc->p, &o->co, o, sw) == 0;
    if (have_sweep && !o->quiet)
        fprintf(stderr, "wgcont: sweep of %d points up and down in %.1f s\n", o->sweep_points,
                now_s() - t1);
    if (c.oom)
        fprintf(stderr, "wgcont: out of memory: some points are missing\n");
    if (!rc || c.r.npt)
        out = write_all(o, sc, &c, have_sweep || g_stop ? sw : NULL);
    free(sw[0].pts);
    free(sw[1].pts);
    cont_result_free(&c.r);
    return g_stop ? 130 : rc || out || c.oom ? 1 : 0;
}

int main(int argc, char **argv)
{
    opts o;
    wg_scene sc;
    int rc = parse_opts(argc, argv, &o);
    if (!rc)
        rc = load_scene(&o, &sc);
    if (!rc) {
        o.co.model = sc.model;
        cli_on_stop_signals(on_signal);
        rc = run(&o, &sc);
    }
    plot_fini();
    return cli_stdout_close("wgcont", rc);
}

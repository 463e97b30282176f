/* wgsim - run the worm-gear model offline and write CSV or a summary.
 * Exit 0 ok, 1 runtime error, 2 usage error, 130 stopped by a signal. */
#include "cli.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_sim.h"
#include "wormgear/wg_status.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define TWO_PI 6.283185307179586
#define PROG "wgsim"

static volatile sig_atomic_t g_stop; /* set by the signal handler only */

/* The first Ctrl-C (or SIGTERM) asks the run to stop at the end of the
 * chunk of periods it is in; a second ends wgsim at once (the default
 * action), as wgsweep's and wgcont's do. */
static void on_signal(int sig)
{
    g_stop = 1;
    signal(sig, SIG_DFL);
}

typedef struct opts {
    const char *scene;
    const char *sets[64];
    int nsets;
    int periods, transient;
    int steps, stepper, model; /* model -1: the scene's */
    const char *poincare, *events, *trace;
    int physical;
} opts;

typedef struct run {
    const opts *o;
    const wg_scene *sc;
    FILE *fp, *fe, *ft;
    long recorded;
    long motion[3];
    long impacts;
    double min_xn, max_xn;
} run;

static void usage(FILE *f)
{
    fprintf(f,
            "usage: wgsim [options]\n"
            "Integrate the worm-gear model of a scene and write CSV or a summary.\n\n"
            "  --scene NAME|FILE         scene name or INI file (default table3)\n"
            "  --set key=value           override a parameter (repeatable; list below)\n"
            "  --periods P               mesh periods recorded after the transient (default 200)\n"
            "  --transient T             mesh periods run first, not recorded (default 100)\n"
            "  --steps-per-period N      RK4 steps per mesh period, %d..%d (default %d)\n"
            "  --stepper default|rk4|rk4-event  plain RK4, or RK4 split at located\n"
            "                            dead-zone crossings; default: rk4-event (the\n"
            "                            printed form runs rk4 only)\n"
            "  --model consistent|printed  equations (default: the scene's, consistent)\n"
            "  --poincare FILE|-         CSV of the Poincare section (psi = 0), one row a period\n"
            "  --events FILE|-           CSV of contact events: tau,contact,kind,velocity\n"
            "  --trace FILE|-            CSV of every step: tau,omega,x_n,dx_n,F,theta1,theta2\n"
            "                            (theta1, theta2: worm and wheel angles in rad, [0, 2 pi);\n"
            "                            the Poincare CSV ends with them too); '-' is stdout, for\n"
            "                            one of the three at most (two CSVs would interleave)\n"
            "  --units dimensionless|physical  CSV units (default dimensionless); physical:\n"
            "                            s, Hz, um, m/s, N (column names get unit suffixes)\n"
            "  -h, --help                this text\n\n"
            "Exit status: 0 ok, 1 runtime error, 2 usage error, 130 stopped: Ctrl-C or\n"
            "SIGTERM stops the run at the end of a chunk of whole periods (a few ms), with\n"
            "every row written whole and a line saying after how many periods; a second\n"
            "Ctrl-C ends it at once.\n\n"
            "Parameters (dimensionless; name unit [min, max] default: help):\n",
            WG_STEPS_MIN, WG_STEPS_MAX, WG_STEPS_DEFAULT);
    for (int i = 0; i < WG_NPARAM; i++) {
        const wg_param_info *r = wg_param_info_get(i);
        char range[48];
        fprintf(f, "  %-5s %-3s %s %g: %s\n", r->name, wg_unit_shown(r->unit),
                wg_range_shown(r->min, r->max, range, sizeof range), r->def, r->help);
    }
    fprintf(f, "\nScene [physical] keys (unit [min, max]):\n");
    for (int i = 0; i < wg_scene_nphys(); i++) {
        const wg_param_info *r = wg_scene_phys_info(i);
        char range[48];
        fprintf(f, "  %-28s %-7s %s: %s\n", r->name, r->unit,
                wg_range_shown(r->min, r->max, range, sizeof range), r->help);
    }
}

static int opt_model(const char *a, int *model)
{
    int m = wg_model_lookup(a);
    if (m < 0)
        return cli_usage_error(PROG, "--model '%s': allowed values are consistent, printed", a);
    *model = m;
    return 0;
}

static int opt_units(const char *a, int *physical)
{
    if (strcmp(a, "physical") == 0)
        *physical = 1;
    else if (strcmp(a, "dimensionless") != 0)
        return cli_usage_error(PROG, "--units '%s': allowed values are dimensionless, physical",
                               a);
    return 0;
}

/* One option c with argument a: 0, CLI_EUSAGE (reported), or -1 unknown. */
static int opt_one(void *ctx, int c, const char *a)
{
    opts *o = ctx;
    switch (c) {
    case 's': o->scene = a; return 0;
    case 'S':
        if (o->nsets == 64)
            return cli_usage_error(PROG, "too many --set options (at most %s)", "64");
        o->sets[o->nsets++] = a;
        return 0;
    case 'p':
        return cli_opt_int(PROG, "--periods", a, 1, 1000000000, "must be an integer in [1, 1e9]",
                           &o->periods);
    case 't':
        return cli_opt_int(PROG, "--transient", a, 0, 1000000000,
                           "must be an integer in [0, 1e9]", &o->transient);
    case 'n':
        return cli_opt_int(PROG, "--steps-per-period", a, WG_STEPS_MIN, WG_STEPS_MAX,
                           "must be an integer in [8, 65536]", &o->steps);
    case 'k':
        if ((o->stepper = wg_stepper_lookup(a)) < WG_STEPPER_DEFAULT)
            return cli_usage_error(PROG, "--stepper '%s': allowed values are default, rk4, "
                                         "rk4-event", a);
        return 0;
    case 'm': return opt_model(a, &o->model);
    case 'P': o->poincare = a; return 0;
    case 'E': o->events = a; return 0;
    case 'T': o->trace = a; return 0;
    case 'u': return opt_units(a, &o->physical);
    case 'h': usage(stdout); exit(0);
    default: return -1;
    }
}

/* Two CSVs on stdout would interleave row by row: at most one output may
 * be "-", and no file may be named twice. 0, or CLI_EUSAGE naming the
 * options. */
static int one_on_stdout(const opts *o)
{
    static const char *const names[3] = {"--poincare", "--events", "--trace"};
    const char *paths[3] = {o->poincare, o->events, o->trace}, *on[3];
    int n = 0;
    for (int i = 0; i < 3; i++)
        if (paths[i] && strcmp(paths[i], "-") == 0)
            on[n++] = names[i];
    if (n == 2)
        return cli_usage_error(PROG, "%s and %s both write to '-': at most one output may go to "
                               "stdout (give the other a FILE)", on[0], on[1]);
    if (n == 3)
        return cli_usage_error(PROG, "%s, %s and %s all write to '-': at most one output may go "
                               "to stdout (give the others a FILE)", on[0], on[1], on[2]);
    for (int i = 0; i < 3; i++) /* one file twice: each open truncated the other's rows */
        for (int j = i + 1; j < 3; j++)
            if (paths[i] && paths[j] && strcmp(paths[i], "-") && !strcmp(paths[i], paths[j]))
                return cli_usage_error(PROG, "%s and %s both write %s: give each its own file",
                                       names[i], names[j], paths[i]);
    return 0;
}

static int parse_opts(int argc, char **argv, opts *o)
{
    static const struct option lo[] = {
        {"scene", required_argument, 0, 's'},     {"set", required_argument, 0, 'S'},
        {"periods", required_argument, 0, 'p'},   {"transient", required_argument, 0, 't'},
        {"steps-per-period", required_argument, 0, 'n'},
        {"stepper", required_argument, 0, 'k'},   {"model", required_argument, 0, 'm'},
        {"poincare", required_argument, 0, 'P'},  {"events", required_argument, 0, 'E'},
        {"trace", required_argument, 0, 'T'},     {"units", required_argument, 0, 'u'},
        {"help", no_argument, 0, 'h'},            {0, 0, 0, 0}};
    *o = (opts){.scene = "table3", .periods = 200, .transient = 100,
                .steps = WG_STEPS_DEFAULT, .stepper = WG_STEPPER_DEFAULT, .model = -1};
    int rc = cli_getopt(PROG, argc, argv, "h", lo, opt_one, o);
    if (rc)
        return rc;
    if (optind < argc)
        return cli_usage_error(PROG, "unexpected argument '%s'", argv[optind]);
    return one_on_stdout(o);
}

/* ---- output ------------------------------------------------------------- */

static FILE *open_out(const char *path)
{
    if (!path)
        return NULL;
    if (strcmp(path, "-") == 0)
        return stdout;
    FILE *f = fopen(path, "w");
    if (!f)
        fprintf(stderr, "wgsim: cannot write '%s': %s\n", path, strerror(errno));
    return f;
}

static const char *const pc_cols[] = {"x1", "y1", "z1", "x2", "y2", "z2", "s",
                                      "dx1", "dy1", "dz1", "dx2", "dy2", "dz2", "ds"};

static void write_headers(run *r)
{
    int ph = r->o->physical;
    if (r->fp) {
        fprintf(r->fp, "period,%s,%s,%s,%s,%s", ph ? "t_s" : "tau", ph ? "f_mesh_hz" : "omega",
                ph ? "x_n_um" : "x_n", ph ? "dx_n_m_s" : "dx_n", ph ? "F_N" : "F");
        for (int i = 0; i < 14; i++)
            fprintf(r->fp, ",%s%s", pc_cols[i], ph ? (i < 7 ? "_um" : "_m_s") : "");
        fprintf(r->fp, "%s\n", ph ? ",theta1_rad,theta2_rad" : ",theta1,theta2");
    }
    if (r->fe)
        fprintf(r->fe, "%s,contact,kind,%s\n", ph ? "t_s" : "tau", ph ? "velocity_m_s" : "velocity");
    if (r->ft)
        fprintf(r->ft, "%s\n", ph ? "t_s,f_mesh_hz,x_n_um,dx_n_m_s,F_N,theta1_rad,theta2_rad"
                                 : "tau,omega,x_n,dx_n,F,theta1,theta2");
}

/* Scale factors for physical output. */
static double sc_t(const run *r) { return r->o->physical ? 1.0 / r->sc->scale.omega_n_rad_s : 1.0; }
static double sc_w(const run *r) { return r->o->physical ? r->sc->scale.omega_n_rad_s / TWO_PI : 1.0; }
static double sc_x(const run *r) { return r->o->physical ? r->sc->scale.length_m * 1e6 : 1.0; }
static double sc_v(const run *r)
{
    return r->o->physical ? r->sc->scale.length_m * r->sc->scale.omega_n_rad_s : 1.0;
}
static double sc_f(const run *r)
{
    return r->o->physical ? r->sc->scale.mesh_stiffness_N_m * r->sc->scale.length_m : 1.0;
}

static void on_section(void *ctx, const wg_section *sec)
{
    run *r = ctx;
    if ((long)sec->stats.period < r->o->transient)
        return;
    r->recorded++;
    r->motion[sec->stats.motion]++;
    r->impacts += sec->stats.impacts;
    r->min_xn = fmin(r->min_xn, sec->stats.min_xn);
    r->max_xn = fmax(r->max_xn, sec->stats.max_xn);
    if (!r->fp)
        return;
    /* printed form: report th1 + th2 as s (the mesh's torsional coordinate) */
    double y[14];
    int printed = r->sc->model == WG_MODEL_PRINTED;
    for (int i = 0; i < 6; i++) {
        y[i] = sec->y[i];
        y[7 + i] = sec->y[(printed ? 8 : 7) + i];
    }
    y[6] = printed ? sec->y[6] + sec->y[7] : sec->y[6];
    y[13] = printed ? sec->y[14] + sec->y[15] : sec->y[13];
    fprintf(r->fp, "%llu,%.15g,%.15g,%.15g,%.15g,%.15g", (unsigned long long)sec->stats.period + 1,
            sec->tau * sc_t(r), sec->omega * sc_w(r), sec->out.xn * sc_x(r), sec->out.dxn * sc_v(r),
            sec->out.F * sc_f(r));
    for (int i = 0; i < 14; i++)
        fprintf(r->fp, ",%.15g", y[i] * (i < 7 ? sc_x(r) : sc_v(r)));
    double th[2]; /* at the section psi = 0, after period + 1 whole periods */
    wg_angles(r->sc->model, &r->sc->p, sec->stats.period + 1, 0.0, sec->y, th);
    fprintf(r->fp, ",%.15g,%.15g\n", th[0], th[1]);
}

static void on_event(void *ctx, const wg_event *ev)
{
    run *r = ctx;
    if ((long)ev->period < r->o->transient || !r->fe)
        return;
    fprintf(r->fe, "%.15g,%s,%s,%.15g\n", ev->tau * sc_t(r), wg_contact_name(ev->contact),
            wg_event_name(ev->kind), ev->velocity * sc_v(r));
}

static void on_step(void *ctx, const wg_sim *s)
{
    run *r = ctx;
    if ((long)s->period < r->o->transient)
        return;
    wg_outputs o;
    double th[2];
    wg_sim_outputs(s, &o);
    wg_sim_angles(s, th);
    fprintf(r->ft, "%.15g,%.15g,%.15g,%.15g,%.15g,%.15g,%.15g\n", s->tau * sc_t(r),
            s->p.v[WG_P_OMEGA] * sc_w(r), o.xn * sc_x(r), o.dxn * sc_v(r), o.F * sc_f(r), th[0],
            th[1]);
}

static void summary(const run *r, const wg_sim *s, double wall)
{
    const wg_scene *sc = r->sc;
    const double *v = s->p.v;
    char kn[64];
    double wn = sc->scale.omega_n_rad_s;
    printf("scene       %s (%s%s)\n", sc->name, sc->physical ? "physical units" : "dimensionless",
           sc->description[0] ? "" : "");
    if (sc->description[0])
        printf("            %s\n", sc->description);
    printf("model       %s, kernel %s (%s), stepper %s\n", wg_model_name(s->cfg.model),
           wg_sim_kernel_name(s, kn, sizeof kn), wg_sim_isa_name(s),
           wg_stepper_name(s->cfg.stepper));
    printf("scale       omega_n = %.6g rad/s, m_e = %.6g kg, b_c = %.3g m, K_m = %.6g N/m\n", wn,
           sc->scale.me_kg, sc->scale.length_m, sc->scale.mesh_stiffness_N_m);
    printf("geometry    a1 = %.6g, a2 = %.6g, a3 = %.6g, mu1 = %.6g, mu2 = %.6g\n", v[WG_P_A1],
           v[WG_P_A2], v[WG_P_A3], v[WG_P_MU1], v[WG_P_MU2]);
    printf("excitation  omega = %.6g (mesh %.6g Hz), xi_p = %.6g\n", v[WG_P_OMEGA],
           v[WG_P_OMEGA] * wn / TWO_PI, v[WG_P_XI_P]);
    char lim[96]; /* the printed form has no limit: its unstable modes grow by design */
    if (s->hmax > 0)
        snprintf(lim, sizeof lim, "RK4 limit N >= %d", wg_min_steps(s->hmax, v[WG_P_OMEGA]));
    else
        snprintf(lim, sizeof lim, "no RK4 limit checked (the printed form grows by design)");
    printf("steps       N = %d per period, h = %.6g, %s; %llu steps, %llu periods\n",
           s->cfg.steps_per_period, s->h, lim, (unsigned long long)s->steps,
           (unsigned long long)s->period);
    printf("time        wall %.3f s, %.4g steps/s, %.1f ns/step, simulated %.6g s physical\n", wall,
           s->steps / wall, 1e9 * wall / (double)s->steps, s->tau / wn);
    if (r->recorded) {
        int cls = r->motion[2] ? 2 : r->motion[1] ? 1 : 0;
        printf("motion      %s (periods: %ld no impact, %ld single-sided, %ld double-sided)\n",
               wg_motion_name(cls), r->motion[0], r->motion[1], r->motion[2]);
        printf("impacts     %.4g per period over %ld periods\n", (double)r->impacts / r->recorded,
               r->recorded);
        printf("x_n         min %.6g, max %.6g (b = %g)\n", r->min_xn, r->max_xn, v[WG_P_B]);
    }
    if (s->cfg.stepper == WG_STEPPER_RK4_EVENT)
        printf("splits      %llu located crossings\n", (unsigned long long)s->nsplit);
}

/* The scene with the command line's --set, --model and --stepper, and a
 * sim at its initial state. 0, or the exit code (the message printed). */
static int setup(opts *o, wg_scene *sc, wg_sim *sim)
{
    char why[640];
    int rc;
    if ((rc = wg_scene_open(sc, o->scene, why, sizeof why))) {
        fprintf(stderr, "wgsim: %s\n", why);
        return 2; /* a --scene that cannot be run, by name or path: as wgsweep and wgcont */
    }
    if (wg_scene_apply_sets(sc, o->sets, o->nsets, why, sizeof why))
        return cli_usage_error(PROG, "--set %s", why);
    if (o->model >= 0 && o->model != sc->model && sc->has_state) /* its values were read */
        return cli_usage_error(PROG, "--model %s: scene %s gives its start state (state = "
                               "given) for the %s model, %d values; use a scene that starts "
                               "at its equilibrium, or one given for the %s model",
                               wg_model_name(o->model), sc->name, wg_model_name(sc->model),
                               wg_model_nstate(sc->model), wg_model_name(o->model));
    if (o->model >= 0)
        sc->model = o->model;
    if (wg_stepper_choose(sc->model, o->stepper, &o->stepper, why, sizeof why)) {
        fprintf(stderr, "wgsim: --stepper %s: %s\n", wg_stepper_name(o->stepper), why);
        return 2;
    }
    wg_sim_config cfg = {sc->model, o->stepper, o->steps};
    if ((rc = wg_sim_init(sim, &sc->p, &cfg, why, sizeof why))) {
        if (rc == WG_ESTABILITY) /* the library's message names N, not the option */
            fprintf(stderr, "wgsim: %s; --steps-per-period sets N (%d..%d)\n", why, WG_STEPS_MIN,
                    WG_STEPS_MAX);
        else
            fprintf(stderr, "wgsim: %s\n", why);
        return rc == WG_ESTABILITY || rc == WG_ERANGE ? 2 : 1;
    }
    double y[WG_NSTATE_MAX];
    wg_scene_initial(sc, y);
    wg_sim_set_state(sim, y, 0, 0.0);
    return 0;
}

/* Open the CSV files asked for and write their headers: 0, or -1. */
static int open_outputs(run *r)
{
    const opts *o = r->o;
    r->fp = open_out(o->poincare);
    r->fe = open_out(o->events);
    r->ft = open_out(o->trace);
    if ((o->poincare && !r->fp) || (o->events && !r->fe) || (o->trace && !r->ft))
        return -1;
    write_headers(r);
    return 0;
}

/* Close the outputs, each checked: a full disk or a closed pipe lost rows
 * while wgsim said nothing and exited 0. 0, or -1 after one line per file
 * that failed, saying why. */
static int close_outputs(run *r)
{
    FILE *fs[3] = {r->fp, r->fe, r->ft};
    const char *path[3] = {r->o->poincare, r->o->events, r->o->trace};
    int bad = 0;
    for (int i = 0; i < 3; i++) {
        if (!fs[i])
            continue;
        int err = ferror(fs[i]);
        errno = 0;
        err |= fs[i] == stdout ? fflush(fs[i]) != 0 : fclose(fs[i]) != 0;
        if (err) {
            fprintf(stderr, "wgsim: writing %s failed%s%s: the file is incomplete\n",
                    strcmp(path[i], "-") ? path[i] : "stdout", errno ? ": " : "",
                    errno ? strerror(errno) : "");
            bad = 1;
        }
    }
    return bad ? -1 : 0;
}

/* Steps per wg_sim_run call: whole periods (N <= 65536: one at least),
 * about 2^16 steps, a millisecond or so (tens with --trace), so that a stop
 * asked for is seen soon and falls at a period's end. The pieces take the
 * same steps to the bit as one call would (wg_sim_run resumes the run). */
static uint64_t chunk_steps(int steps) { return (uint64_t)(65536 / steps) * (uint64_t)steps; }

/* What to try after a blow-up: more steps, except for the printed form,
 * which grows at any step (README: "The model, and why it is not the
 * paper's equations as printed"). */
static const char *blowup_advice(const wg_sim *sim)
{
    if (sim->cfg.model != WG_MODEL_PRINTED)
        return "Try more --steps-per-period.";
    return "The printed equations (--model printed) are not energy-consistent (their theta1 "
           "coupling is anti-restoring: the mesh force does net work) and grow at any "
           "--steps-per-period: twice the steps blowing up at about the same tau is the model, "
           "not the step; --model consistent is the energy-consistent form (README: \"The "
           "model, and why it is not the paper's equations as printed\").";
}

/* Run the transient and the recorded periods into r's sinks, a chunk at a
 * time, until they are done, the state blows up (reported) or a stop is
 * asked for (*stopped 1); the wall time in *wall. WG_OK, or the code of a
 * blow-up. */
static int run_periods(run *r, wg_sim *sim, double *wall, int *stopped)
{
    const opts *o = r->o;
    wg_sink sink = {r, r->ft ? on_step : NULL, on_section, r->fe ? on_event : NULL};
    uint64_t n = ((uint64_t)o->periods + (uint64_t)o->transient) * (uint64_t)o->steps, done = 0;
    uint64_t chunk = chunk_steps(o->steps);
    double t0 = cli_mono_s();
    int rc = WG_OK;
    while (rc == WG_OK && done < n && !g_stop) {
        uint64_t took = 0;
        rc = wg_sim_run(sim, n - done < chunk ? n - done : chunk, &sink, &took);
        done += took;
    }
    *wall = cli_mono_s() - t0;
    *stopped = rc == WG_OK && done < n;
    if (rc)
        fprintf(stderr, "wgsim: step %llu (tau = %.9g): %s: the state blew up; the last good "
                        "state is kept. %s\n",
                (unsigned long long)done, sim->tau, wg_status_str(rc), blowup_advice(sim));
    return rc;
}

/* The one line of a run stopped by a signal, after its files are closed. */
static void say_stopped(const run *r, const wg_sim *sim)
{
    const opts *o = r->o;
    fprintf(stderr, "wgsim: interrupted after %llu of %llu periods (%ld recorded after a "
                    "transient of %d); every row written is whole\n",
            (unsigned long long)sim->period,
            (unsigned long long)o->periods + (unsigned long long)o->transient, r->recorded,
            o->transient);
}

int main(int argc, char **argv)
{
    opts o;
    wg_scene sc;
    wg_sim sim;
    int rc = parse_opts(argc, argv, &o);
    if (rc || (rc = setup(&o, &sc, &sim)))
        return rc;
    run r = {.o = &o, .sc = &sc, .min_xn = INFINITY, .max_xn = -INFINITY};
    double wall = 0.0;
    int stopped = 0;
    /* restart: a row blocked on a full pipe is written, not dropped */
    cli_on_stop_signals_restart(on_signal);
    if (open_outputs(&r) == 0) {
        rc = run_periods(&r, &sim, &wall, &stopped);
        if (!o.poincare && !o.events && !o.trace)
            summary(&r, &sim, wall);
    } else {
        rc = 1;
    }
    if (close_outputs(&r) && !rc)
        rc = 1;
    if (stopped)
        say_stopped(&r, &sim);
    wg_sim_fini(&sim);
    return cli_stdout_close(PROG, stopped ? 130 : rc ? 1 : 0);
}

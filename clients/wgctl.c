/* wgctl - control wormgeard from the shell over LCM.
 * Exit 0 accepted, 1 refused or no answer, 2 usage error. */
#include "bus.h"
#include "bus_msg.h"
#include "cli.h"
#include "ctl_tick.h"
#include "units.h"

#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "wormgear/wg_sim.h"
#include "wormgear/wg_key.h"
#include "wormgear/wg_param.h"

#include <float.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

typedef struct opts {
    const char *url, *prefix, *key_file;
    double timeout_s;
    int json;
    double over;         /* ramp duration */
    const char *unit;    /* "s" or "tau" */
    int have_over;
    int reset_params;
    int at_section;      /* set: apply at the next Poincare section */
    int wait;            /* tick: watch STATUS for what came of it */
} opts;

typedef struct ctl {
    bus c;
    opts o;
    wormgear_params_t *params; /* copy of the PARAMS answering a get */
    wormgear_status_t *status;
    const char *want[WG_NPARAM]; /* get NAME...: the parameters asked for */
    int nwant;
} ctl;

static void usage(FILE *f)
{
    fprintf(f,
            "usage: wgctl [options] COMMAND [ARGS]\n"
            "Control a running wormgeard over LCM; waits for the daemon's ACK.\n\n"
            "Commands:\n"
            "  set NAME=VALUE...          change parameters atomically (all or none)\n"
            "                             (--at-section: at the next Poincare section, psi = 0)\n"
            "  ramp NAME [FROM] TO --over DURATION\n"
            "                             ramp a parameter phase-continuously; DURATION is\n"
            "                             simulated time: 60s, 250ms, 2min, or 5000tau\n"
            "                             (a bare number is seconds)\n"
            "  pause | resume             stop / continue the simulation (resume clears a fault)\n"
            "  reset [--params]           back to the scene's initial state (and parameters)\n"
            "  step N                     advance N RK4 steps (lockstep mode, or paused)\n"
            "  tick N [--wait]            one TICK owing N RK4 steps (lockstep; signed with a\n"
            "                             key). A tick taken has no answer: --wait watches\n"
            "                             STATUS until the steps ran (exit 0), or ACK for its\n"
            "                             refusal, or STATUS for it lapsing (not lockstep,\n"
            "                             paused): exit 1, saying why\n"
            "  mode realtime|fast|lockstep [RATE]\n"
            "                             change pacing (RATE: realtime factor, 1 = physical)\n"
            "  contacts all|mesh|none [N] which contact events the daemon publishes on CONTACT:\n"
            "                             all (N: 1 in N of each bearing's), the mesh's, none\n"
            "  save NAME | restore NAME   full state to/from NAME.wgstate in the state dir\n"
            "  get [NAME...]              the current parameters (or those named): value, unit\n"
            "                             (- for dimensionless) and the physical equivalent\n"
            "                             (omega in Hz, lengths in µm, loads in N, ...)\n"
            "  params                     every parameter: name, unit, range, default, help\n"
            "                             and how it maps to physical units (no daemon needed)\n"
            "  status                     one STATUS message, readable\n"
            "  keygen FILE                a new key for signed commands (mode 0600; the\n"
            "                             daemon's command_key_file, clients' --key-file)\n\n"
            "Options:\n"
            "  --url URL        LCM URL (default $WORMGEAR_URL or %s)\n"
            "  --prefix P       channel prefix (default $WORMGEAR_PREFIX or %s)\n"
            "  --timeout SEC    wait this long for the answer (default 3 s)\n"
            "  --over DURATION  ramp duration (see ramp)\n"
            "  --params         reset: the scene's parameters too\n"
            "  --at-section     set: apply at the next Poincare section (psi = 0), not\n"
            "                   mid-period; the answer comes then, with that section's tau\n"
            "  --wait           tick: wait for the steps to run (see tick; --timeout)\n"
            "  --json           machine-readable output on stdout\n"
            "  --key-file FILE  sign commands with this key (default $WORMGEAR_KEY_FILE;\n"
            "                   needed when the daemon has command_key_file)\n"
            "  -h, --help       this text\n\n"
            "Exit status: 0 accepted (tick: sent; with --wait: run), 1 refused or no answer\n"
            "(or no bus), 2 usage error (an LCM URL LCM refuses too).\n",
            BUS_DEFAULT_URL, BUS_DEFAULT_PREFIX);
}

#define PROG "wgctl"

/* Options may appear anywhere; everything else (negative numbers too) is
 * positional and collected into pos. */
static int option(opts *o, const char *name, const char *val, int *used)
{
    static const char *const withval[] = {"url", "prefix", "timeout", "over", "key-file"};
    *used = 0;
    for (unsigned i = 0; i < sizeof withval / sizeof withval[0]; i++)
        if (strcmp(name, withval[i]) == 0) {
            if (!val)
                return cli_usage_error(PROG, "option --%s needs a value", name);
            *used = 1;
        }
    if (!strcmp(name, "url")) o->url = val;
    else if (!strcmp(name, "key-file")) o->key_file = val;
    else if (!strcmp(name, "prefix")) o->prefix = val;
    else if (!strcmp(name, "timeout")) {
        if (cli_num(val, DBL_TRUE_MIN, 86400, &o->timeout_s))
            return cli_usage_error(PROG, "--timeout '%s': seconds in (0, 86400]", val);
    } else if (!strcmp(name, "over")) {
        if (cli_duration(val, &o->over, &o->unit) || !(o->over > 0))
            return cli_usage_error(PROG, "--over '%s': a positive duration like 60s, 250ms, "
                                         "2min, 5000tau", val);
        o->have_over = 1;
    } else if (!strcmp(name, "params")) o->reset_params = 1;
    else if (!strcmp(name, "at-section")) o->at_section = 1;
    else if (!strcmp(name, "wait")) o->wait = 1;
    else if (!strcmp(name, "json")) o->json = 1;
    else if (!strcmp(name, "help")) { usage(stdout); exit(0); }
    else return cli_usage_error(PROG, "unknown option '--%s'", name);
    return 0;
}

static int parse_opts(int argc, char **argv, opts *o, char **pos, int *npos)
{
    *o = (opts){.timeout_s = 3.0, .unit = "s"};
    *npos = 0;
    for (int i = 1; i < argc; i++) {
        const char *a = argv[i];
        if (!strcmp(a, "-h"))
            a = "--help";
        if (strncmp(a, "--", 2) != 0 || !a[2]) {
            if (strcmp(a, "--") != 0)
                pos[(*npos)++] = argv[i];
            continue;
        }
        char name[32];
        const char *eq = strchr(a, '='), *val = eq ? eq + 1 : (i + 1 < argc ? argv[i + 1] : NULL);
        snprintf(name, sizeof name, "%.*s", (int)(eq ? eq - a - 2 : (long)strlen(a) - 2), a + 2);
        int used, rc = option(o, name, val, &used);
        if (rc)
            return rc;
        if (used && !eq)
            i++;
    }
    return 0;
}

/* ---- answers --------------------------------------------------------------- */

/* The strings of a message as text, in place: whoever sent it chose them,
 * and a terminal would obey an escape among them (cli_text). */
#define CLEAN(s) ((s) ? (void)cli_text((s), strlen(s) + 1, (s)) : (void)0)

static void clean_params(wormgear_params_t *p)
{
    CLEAN(p->scene), CLEAN(p->model), CLEAN(p->stepper);
    for (int i = 0; i < p->n; i++)
        CLEAN(p->name[i]), CLEAN(p->unit[i]);
}

static void clean_status(wormgear_status_t *s)
{
    CLEAN(s->scene), CLEAN(s->mode), CLEAN(s->run), CLEAN(s->health), CLEAN(s->fault);
    CLEAN(s->motion), CLEAN(s->regime), CLEAN(s->tick_refusal);
}

/* Why the silence of a command the daemon answers late (msg_cmd_late) need
 * not mean that no daemon is there. */
static const char *late_answer(const char *what)
{
    if (!strcmp(what, "set"))
        return "a set --at-section is answered at the next Poincare section (psi = 0), which in "
               "lockstep mode comes only with further steps: it may still be pending, to be "
               "applied there (a reset cancels it; --timeout waits longer)";
    return "a step is answered when its steps are done: it may still be running (pause "
           "cancels it; --timeout waits longer)";
}

/* late_cmd: a command the daemon answers late (msg_cmd_late). */
static int report(ctl *t, const char *what, int late_cmd)
{
    bus_ack *a = &t->c.ack;
    if (!a->got) {
        char hint[1024], msg[1280];
        const char *late = late_cmd ? late_answer(what) : NULL;
        if (t->o.json) { /* the same words as on stderr: it said only "no ACK within N s" */
            snprintf(msg, sizeof msg, "no ACK within %g s: %s", t->o.timeout_s,
                     late ? late : bus_hint(&t->c, hint, sizeof hint));
            printf("{\"accepted\":false,\"code\":\"ETIMEDOUT\",\"message\":");
            cli_json_str(stdout, msg);
            printf("}\n");
        }
        if (late)
            fprintf(stderr, "wgctl: %s: no answer within %g s: %s. If no daemon answers at "
                    "all: %s\n", what, t->o.timeout_s, late, bus_hint(&t->c, hint, sizeof hint));
        else
            fprintf(stderr, "wgctl: %s: no answer within %g s: %s\n", what, t->o.timeout_s,
                    bus_hint(&t->c, hint, sizeof hint));
        return 1;
    }
    if (t->o.json) {
        printf("{\"accepted\":%s,\"code\":", a->accepted ? "true" : "false");
        cli_json_str(stdout, a->code);
        printf(",\"status\":%d,\"message\":", a->rc);
        cli_json_str(stdout, a->message);
        printf(",\"tau\":%.17g,\"t_s\":%.17g,\"steps\":%lld,\"seq\":%lld,\"client\":", a->tau,
               a->t_s, (long long)a->steps, (long long)a->cmd_seq);
        cli_json_str(stdout, t->c.client);
        printf("}\n");
    } else if (a->accepted) {
        printf("ok: %s [tau %.9g, t %.6g s]\n", a->message, a->tau, a->t_s);
    }
    if (!a->accepted)
        fprintf(stderr, "wgctl: %s refused (%s): %s\n", what, a->code, a->message);
    return a->accepted ? 0 : 1;
}

static int send_wait(ctl *t, wormgear_cmd_t *cmd)
{
    if (bus_send(&t->c, cmd) < 0) {
        fprintf(stderr, "wgctl: %s not sent: %s\n", cmd->op, t->c.send_why);
        return 1;
    }
    bus_wait_ack(&t->c, (int)(t->o.timeout_s * 1000));
    return report(t, cmd->op, msg_cmd_late(cmd->op, cmd->at_section));
}

/* ---- commands ---------------------------------------------------------------- */

static int do_set(ctl *t, int n, char **args)
{
    char *names[WG_NPARAM + 8];
    double vals[WG_NPARAM + 8];
    if (n < 1 || n > WG_NPARAM)
        return cli_usage_error(PROG, "set needs 1 to %d NAME=VALUE pairs", WG_NPARAM);
    for (int i = 0; i < n; i++) {
        char *eq = strchr(args[i], '=');
        if (!eq || eq == args[i] || cli_double(eq + 1, &vals[i]))
            return cli_usage_error(PROG, "set: '%s' is not NAME=NUMBER", args[i]);
        *eq = 0;
        if (wg_param_lookup(args[i]) < 0) /* the table is ours too: no need to ask */
            return cli_usage_error(PROG, "set: '%s' is not a parameter (wgctl params lists "
                                   "them)", args[i]);
        names[i] = args[i];
    }
    wormgear_cmd_t c = bus_cmd("set");
    c.nparams = n;
    c.names = names;
    c.values = vals;
    c.at_section = (int8_t)t->o.at_section;
    return send_wait(t, &c);
}

static int do_ramp(ctl *t, int n, char **args)
{
    double from = 0, to, d;
    const char *u;
    if (n >= 2 && n <= 4 && cli_double(args[n - 1], &to) && !cli_duration(args[n - 1], &d, &u)) {
        char say[256] = ""; /* the words before it, NAME=TO spelled NAME TO */
        for (int i = 0; i < n - 1; i++) {
            size_t k = strlen(say);
            snprintf(say + k, sizeof say - k, "%s%s", i ? " " : "", args[i]);
        }
        for (char *c = say; (c = strchr(c, '=')) != NULL;)
            *c = ' ';
        return cli_usage_error(PROG, "ramp: '%s' is a duration: give it with --over (wgctl ramp "
                               "%s --over %s)", args[n - 1], say, args[n - 1]);
    }
    if (n == 1 && strchr(args[0], '='))
        return cli_usage_error(PROG, "ramp: expected NAME [FROM] TO --over DURATION, with spaces "
                               "(got '%s')", args[0]);
    if (n < 2 || n > 3)
        return cli_usage_error(PROG, "ramp: expected NAME [FROM] TO --over DURATION");
    if (!t->o.have_over)
        return cli_usage_error(PROG, "ramp: --over DURATION is required (e.g. --over 60s)");
    if (cli_double(args[n - 1], &to) || (n == 3 && cli_double(args[1], &from)))
        return cli_usage_error(PROG, "ramp: FROM and TO must be numbers (got '%s')", args[n - 1]);
    if (wg_param_lookup(args[0]) < 0)
        return cli_usage_error(PROG, "ramp: '%s' is not a parameter (wgctl params lists them)",
                               args[0]);
    wormgear_cmd_t c = bus_cmd("ramp");
    c.nparams = 1;
    c.names = &args[0];
    c.values = &to;
    c.has_from = n == 3;
    c.from = from;
    c.duration = t->o.over;
    c.unit = (char *)t->o.unit;
    return send_wait(t, &c);
}

static int do_step(ctl *t, int n, char **args)
{
    int64_t v;
    if (n != 1 || cli_int64(args[0], 1, INT64_MAX, &v))
        return cli_usage_error(PROG, "step: expected a step count N >= 1");
    wormgear_cmd_t c = bus_cmd("step");
    c.nsteps = v;
    return send_wait(t, &c);
}

/* A TICK is not answered: ctl_tick says what was sent, or with --wait what
 * STATUS showed of it. */
static int do_tick(ctl *t, int n, char **args)
{
    int64_t v;
    if (n != 1 || cli_int64(args[0], 1, 10000000, &v))
        return cli_usage_error(PROG, "tick: expected a step count N in [1, 10000000]");
    return ctl_tick(&t->c, v, t->o.wait, t->o.timeout_s, t->o.json);
}

static int do_named(ctl *t, const char *op, int n, char **args)
{
    if (n != 1)
        return cli_usage_error(PROG, "%s: expected one NAME", op);
    wormgear_cmd_t c = bus_cmd(op);
    c.name = args[0];
    return send_wait(t, &c);
}

/* s is a, b or c (a name the daemon takes: checked before sending). */
static int one_of(const char *s, const char *a, const char *b, const char *c)
{
    return !strcmp(s, a) || !strcmp(s, b) || !strcmp(s, c);
}

/* A usage error saying what was expected and what was given: the first
 * argument, and the second of two ("mode: expected ... (got 'turbo')"). */
static int expected(const char *what, int n, char **args)
{
    if (n < 1)
        return cli_usage_error(PROG, "%s", what);
    return cli_usage_error(PROG, "%s (got '%s%s%s')", what, args[0], n == 2 ? " " : "",
                           n == 2 ? args[1] : "");
}

static int do_mode(ctl *t, int n, char **args)
{
    double rate = 0; /* 0 on the wire: keep the rate; a RATE given: the daemon's range */
    if (n < 1 || n > 2 ||
        (n == 2 && cli_num(args[1], WG_RATE_MIN, WG_RATE_MAX, &rate)) ||
        !one_of(args[0], "realtime", "fast", "lockstep")) {
        char what[96];
        snprintf(what, sizeof what, "mode: expected realtime|fast|lockstep [RATE in [%g, %g]]",
                 WG_RATE_MIN, WG_RATE_MAX);
        return expected(what, n, args);
    }
    wormgear_cmd_t c = bus_cmd("mode");
    c.name = args[0];
    c.rate = rate;
    return send_wait(t, &c);
}

/* contacts all|mesh|none [N]: the daemon checks N's range. */
static int do_contacts(ctl *t, int n, char **args)
{
    int64_t every = 0;
    if (n < 1 || n > 2 || (n == 2 && cli_int64(args[1], 1, INT64_MAX, &every)) ||
        !one_of(args[0], "all", "mesh", "none"))
        return expected("contacts: expected all|mesh|none [N >= 1]", n, args);
    wormgear_cmd_t c = bus_cmd("contacts");
    c.name = args[0];
    c.nsteps = every;
    return send_wait(t, &c);
}

static int do_simple(ctl *t, const char *op, int n)
{
    if (n != 0)
        return cli_usage_error(PROG, "%s takes no arguments", op);
    wormgear_cmd_t c = bus_cmd(op);
    if (!strcmp(op, "reset") && t->o.reset_params)
        c.name = (char *)"params";
    return send_wait(t, &c);
}

static void on_params(const lcm_recv_buf_t *rb, const char *ch, const wormgear_params_t *m,
                      void *u)
{
    (void)ch;
    ctl *t = u;
    if (!t->params && m->cmd_seq == t->c.seq && m->cmd_utime == t->c.cmd_utime &&
        strcmp(m->cmd_client, t->c.client) == 0 &&
        bus_signed(&t->c, BUS_PARAMS, rb)) { /* with a key: the daemon's only */
        t->params = wormgear_params_t_copy(m);
        if (t->params)
            clean_params(t->params);
    }
}

BUS_RAW_HANDLER(on_params_raw, wormgear_params_t, BUS_PARAMS, on_params)

static int get_done(void *u)
{
    ctl *t = u;
    return t->params && t->c.ack.got;
}

/* Is parameter name one that `get NAME...` asked for (all when none)? */
static int wanted(const ctl *t, const char *name)
{
    for (int i = 0; i < t->nwant; i++)
        if (strcmp(t->want[i], name) == 0)
            return 1;
    return t->nwant == 0;
}

/* The message's values as a parameter set (table defaults for any it
 * lacks) and its scale, for the physical equivalents. */
static void params_of(const wormgear_params_t *p, wg_params *v, units_scale *s)
{
    wg_params_default(v);
    for (int i = 0; i < p->n; i++) {
        int id = wg_param_lookup(p->name[i]);
        if (id >= 0)
            v->v[id] = p->value[i];
    }
    *s = (units_scale){p->omega_n_rad_s, p->length_m, p->mesh_stiffness_N_m};
}

static void print_params_json(const ctl *t, const wormgear_params_t *p)
{
    wg_params v;
    units_scale sc;
    params_of(p, &v, &sc);
    printf("{\"scene\":");
    cli_json_str(stdout, p->scene);
    printf(",\"tau\":%.17g,\"omega_n_rad_s\":%.17g,\"length_m\":%.17g,"
           "\"mesh_stiffness_N_m\":%.17g,\"steps_per_period\":%d,\"params\":{",
           p->tau, p->omega_n_rad_s, p->length_m, p->mesh_stiffness_N_m, p->steps_per_period);
    for (int i = 0, k = 0; i < p->n; i++)
        if (wanted(t, p->name[i])) {
            printf("%s", k++ ? "," : "");
            cli_json_str(stdout, p->name[i]);
            printf(":%.17g", p->value[i]);
        }
    printf("},\"physical\":{");
    for (int i = 0, k = 0; i < p->n; i++) {
        double x;
        const char *u;
        if (wanted(t, p->name[i]) && !units_param(wg_param_lookup(p->name[i]), &v, &sc, &x, &u)) {
            printf("%s", k++ ? "," : "");
            cli_json_str(stdout, p->name[i]);
            printf(":{\"value\":%.17g,\"unit\":\"%s\"}", x, u);
        }
    }
    printf("},\"ramp\":%s}\n", p->ramp_active ? "true" : "false");
}

/* One line per parameter: name = value, the unit ("-": dimensionless),
 * and the physical equivalent where there is one. */
static void print_params(const ctl *t, const wormgear_params_t *p)
{
    char num[32];
    wg_params v;
    units_scale sc;
    if (t->o.json)
        return print_params_json(t, p);
    params_of(p, &v, &sc);
    if (!t->nwant) {
        printf("scene %s, model %s, stepper %s, N = %d, tau %.9g (%.6g s)\n", p->scene, p->model,
               p->stepper, p->steps_per_period, p->tau, p->tau / p->omega_n_rad_s);
        printf("scale omega_n = %.6g rad/s, b_c = %.6g µm, K_m = %.6g N/m, m_e = %.6g kg\n",
               p->omega_n_rad_s, p->length_m * 1e6, p->mesh_stiffness_N_m,
               p->mesh_stiffness_N_m / (p->omega_n_rad_s * p->omega_n_rad_s));
    }
    for (int i = 0; i < p->n; i++) {
        double x;
        const char *u;
        if (!wanted(t, p->name[i]))
            continue;
        const char *shown = wg_unit_shown(p->unit[i]);
        printf("  %-5s = %-19s", p->name[i], wg_num_format(p->value[i], num, sizeof num));
        if (!units_param(wg_param_lookup(p->name[i]), &v, &sc, &x, &u))
            printf(" %-3s  %.6g %s\n", shown, x, u);
        else
            printf(" %s\n", shown);
    }
    if (p->ramp_active && !t->nwant)
        printf("ramp: %s %.9g -> %.9g over %.9g tau from tau %.9g\n", p->ramp_param, p->ramp_from,
               p->ramp_to, p->ramp_duration_tau, p->ramp_tau0);
}

static int do_get(ctl *t)
{
    lcm_subscription_t *s = bus_subscribe(&t->c, "PARAMS", on_params_raw, t, 0);
    wormgear_cmd_t c = bus_cmd("get");
    if (bus_send(&t->c, &c) < 0) {
        fprintf(stderr, "wgctl: get not sent: %s\n", t->c.send_why);
        return 1;
    }
    bus_wait(&t->c, (int)(t->o.timeout_s * 1000), get_done, t);
    int rc = 1;
    if (t->params && t->c.ack.got && t->c.ack.accepted) {
        print_params(t, t->params);
        rc = 0;
    } else if ((rc = report(t, "get", 0)) == 0) {
        fprintf(stderr, "wgctl: get: the PARAMS answer did not arrive\n");
        rc = 1;
    }
    if (t->params)
        wormgear_params_t_destroy(t->params);
    lcm_unsubscribe(t->c.lcm, s);
    return rc;
}

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const wormgear_status_t *m,
                      void *u)
{
    (void)ch;
    ctl *t = u;
    if (!t->status && bus_signed(&t->c, BUS_STATUS, rb)) { /* with a key: the daemon's only */
        t->status = wormgear_status_t_copy(m);
        if (t->status)
            clean_status(t->status);
    }
}

BUS_RAW_HANDLER(on_status_raw, wormgear_status_t, BUS_STATUS, on_status)

static int status_done(void *u) { return ((ctl *)u)->status != NULL; }

static void print_status(const ctl *t, const wormgear_status_t *s)
{
    if (t->o.json) {
        printf("{\"scene\":");
        cli_json_str(stdout, s->scene);
        printf(",\"mode\":");
        cli_json_str(stdout, s->mode);
        printf(",\"rate\":%.17g,\"run\":", s->rate);
        cli_json_str(stdout, s->run);
        printf(",\"health\":");
        cli_json_str(stdout, s->health);
        printf(",\"fault\":");
        cli_json_str(stdout, s->fault);
        printf(",\"tau\":%.17g,\"t_s\":%.17g,\"omega\":%.17g,\"steps\":%lld,\"period\":%lld,"
               "\"rtf\":%.6g,\"lag_s\":%.6g,\"overruns\":%lld,\"loop_mean_us\":%.6g,"
               "\"loop_max_us\":%.6g,\"steps_per_s\":%.6g,\"cpu_share\":%.6g,"
               "\"msgs_dropped\":%lld,\"cmds_accepted\":%lld,\"cmds_refused\":%lld,"
               "\"motion\":",
               s->tau, s->t_s, s->omega, (long long)s->steps, (long long)s->period, s->rtf,
               s->lag_s, (long long)s->overruns, s->loop_mean_us, s->loop_max_us,
               s->steps_per_s, s->cpu_share, (long long)s->msgs_dropped,
               (long long)s->cmds_accepted, (long long)s->cmds_refused);
        cli_json_str(stdout, s->motion);
        printf(",\"impacts_per_period\":%.6g,\"regime\":", s->impacts_per_period);
        cli_json_str(stdout, s->regime);
        printf(",\"ticks_refused\":%lld,\"tick_refusal\":", (long long)s->ticks_refused);
        cli_json_str(stdout, s->tick_refusal);
        printf(",\"ticks_lost\":%lld,\"seq\":%lld}\n", (long long)s->ticks_lost,
               (long long)s->seq);
        return;
    }
    printf("scene %s, mode %s (rate %g), %s, health %s%s%s\n", s->scene, s->mode, s->rate,
           s->run, s->health, s->fault[0] ? ": " : "", s->fault);
    printf("time      t = %.6f s, tau = %.9g, step %lld, period %lld (N = %d)\n", s->t_s, s->tau,
           (long long)s->steps, (long long)s->period, s->steps_per_period);
    printf("omega     %.9g\n", s->omega); /* "(ramping)" was here for a ramp of any
                                                  parameter: STATUS does not say which */
    if (s->ramp_active)
        printf("ramp      a parameter is ramping (wgctl get names it)\n");
    printf("pace      real-time factor %.4f, lag %.3f ms, overruns %lld\n", s->rtf,
           s->lag_s * 1e3, (long long)s->overruns);
    printf("load      %.4g steps/s, cpu %.1f%%, loop %.1f us mean / %.1f us max\n",
           s->steps_per_s, s->cpu_share * 100, s->loop_mean_us, s->loop_max_us);
    printf("motion    %s, %.3g impacts per period, regime %s\n", s->motion,
           s->impacts_per_period, s->regime);
    printf("messages  %lld not published; commands %lld accepted, %lld refused; up %.1f s\n",
           (long long)s->msgs_dropped, (long long)s->cmds_accepted, (long long)s->cmds_refused,
           s->uptime_s);
    if (s->ticks_lost) /* gaps in the seq of the ticks the daemon took */
        printf("ticks     %lld lost on the way (gaps in their seq)\n", (long long)s->ticks_lost);
    if (s->ticks_refused) /* refused ticks: their ACKs went to their senders */
        printf("ticks     %lld refused; the last: %s\n", (long long)s->ticks_refused,
               s->tick_refusal);
}

static int do_status(ctl *t)
{
    lcm_subscription_t *s = bus_subscribe(&t->c, "STATUS", on_status_raw, t, 0);
    bus_wait(&t->c, (int)(t->o.timeout_s * 1000), status_done, t);
    lcm_unsubscribe(t->c.lcm, s);
    if (!t->status) {
        char hint[512];
        fprintf(stderr, "wgctl: status: no STATUS on %sSTATUS within %g s: %s\n", t->c.prefix,
                t->o.timeout_s, bus_hint(&t->c, hint, sizeof hint));
        return 1;
    }
    print_status(t, t->status);
    wormgear_status_t_destroy(t->status);
    return 0;
}

static int do_params(const ctl *t)
{
    if (!t->o.json)
        printf("%-5s %-4s %-19s %-9s %s\n", "name", "unit", "range", "default",
               "meaning (- : dimensionless); physical: its equivalent, as wgctl get shows it");
    for (int i = 0; i < WG_NPARAM; i++) {
        const wg_param_info *r = wg_param_info_get(i);
        if (t->o.json) {
            printf("%s{\"name\":\"%s\",\"unit\":\"%s\",\"min\":%.17g,\"max\":%.17g,"
                   "\"default\":%.17g,\"rampable\":%s,\"help\":", i ? "," : "[", r->name, r->unit,
                   r->min, r->max, r->def, r->flags & WG_PF_RAMP ? "true" : "false");
            cli_json_str(stdout, r->help);
            printf("}%s", i == WG_NPARAM - 1 ? "]\n" : "\n");
        } else {
            char range[48];
            const char *rule = units_param_rule(i);
            wg_range_shown(r->min, r->max, range, sizeof range); /* accepted as shown */
            printf("%-5s %-4s %-19s %-9.6g %s%s%s%s\n", r->name, wg_unit_shown(r->unit), range,
                   r->def, r->help,
                   r->flags & WG_PF_RAMP ? " (rampable)" : "", *rule ? "; physical: " : "", rule);
        }
    }
    return 0;
}

/* A new random key in a new file (never over an existing one). */
static int do_keygen(const char *path)
{
    char why[600];
    if (wg_key_create(path, why, sizeof why)) {
        fprintf(stderr, "wgctl: %s\n", why);
        return 1;
    }
    printf("wrote a new key to %s (mode 0600): give it to wormgeard (command_key_file) and to "
           "each client that sends commands (--key-file or $WORMGEAR_KEY_FILE)\n", path);
    return 0;
}

/* get NAME...: every name must be a parameter of the table. */
static int get_names(ctl *t, int n, char **args)
{
    if (n > WG_NPARAM)
        return cli_usage_error(PROG, "get: at most %d names", WG_NPARAM);
    for (int i = 0; i < n; i++) {
        if (wg_param_lookup(args[i]) < 0)
            return cli_usage_error(PROG, "get: '%s' is not a parameter (wgctl params lists "
                                         "them)", args[i]);
        t->want[i] = args[i];
    }
    t->nwant = n;
    return 0;
}

static int dispatch(ctl *t, const char *cmd, int n, char **args)
{
    if (t->o.at_section && strcmp(cmd, "set"))
        return cli_usage_error(PROG, "--at-section applies to set only, not to %s", cmd);
    if (!strcmp(cmd, "set")) return do_set(t, n, args);
    if (!strcmp(cmd, "ramp")) return do_ramp(t, n, args);
    if (!strcmp(cmd, "step")) return do_step(t, n, args);
    if (!strcmp(cmd, "tick")) return do_tick(t, n, args);
    if (!strcmp(cmd, "save") || !strcmp(cmd, "restore")) return do_named(t, cmd, n, args);
    if (!strcmp(cmd, "mode")) return do_mode(t, n, args);
    if (!strcmp(cmd, "contacts")) return do_contacts(t, n, args);
    if (!strcmp(cmd, "pause") || !strcmp(cmd, "resume") || !strcmp(cmd, "reset"))
        return do_simple(t, cmd, n);
    if (!strcmp(cmd, "get"))
        return get_names(t, n, args) ? CLI_EUSAGE : do_get(t);
    if (!strcmp(cmd, "status"))
        return n ? cli_usage_error(PROG, "status takes no arguments") : do_status(t);
    return cli_usage_error(PROG, "unknown command '%s'", cmd);
}

/* With --json, a run that ends before anything was sent (a usage error,
 * the bus not opened) still writes one object on stdout, as a timeout
 * does: it wrote nothing there. The reason is on stderr. */
static int json_end(int argc, char **argv, int rc, const char *code)
{
    for (int i = 1; i < argc; i++)
        if (!strcmp(argv[i], "--json")) {
            printf("{\"accepted\":false,\"code\":\"%s\",\"message\":\"%s (see stderr)\"}\n",
                   code, rc == CLI_EUSAGE ? "usage error" : "not sent");
            break;
        }
    return rc;
}

static int run(ctl *t, int argc, char **argv)
{
    char *pos[256], why[256];
    int npos;
    if (argc > 256)
        return cli_usage_error(PROG, "too many arguments");
    int rc = parse_opts(argc, argv, &t->o, pos, &npos);
    if (rc)
        return rc;
    if (npos == 0)
        return cli_usage_error(PROG, "no command given");
    if (!strcmp(pos[0], "params"))
        return npos > 1 ? cli_usage_error(PROG, "params takes no arguments") : do_params(t);
    if (!strcmp(pos[0], "keygen"))
        return npos != 2 ? cli_usage_error(PROG, "keygen: expected one FILE") : do_keygen(pos[1]);
    static const char *const known[] = {"set", "ramp", "step", "tick", "save", "restore", "mode",
                                        "pause", "resume", "reset", "get", "status", "contacts"};
    unsigned k = 0;
    while (k < sizeof known / sizeof known[0] && strcmp(known[k], pos[0]))
        k++;
    if (k == sizeof known / sizeof known[0] && !strcmp(pos[0], "help") && npos == 1)
        return usage(stdout), 0;
    if (k == sizeof known / sizeof known[0]) {
        char list[160] = "";
        for (unsigned i = 0; i < sizeof known / sizeof known[0]; i++) {
            size_t l = strlen(list);
            snprintf(list + l, sizeof list - l, "%s, ", known[i]);
        }
        return cli_usage_error(PROG, "unknown command '%s' (one of: %sparams, keygen)", pos[0],
                               list);
    }
    if (t->o.prefix && !bus_prefix_ok(t->o.prefix))
        return cli_usage_error(PROG, "--prefix '%.60s': need [A-Za-z0-9_.-], at most %d "
                               "characters (the daemon's rule)", t->o.prefix, BUS_PREFIX_MAX);
    if (t->o.url && !*t->o.url)
        return cli_usage_error(PROG, "--url '': need an LCM URL (e.g. %s)", bus_default_url());
    int brc = bus_open(&t->c, t->o.url, t->o.prefix, "wgctl", why, sizeof why);
    if (brc || (t->o.key_file && bus_set_key(&t->c, t->o.key_file, why, sizeof why))) {
        fprintf(stderr, "wgctl: %s\n", why);
        bus_close(&t->c);
        return json_end(argc, argv, bus_exit_status(brc), brc == BUS_EURL ? "EUSAGE" : "EBUS");
    }
    rc = dispatch(t, pos[0], npos - 1, pos + 1);
    bus_close(&t->c);
    return rc;
}

int main(int argc, char **argv)
{
    static ctl t;
    int rc = run(&t, argc, argv);
    return cli_stdout_close(PROG, rc == CLI_EUSAGE ? json_end(argc, argv, rc, "EUSAGE") : rc);
}

/* wgmon - live terminal dashboard of wormgeard (plain ANSI, works over ssh).
 * Subscribes to STATUS, PARAMS, STATE, POINCARE and CONTACT and redraws a
 * frame a few times a second: pacing health, the key parameters, the x_n
 * trace over a window of mesh periods with a time axis (mon_view.c:
 * scrolling, or stroboscopic when STATE has too few samples per period),
 * the Poincare scatter of the last seconds, impacts per period, motion
 * class and regime (the daemon's, and a local period detection), and
 * dropped-message counts from seq gaps; senders told apart (bus.h: a
 * restart, a replay, the live one of several). --once / --frames N print
 * plain text. Exit 0, 1 no STATUS heard (--once, --frames), 2 usage. */
#include "bus.h"
#include "bus_msg.h"
#include "cli.h"
#include "mon_term.h"
#include "mon_text.h"
#include "mon_view.h"

#include "lcmtypes/wormgear_contact_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "wormgear/wg_model.h"
#include "wormgear/wg_regime.h"
#include "wormgear/wg_writer.h"

#include <errno.h>
#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/select.h>
#include <unistd.h>

enum { TR_CAP = 1 << 17, PC_CAP = 1 << 15, NKEY = 8 };
/* The frames' queue: a frame is queued only when the last is written (an
 * empty queue takes one of any size), so this bounds only the closing
 * escapes behind it. */
enum { OUT_QUEUE = 1 << 16 };
enum { CH_STATUS, CH_PARAMS, CH_STATE, CH_POINCARE, CH_CONTACT, NCH };
static const char *const ch_suffix[NCH] = {"STATUS", "PARAMS", "STATE", "POINCARE", "CONTACT"};
static const char *const key_names[NKEY] = {"omega", "xi_p", "f_m", "f_e", "k_a", "e_m", "b", "b_j"};

static volatile sig_atomic_t g_quit, g_winch; /* set by signal handlers only */

typedef struct opts {
    const char *url, *prefix;
    double window_s, fps, timeout_s, tol;
    int periods;      /* the trace's window, mesh periods */
    int frames;       /* 0: interactive until q */
    int plain;        /* no escape sequences */
    int cols, rows;   /* 0: from the terminal */
} opts;

typedef struct seqc {      /* per-channel counters */
    bus_streams seq;      /* its senders; .missing: messages dropped */
    int64_t count, bad, unverified; /* undecodable; with a key, not signed or old */
    int64_t ignored;      /* messages of a sender not shown */
} seqc;

typedef struct status_copy {
    char scene[64], mode[16], run[16], health[16], fault[160], motion[24], regime[32];
    char tick_refusal[200];
    double rate, tau, t_s, omega, rtf, lag_s, loop_mean_us, loop_max_us, steps_per_s, cpu;
    double imp_pp, uptime_s;
    int64_t period, overruns, dropped, acc, ref, ticks_refused, ticks_lost;
    int N, ramp;
} status_copy;

typedef struct mon {
    bus c;
    opts o;
    seqc sc[NCH];
    void *subs[NCH];
    int have_status, have_params;
    double follow_off;            /* the shown sender's clock offset (s) */
    int64_t follow_sender;        /* its id, when messages carry one */
    int following;                /* a STATUS chose the sender to show */
    double status_at;             /* wall seconds (monotonic) of the last STATUS */
    status_copy st;
    double key[NKEY];
    int has_key[NKEY];
    char stepper[16], ramp_param[16];
    double omega_n_rad_s, length_m; /* the scale, from PARAMS */
    double ramp_from, ramp_to, ramp_tau0, ramp_dur;
    int ramp_active;
    mon_trace tr;                 /* STATE samples */
    double theta1, theta2;        /* worm and wheel angles of the latest sample, rad */
    int have_theta;
    mon_sections pc;              /* POINCARE sections */
    double since;                 /* monotonic s the rings began to fill */
    wg_tracker trk;               /* last consecutive sections: the local period */
    long contacts[WG_NCONTACT][WG_NEVKIND]; /* CONTACT events in the session */
    int rows, cols, frozen;
    int tight;                    /* under 30 rows: the details that leave the plots room go */
    mon_term term;                /* raw keys, the alternate screen */
    wg_writer *out;               /* the frames' writer: a stalled terminal never stops the loop */
    int stalled;                  /* at the end, the terminal still took nothing */
} mon;

/* ---- options --------------------------------------------------------------- */

static void usage(FILE *f)
{
    fprintf(f,
            "usage: wgmon [options]\n"
            "Live dashboard of a running wormgeard: pacing, parameters, x_n trace, Poincare\n"
            "scatter, impacts, motion and regime, senders and dropped messages; the worm and\n"
            "wheel angles theta1/2 (deg) when the time line has room. Keys: q quit,\n"
            "c clear, space freeze/unfreeze the display.\n\n"
            "  --url URL          LCM URL (default $WORMGEAR_URL or %s)\n"
            "  --prefix P         channel prefix (default $WORMGEAR_PREFIX or %s)\n"
            "  --periods P        the x_n trace's window, mesh periods (default 4; [1, 1000])\n"
            "  --window SEC       wall seconds of sections in the scatter and motion counts,\n"
            "                     and of samples in a stroboscopic trace (default 5; [0.5,\n"
            "                     600]; the labels say fewer while less was heard: --once)\n"
            "  --fps HZ           frames per second (default 4; [0.2, 30])\n"
            "  --tol X            period-detection tolerance, max norm (default 1e-6; (0, 1])\n"
            "  --once             wait for a STATUS (see --timeout), print one frame, exit\n"
            "  --frames N         print N frames, one per 1/fps s, then exit ([1, 100000])\n"
            "  --timeout SEC      --once/--frames: wait this long for a STATUS (default 5 s)\n"
            "  --size COLSxROWS   frame size in characters (default: the terminal, else 100x32)\n"
            "  --plain            no ANSI escapes (default when stdout is not a terminal)\n"
            "  -h, --help         this text\n\n"
            "The trace and the daemon's rate. The trace's time axis is simulated time: mesh\n"
            "periods, and ms once PARAMS gave the scale. The daemon publishes about 2000 STATE\n"
            "samples per wall second (wormgeard --state-rate-hz). At physical real time\n"
            "(wormgeard --rate 1; table3 at omega = 1 meshes at 5077 Hz) that is under one\n"
            "sample per mesh period, so a trace of raw samples would alias: wgmon then folds\n"
            "the last --window seconds of samples onto the window by their phase from the\n"
            "section psi = 0 and says STROBOSCOPIC over the plot (a faithful picture of a\n"
            "periodic orbit; a cloud for a chaotic one). With 8 or more samples per period\n"
            "it scrolls: the last --periods periods, newest at the right. For a scrolling\n"
            "trace slow the daemon down: wormgeard --rate 0.01, or at run time\n"
            "`wgctl mode realtime 0.01` (20 ms of wall time per mesh period at omega = 1,\n"
            "about 40 samples each), or raise --state-rate-hz.\n\n"
            "Senders. Messages are told apart by their seq lines and the offset of their\n"
            "utime to this host's clock: a daemon restart shows as `restarted xN`, a log\n"
            "played back (lcm-logplayer) as REPLAY with its age, and when several senders\n"
            "share the channels the live one is shown and the others are named.\n\n"
            "Exit status: 0 ok, 1 no STATUS heard (--once/--frames) or no bus, 2 usage error\n"
            "(an LCM URL LCM refuses too).\n",
            BUS_DEFAULT_URL, BUS_DEFAULT_PREFIX);
}

#define PROG "wgmon"

static int opt_size(const char *a, opts *o)
{
    if (sscanf(a, "%dx%d%c", &o->cols, &o->rows, (char[2]){0}) != 2 || o->cols < 40 ||
        o->cols > 1000 || o->rows < 16 || o->rows > 500)
        return cli_usage_error(PROG, "--size '%s': %s", a,
                               "COLSxROWS with COLS in [40, 1000], ROWS in [16, 500]");
    return 0;
}

/* One option c with argument a: 0, CLI_EUSAGE (reported), or -1 unknown. */
static int opt_one(void *ctx, int c, const char *a)
{
    opts *o = ctx;
    switch (c) {
    case 'u': o->url = a; return 0;
    case 'p': /* a usage error (exit 2), as wgctl's */
        if (bus_prefix_ok(o->prefix = a))
            return 0;
        return cli_usage_error(PROG, "--prefix '%.60s': need [A-Za-z0-9_.-], at most %d "
                               "characters (the daemon's rule)", a, BUS_PREFIX_MAX);
    case 'w': return cli_opt_num(PROG, "--window", a, 0.5, 600, "seconds in [0.5, 600]", &o->window_s);
    case 'r':
        return cli_opt_int(PROG, "--periods", a, 1, 1000, "mesh periods, an integer in [1, 1000]",
                           &o->periods);
    case 'f': return cli_opt_num(PROG, "--fps", a, 0.2, 30, "frames per second in [0.2, 30]", &o->fps);
    case 't': return cli_opt_num(PROG, "--tol", a, 1e-300, 1, "a tolerance in (0, 1]", &o->tol);
    case '1': o->frames = 1; return 0;
    case 'n': return cli_opt_int(PROG, "--frames", a, 1, 100000, "an integer in [1, 100000]", &o->frames);
    case 'T':
        return cli_opt_num(PROG, "--timeout", a, 0.1, 3600, "seconds in [0.1, 3600]", &o->timeout_s);
    case 's': return opt_size(a, o);
    case 'P': o->plain = 1; return 0;
    case 'h': usage(stdout); exit(0);
    default: return -1;
    }
}

static int parse_opts(int argc, char **argv, opts *o)
{
    static const struct option lo[] = {
        {"url", 1, 0, 'u'},    {"prefix", 1, 0, 'p'}, {"window", 1, 0, 'w'},
        {"periods", 1, 0, 'r'}, {"fps", 1, 0, 'f'},   {"tol", 1, 0, 't'},
        {"once", 0, 0, '1'},   {"frames", 1, 0, 'n'}, {"timeout", 1, 0, 'T'},
        {"size", 1, 0, 's'},   {"plain", 0, 0, 'P'},  {"help", 0, 0, 'h'},
        {0, 0, 0, 0}};
    *o = (opts){.window_s = 5, .fps = 4, .timeout_s = 5, .tol = 1e-6, .periods = 4};
    int rc = cli_getopt(PROG, argc, argv, "h", lo, opt_one, o);
    if (rc)
        return rc;
    if (optind < argc)
        return cli_usage_error(PROG, "argument '%s': wgmon takes no arguments", argv[optind]);
    return 0;
}

/* ---- messages --------------------------------------------------------------- */

static void ask_params(mon *m);

static void clear_plots(mon *m);

/* The sender to show: of every line heard on any channel, the one whose
 * clock is nearest ours (a live daemon before a replay); its clock (or its
 * id, when messages carry one) picks the messages shown. When the choice
 * moves to another sender the plots start again. */
static void choose_sender(mon *m)
{
    const bus_stream *best = NULL;
    for (int k = 0; k < NCH; k++)
        for (int i = 0; i < m->sc[k].seq.n; i++) {
            const bus_stream *l = &m->sc[k].seq.s[i];
            if (!best || fabs(l->offset_s) < fabs(best->offset_s))
                best = l;
        }
    if (!best)
        return;
    int moved = m->following && (best->sender != m->follow_sender ||
                                 (!best->sender && fabs(best->offset_s - m->follow_off) > 1.0));
    m->follow_off = best->offset_s;
    m->follow_sender = best->sender;
    m->following = 1;
    if (moved)
        clear_plots(m);
}

/* Is a message on line l of the sender shown? */
static int shown(const mon *m, const bus_stream *l)
{
    if (!m->following)
        return 1;
    if (l->sender || m->follow_sender)
        return l->sender == m->follow_sender;
    return fabs(l->offset_s - m->follow_off) <= 1.0;
}

/* Note a message's sender on channel k: 1 if it is the sender shown. A
 * restart of it asks PARAMS again and restarts the period detection. */
static int seq_note(mon *m, int k, int64_t seq, int64_t utime)
{
    int line;
    m->sc[k].count++;
    int rc = bus_streams_note(&m->sc[k].seq, seq, utime, 0, cli_mono_s(), cli_wall_us(), &line);
    choose_sender(m);
    if (!shown(m, &m->sc[k].seq.s[line])) {
        m->sc[k].ignored++;
        return 0;
    }
    if (rc == BUS_RESTART && k == CH_STATUS)
        ask_params(m);
    if (rc != BUS_IN_ORDER && k == CH_POINCARE)
        wg_tracker_init(&m->trk, m->trk.dim, m->o.tol); /* it needs consecutive ones */
    return 1;
}

/* A STATUS string as text for the terminal: no escape it would obey */
#define CPY(dst, src) cli_text((dst), sizeof(dst), (src))

/* Ask the daemon to republish PARAMS now (instead of at its 1 Hz); the
 * ACK is not awaited. */
static void ask_params(mon *m)
{
    wormgear_cmd_t c = bus_cmd("get");
    bus_send(&m->c, &c);
}

static void on_status(mon *m, const wormgear_status_t *s)
{
    status_copy *c = &m->st;
    CPY(c->scene, s->scene); CPY(c->mode, s->mode); CPY(c->run, s->run);
    CPY(c->health, s->health); CPY(c->fault, s->fault); CPY(c->motion, s->motion);
    CPY(c->regime, s->regime); CPY(c->tick_refusal, s->tick_refusal);
    c->ticks_refused = s->ticks_refused, c->ticks_lost = s->ticks_lost;
    c->rate = s->rate; c->tau = s->tau; c->t_s = s->t_s; c->omega = s->omega;
    c->rtf = s->rtf; c->lag_s = s->lag_s; c->loop_mean_us = s->loop_mean_us;
    c->loop_max_us = s->loop_max_us; c->steps_per_s = s->steps_per_s; c->cpu = s->cpu_share;
    c->imp_pp = s->impacts_per_period; c->uptime_s = s->uptime_s; c->period = s->period;
    c->overruns = s->overruns; c->dropped = s->msgs_dropped; c->acc = s->cmds_accepted;
    c->ref = s->cmds_refused; c->N = s->steps_per_period; c->ramp = s->ramp_active;
    m->have_status = 1;
    m->status_at = cli_mono_s();
}

static void on_params(mon *m, const wormgear_params_t *p)
{
    for (int k = 0; k < NKEY; k++) {
        m->has_key[k] = 0;
        for (int i = 0; i < p->n; i++)
            if (strcmp(p->name[i], key_names[k]) == 0) {
                m->key[k] = p->value[i];
                m->has_key[k] = 1;
            }
    }
    CPY(m->stepper, p->stepper);
    CPY(m->ramp_param, p->ramp_param);
    m->ramp_active = p->ramp_active;
    m->ramp_from = p->ramp_from; m->ramp_to = p->ramp_to;
    m->ramp_tau0 = p->ramp_tau0; m->ramp_dur = p->ramp_duration_tau;
    m->omega_n_rad_s = p->omega_n_rad_s;
    m->length_m = p->length_m;
    m->have_params = 1;
}

static void on_state(mon *m, const wormgear_state_t *s)
{
    double t = cli_mono_s();
    m->tr.decimation = s->decimation;
    for (int i = 0; i < s->n; i++)
        mon_trace_push(&m->tr, s->step0 + (int64_t)i * s->decimation, s->xn[i], t);
    if (s->n > 0) { /* the latest sample's angles, if they are angles: [0, 2 pi) */
        double a = s->theta1[s->n - 1], b = s->theta2[s->n - 1];
        m->have_theta = a >= 0 && a < 2 * M_PI && b >= 0 && b < 2 * M_PI;
        m->theta1 = a;
        m->theta2 = b;
    }
}

static void on_poincare(mon *m, const wormgear_poincare_t *p)
{
    double t = cli_mono_s();
    int dim = p->nstate > WG_NSTATE_MAX ? WG_NSTATE_MAX : p->nstate;
    if (dim >= 1 && dim != m->trk.dim)
        wg_tracker_init(&m->trk, dim, m->o.tol);
    for (int i = 0; i < p->n; i++) {
        mon_sections_push(&m->pc, t, p->xn[i], p->dxn[i], p->impacts[i], p->motion[i]);
        if (dim < 1)
            continue;
        wg_section sec = {.stats = {.impacts = p->impacts[i], .motion = p->motion[i]}};
        memcpy(sec.y, p->y[i], sizeof(double) * (size_t)dim);
        wg_tracker_push(&m->trk, &sec);
    }
}

static void on_contact(mon *m, const wormgear_contact_t *c)
{
    for (int i = 0; i < c->n; i++)
        if (c->contact[i] >= 0 && c->contact[i] < WG_NCONTACT && c->kind[i] >= 0 &&
            c->kind[i] < WG_NEVKIND)
            m->contacts[c->contact[i]][c->kind[i]]++;
}

/* Raw handler: decode by channel, count seq and undecodable messages, use
 * the messages of the sender shown. */
#define DECODE(T, TYPE, fn)                                                                  \
    do {                                                                                   \
        T msg;                                                                             \
        if (BUS_DECODE(T, TYPE, rb, &msg)) { /* bytes checked first: bus_msg.h */          \
            m->sc[k].bad++;                                                                \
            return;                                                                        \
        }                                                                                  \
        if (seq_note(m, k, msg.seq, msg.utime) && !m->frozen)                              \
            fn(m, &msg);                                                                   \
        T##_decode_cleanup(&msg);                                                          \
    } while (0)

static void on_raw(const lcm_recv_buf_t *rb, const char *channel, void *u)
{
    mon *m = u;
    int k = 0;
    while (k < NCH && strcmp(channel + strlen(m->c.prefix), ch_suffix[k]) != 0)
        k++;
    static const int type[NCH] = {[CH_STATUS] = BUS_STATUS, [CH_PARAMS] = BUS_PARAMS,
                                  [CH_STATE] = BUS_STATE, [CH_POINCARE] = BUS_POINCARE,
                                  [CH_CONTACT] = BUS_CONTACT};
    if (k < NCH && !bus_signed(&m->c, type[k], rb)) {
        m->sc[k].unverified++; /* with a key: not the daemon's, or not now */
        return;
    }
    switch (k) {
    case CH_STATUS: DECODE(wormgear_status_t, BUS_STATUS, on_status); break;
    case CH_PARAMS: DECODE(wormgear_params_t, BUS_PARAMS, on_params); break;
    case CH_STATE: DECODE(wormgear_state_t, BUS_STATE, on_state); break;
    case CH_POINCARE: DECODE(wormgear_poincare_t, BUS_POINCARE, on_poincare); break;
    case CH_CONTACT: DECODE(wormgear_contact_t, BUS_CONTACT, on_contact); break;
    default: break;
    }
}

/* Forget the plotted data (another sender is shown now). */
static void clear_plots(mon *m)
{
    m->tr.n = m->pc.n = 0;
    m->since = cli_mono_s();
    m->have_theta = 0;
    wg_tracker_init(&m->trk, m->trk.dim, m->o.tol);
    memset(m->contacts, 0, sizeof m->contacts);
}

static void clear_data(mon *m)
{
    clear_plots(m);
    for (int k = 0; k < NCH; k++)
        m->sc[k] = (seqc){0};
    m->following = 0;
}

/* ---- drawing ---------------------------------------------------------------- */

static int health_colour(const char *h) { return !strcmp(h, "ok") ? 32 : !strcmp(h, "lagging") ? 33 : 31; }

/* The senders on STATUS, when there is more than the live one: the shown
 * one a replay, or others beside it. */
static void draw_senders(mon *m, mon_text *f)
{
    const bus_streams *b = &m->sc[CH_STATUS].seq;
    char age[32];
    if (!m->following)
        return;
    if (fabs(m->follow_off) > BUS_REPLAY_S) {
        mon_text_put(f, 35, "source  REPLAY: sent %s %s (a log played back, or a clock that far "
                     "off)", mon_text_age(m->follow_off, age, sizeof age),
                     m->follow_off < 0 ? "ago" : "ahead");
        mon_text_nl(f);
    }
    int n = 0; /* a line a restart replaced is gone, not a sender beside it */
    for (int i = 0; i < b->n; i++)
        n += !b->s[i].replaced_by;
    if (n < 2)
        return;
    mon_text_put(f, 33, "senders %d on %sSTATUS: showing the %s;", n, m->c.prefix,
                 fabs(m->follow_off) > BUS_REPLAY_S ? "one nearest this host's clock" : "live one");
    int me = 0; /* the STATUS line of the sender shown */
    for (int i = 1; i < b->n; i++)
        if (fabs(b->s[i].offset_s - m->follow_off) < fabs(b->s[me].offset_s - m->follow_off))
            me = i;
    for (int i = 0; i < b->n; i++) {
        const bus_stream *l = &b->s[i];
        if (l->replaced_by || i == me)
            continue;
        if (fabs(l->offset_s - m->follow_off) <= 1.0)
            mon_text_put(f, 33, " another on the same clock, seq %lld.. (a second daemon?): "
                         "mixed in", (long long)l->first_seq);
        else
            mon_text_put(f, 33, " seq %lld.. sent %s %s%s: not shown", (long long)l->first_seq,
                         mon_text_age(l->offset_s, age, sizeof age),
                         l->offset_s < 0 ? "ago" : "ahead", bus_stream_replayed(l) ? " (a replay)" : "");
    }
    mon_text_nl(f);
}

static void draw_header(mon *m, mon_text *f, double now)
{
    const status_copy *s = &m->st;
    mon_text_put(f, 1, "wormgear monitor");
    mon_text_put(f, 0, "  %s* on %s", m->c.prefix, m->c.url);
    mon_text_nl(f);
    if (!m->have_status) { /* word by word: the hint wraps, never cut at the edge */
        char hint[512];
        mon_text_put(f, 33, "waiting for %sSTATUS ...", m->c.prefix);
        bus_hint(&m->c, hint, sizeof hint);
        for (char *save = NULL, *w = strtok_r(hint, " ", &save); w;
             w = strtok_r(NULL, " ", &save))
            mon_text_put(f, 33, " %s", w);
        mon_text_nl(f);
        return;
    }
    double age = now - m->status_at;
    mon_text_put(f, 0, "daemon  %s  %s x%g  %s  ", s->scene, s->mode, s->rate, s->run);
    mon_text_put(f, health_colour(s->health), "%s", s->health);
    if (s->fault[0])
        mon_text_put(f, 31, " (%s)", s->fault);
    mon_text_put(f, 0, "  up %.0f s", s->uptime_s);
    if (fabs(m->follow_off) > BUS_REPLAY_S)
        mon_text_put(f, 35, "  REPLAY");
    if (age > 3.0)
        mon_text_put(f, 31, "  NO HEARTBEAT for %.0f s", age);
    if (m->sc[CH_STATUS].seq.restarts)
        mon_text_put(f, 33, "  restarted x%ld", m->sc[CH_STATUS].seq.restarts);
    mon_text_nl(f);
    draw_senders(m, f);
    mon_text_put(f, 0, "time    t %.6f s  tau %.3f  period %lld  N %d %s", s->t_s, s->tau,
                 (long long)s->period, s->N, m->stepper);
    char th[48]; /* worm, wheel (MODEL.md s2): in [0, 360), 0 at the start */
    snprintf(th, sizeof th, "  theta1/2 %.1f/%.1f deg", m->theta1 * (180.0 / M_PI),
             m->theta2 * (180.0 / M_PI));
    if (m->have_theta && f->col + mon_text_width(th) <= f->cols) /* only if it fits */
        mon_text_put(f, 0, "%s", th);
    mon_text_nl(f);
    mon_text_put(f, 0, "pace    rtf %.4f  lag %.3f ms  ", s->rtf, s->lag_s * 1e3);
    mon_text_put(f, s->overruns ? 33 : 0, "overruns %lld", (long long)s->overruns);
    if (!m->tight)
        mon_text_put(f, 0, "  loop %.1f/%.1f us", s->loop_mean_us, s->loop_max_us);
    mon_text_put(f, 0, "  %.0f steps/s  cpu %.1f%%", s->steps_per_s, s->cpu * 100);
    mon_text_nl(f);
}

static void draw_params(mon *m, mon_text *f)
{
    mon_text_put(f, 0, "params ");
    for (int k = 0; k < NKEY; k++)
        if (m->has_key[k]) {
            mon_text_put(f, k == 0 ? 1 : 0, " %s %.6g", key_names[k], m->key[k]);
            if (k == 0 && m->omega_n_rad_s > 0)
                mon_text_put(f, 0, " (%.0f Hz)", m->key[k] * m->omega_n_rad_s / (2 * M_PI));
        }
    if (!m->have_params)
        mon_text_put(f, 0, " omega %.6g (PARAMS not yet heard)", m->st.omega);
    if (m->ramp_active && m->ramp_dur > 0) {
        double fr = (m->st.tau - m->ramp_tau0) / m->ramp_dur;
        mon_text_put(f, 36, "  ramp %s %.4g->%.4g %.0f%%", m->ramp_param, m->ramp_from,
                     m->ramp_to, 100 * fmin(1, fmax(0, fr)));
    }
    mon_text_nl(f);
}

static void draw_motion(mon *m, mon_text *f, const mon_view_ctx *c)
{
    const mon_sections *pc = &m->pc;
    long j0 = mon_view_from(pc->t, pc->n, pc->cap, c->now - c->window_s), n = pc->n - j0;
    char span[16];
    long imp = 0, mot[3] = {0, 0, 0};
    for (long j = j0; j < pc->n; j++) {
        imp += pc->imp[j % pc->cap];
        int c = pc->mot[j % pc->cap];
        mot[c < 0 ? 0 : c > 2 ? 2 : c]++;
    }
    int worst = mot[2] ? 2 : mot[1] ? 1 : 0;
    mon_text_put(f, 0, "motion  daemon: %s, %.3g impacts/period", m->st.motion, m->st.imp_pp);
    if (n)
        mon_text_put(f, 0, "  last %s s: %s, %.3g impacts/period",
                     mon_view_span(c, span, sizeof span), wg_motion_name(worst), (double)imp / n);
    if (n && !m->tight)
        mon_text_put(f, 0, " (periods none/single/double %ld/%ld/%ld)", mot[0], mot[1], mot[2]);
    mon_text_nl(f);
    double resid = 0;
    int per = m->trk.n >= 16 ? wg_tracker_period(&m->trk, &resid) : -1;
    mon_text_put(f, 0, "regime  daemon: %s  local: ", m->st.regime);
    if (per > 0)
        mon_text_put(f, 32, "period-%d", per);
    else if (per == 0)
        mon_text_put(f, 35, "aperiodic (no period <= %d)", WG_PERIOD_MAX);
    else
        mon_text_put(f, 0, "(collecting %d/16 sections)", m->trk.n);
    if (per >= 0 && !m->tight)
        mon_text_put(f, 0, " over %d sections, resid %.2g, tol %.2g", m->trk.n, resid, m->o.tol);
    mon_text_nl(f);
}

static void draw_msgs(mon *m, mon_text *f)
{
    long drop = 0, ign = 0;
    mon_text_put(f, 0, "msgs   ");
    for (int k = 0; k < NCH; k++) {
        const seqc *c = &m->sc[k];
        drop += c->seq.missing, ign += c->ignored;
        mon_text_put(f, 0, " %s %lld", ch_suffix[k], (long long)c->count);
        if (c->seq.missing)
            mon_text_put(f, 33, " (-%ld)", c->seq.missing);
        if (c->bad)
            mon_text_put(f, 31, " (%lld undecodable)", (long long)c->bad);
        if (c->unverified)
            mon_text_put(f, 31, " (%lld unverified)", (long long)c->unverified);
    }
    mon_text_put(f, drop ? 33 : 0, "  dropped %ld", drop);
    if (ign)
        mon_text_put(f, 33, "  not shown %ld (other senders)", ign);
    if (m->st.dropped || !m->tight)
        mon_text_put(f, m->st.dropped ? 33 : 0, "  not published %lld", (long long)m->st.dropped);
    mon_text_put(f, 0, "  cmds %lld/%lld refused", (long long)m->st.acc, (long long)m->st.ref);
    if (!m->tight)
        mon_text_put(f, 0, "  mesh impacts %ld",
                 m->contacts[WG_C_MESH][WG_EV_DRIVE_IMPACT] + m->contacts[WG_C_MESH][WG_EV_BACK_IMPACT]);
    mon_text_nl(f);
    if (m->st.ticks_refused) { /* refused ticks (each ACKed to its sender) */
        mon_text_put(f, 31, "ticks   %lld refused", (long long)m->st.ticks_refused);
        mon_text_put(f, 0, ", the last: %s", m->st.tick_refusal);
        mon_text_nl(f);
    }
    if (m->st.ticks_lost) { /* gaps in the seq of the ticks taken */
        mon_text_put(f, 33, "ticks   %lld lost on the way", (long long)m->st.ticks_lost);
        mon_text_nl(f);
    }
}

#define MON_SYNC_BEGIN "\033[?2026h"
#define MON_SYNC_END "\033[?2026l"

/* Build a frame (clear: the whole screen first, after a resize). */
static void render(mon *m, mon_text *f, int clear)
{
    double now = cli_mono_s();
    mon_text_begin(f, m->cols, m->o.plain);
    m->tight = m->rows < 30;
    if (!f->plain) { /* the frame as one synchronized update (DEC mode 2026): a
                        terminal that has it shows it whole, never half old,
                        half new; one that has not ignores the mode */
        mon_text_raw(f, MON_SYNC_BEGIN, sizeof MON_SYNC_BEGIN - 1);
        mon_text_raw(f, clear ? "\033[2J\033[H" : "\033[H", clear ? 7 : 3);
    }
    draw_header(m, f, now);
    if (m->have_status) {
        mon_view_ctx c = {m->st.N, m->st.omega, m->omega_n_rad_s, m->length_m, m->o.periods,
                          m->o.window_s, now, m->since};
        draw_params(m, f);
        draw_motion(m, f, &c);
        draw_msgs(m, f);
        mon_view_plots(f, &m->tr, &m->pc, &c, m->rows - f->lines - 1);
    }
    mon_text_put(f, 0, "%s", f->plain ? "" : m->frozen ? "-- frozen -- space: resume  q: quit  c: clear" : "q: quit  c: clear  space: freeze");
    if (!f->plain) {
        mon_text_raw(f, "\033[K\033[J", 6);
        mon_text_raw(f, MON_SYNC_END, sizeof MON_SYNC_END - 1);
    } else
        mon_text_nl(f);
}

/* ---- terminal and loop --------------------------------------------------------- */

static void on_signal(int sig)
{
    if (sig == SIGWINCH)
        g_winch = 1;
    else
        g_quit = 1;
}

static void term_size(mon *m)
{
    struct winsize ws;
    m->cols = m->o.cols ? m->o.cols : 100;
    m->rows = m->o.rows ? m->o.rows : 32;
    if (!m->o.cols && ioctl(STDOUT_FILENO, TIOCGWINSZ, &ws) == 0 && ws.ws_col >= 20 && ws.ws_row >= 8)
        m->cols = ws.ws_col, m->rows = ws.ws_row;
}

static void key(mon *m)
{
    char ch;
    while (read(STDIN_FILENO, &ch, 1) == 1) {
        if (ch == 'q' || ch == 'Q')
            g_quit = 1;
        else if (ch == 'c')
            clear_data(m);
        else if (ch == ' ')
            m->frozen = !m->frozen;
    }
}

/* Handle LCM and keys until `until` (monotonic seconds) or quit; with
 * idle, until the writer has written its frame, if that is sooner. */
static void pump(mon *m, double until, int idle)
{
    int lfd = lcm_get_fileno(m->c.lcm), kfd = m->term.raw ? STDIN_FILENO : -1;
    int wfd = m->out ? wg_writer_fd(m->out) : -1;
    int top = lfd > kfd ? lfd : kfd;
    top = top > wfd ? top : wfd;
    for (double left; !g_quit && (left = until - cli_mono_s()) > 0;) {
        fd_set set;
        FD_ZERO(&set);
        FD_SET(lfd, &set);
        if (kfd >= 0)
            FD_SET(kfd, &set);
        if (wfd >= 0)
            FD_SET(wfd, &set);
        struct timeval tv = {(long)left, (long)((left - floor(left)) * 1e6)};
        int n = select(top + 1, &set, NULL, NULL, &tv);
        if (n > 0 && FD_ISSET(lfd, &set))
            lcm_handle(m->c.lcm);
        if (n > 0 && kfd >= 0 && FD_ISSET(kfd, &set))
            key(m);
        if (n > 0 && wfd >= 0 && FD_ISSET(wfd, &set)) {
            int written = wg_writer_idle(m->out); /* which reads the fd: else select spins */
            if (written && idle)
                return;
        }
        if (g_winch)
            return;
    }
}

/* The monitor ends: the terminal as it was, its closing escapes written
 * after the last frame within a second, and its modes restored. If it
 * still takes nothing (Ctrl-S), m->stalled: the process must end at once
 * (the writer is left blocked). */
static void finish(mon *m)
{
    if (!m->o.plain)
        wg_writer_put(m->out, STDOUT_FILENO, mon_term_leave_seq, mon_term_leave_len);
    m->stalled = wg_writer_stop(m->out, 1.0) != 0;
    mon_term_restore(&m->term);
}

static int run(mon *m)
{
    mon_text f = {0};
    double next = cli_mono_s();
    if (m->o.frames) { /* headless: first wait for a heartbeat */
        double end = cli_mono_s() + m->o.timeout_s;
        while (!m->have_status && !g_quit && cli_mono_s() < end)
            pump(m, fmin(end, cli_mono_s() + 0.05), 0);
        /* a little data for the plots, PARAMS and the local period detection */
        for (end = cli_mono_s() + 1.5; m->have_status && !g_quit && cli_mono_s() < end &&
                                  (m->trk.n < 24 || !m->have_params || m->tr.n < 1000);)
            pump(m, fmin(end, cli_mono_s() + 0.05), 0);
        next = cli_mono_s();
    }
    if (!m->o.plain)
        mon_term_enter(&m->term);
    if (!(m->out = wg_writer_start(OUT_QUEUE))) {
        fprintf(stderr, "wgmon: cannot start the frame writer: %s\n", strerror(errno));
        if (!m->o.plain)
            mon_term_leave(&m->term);
        return 1;
    }
    int clear = 0;
    for (int n = 0; !g_quit && !wg_writer_error(m->out, STDOUT_FILENO) && (!m->o.frames || n < m->o.frames);) {
        if (g_winch) {
            g_winch = 0;
            term_size(m);
            clear = !m->o.plain;
        }
        if (!wg_writer_idle(m->out)) { /* the last frame not yet written: the bus is read meanwhile */
            pump(m, cli_mono_s() + 0.25, 1);
            continue;
        }
        render(m, &f, clear);
        wg_writer_put(m->out, STDOUT_FILENO, f.buf, f.len); /* copied */
        clear = 0;
        n++;
        double now = cli_mono_s();
        next = fmax(next + 1.0 / m->o.fps, now); /* after a stall: on, not a burst */
        if (!m->o.frames || n < m->o.frames)
            pump(m, next, 0);
    }
    while (m->o.frames && !g_quit && !wg_writer_idle(m->out)) /* headless: every frame out */
        pump(m, cli_mono_s() + 0.25, 1);
    finish(m);
    mon_text_free(&f);
    char hint[512];
    if (m->o.frames && !m->have_status && !g_quit) /* exit 1: said on stderr too */
        fprintf(stderr, "wgmon: no STATUS on %sSTATUS within %g s: %s\n", m->c.prefix,
                m->o.timeout_s, bus_hint(&m->c, hint, sizeof hint));
    return m->o.frames && !m->have_status ? 1 : 0;
}

static int setup(mon *m)
{
    char why[256];
    int brc = bus_open(&m->c, m->o.url, m->o.prefix, "wgmon", why, sizeof why);
    if (brc) {
        fprintf(stderr, "wgmon: %s\n", why);
        return bus_exit_status(brc);
    }
    /* LCM's default queue (30 a subscription) drops what comes while the
     * monitor is not scheduled for ~0.3 s (~100 a second on a channel),
     * and "dropped" would count it: a longer one, as wgrig's. */
    m->since = cli_mono_s();
    for (int k = 0; k < NCH; k++)
        m->subs[k] = bus_subscribe(&m->c, ch_suffix[k], on_raw, m, 4096);
    ask_params(m);
    if (mon_trace_alloc(&m->tr, TR_CAP) || mon_sections_alloc(&m->pc, PC_CAP)) {
        fprintf(stderr, "wgmon: out of memory\n");
        return 1;
    }
    return 0;
}

static void teardown(mon *m)
{
    bus_close(&m->c);
    mon_trace_free(&m->tr);
    mon_sections_free(&m->pc);
}

int main(int argc, char **argv)
{
    mon *m = calloc(1, sizeof *m);
    if (!m)
        return 1;
    int rc = parse_opts(argc, argv, &m->o);
    if (!rc) {
        if (!isatty(STDOUT_FILENO))
            m->o.plain = 1;
        cli_on_stop_signals(on_signal);
        struct sigaction sa = {.sa_handler = on_signal}; /* a resize wakes the loop too */
        sigaction(SIGWINCH, &sa, NULL);
        sigaction(SIGHUP, &sa, NULL); /* a closed terminal: quit, the tty restored (it was
                                         left without echo and line editing) */
        signal(SIGPIPE, SIG_IGN);
        term_size(m);
        rc = setup(m);
        if (!rc)
            rc = run(m);
        if (m->stalled) /* the terminal takes nothing: LCM's thread may be blocked */
            _exit(rc);  /* writing a warning to it too, and lcm_destroy would join it */
        teardown(m);
    }
    free(m);
    return rc;
}

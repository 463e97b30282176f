/* wgmon - live terminal dashboard of wormgeard (plain ANSI, works over ssh).
 *
 * Subscribes to STATUS, PARAMS, STATE, POINCARE and CONTACT and redraws a
 * frame a few times a second: pacing health, the key parameters, a scrolling
 * x_n trace, the Poincare scatter of the last seconds, impacts per period,
 * motion class and regime (the daemon's, and a local period detection with
 * the analysis library), and dropped-message counts from seq gaps. A daemon
 * restart shows as a seq reset. Headless: --once / --frames N print frames
 * as plain text. Exit 0, 1 no STATUS heard (--once/--frames), 2 usage. */
#include "bus.h"
#include "cli.h"

#include "lcmtypes/wormgear_contact_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "wormgear/wg_model.h"
#include "wormgear/wg_regime.h"

#include <getopt.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/ioctl.h>
#include <sys/select.h>
#include <termios.h>
#include <unistd.h>

enum { TR_CAP = 1 << 17, PC_CAP = 1 << 15, NKEY = 8 };
enum { CH_STATUS, CH_PARAMS, CH_STATE, CH_POINCARE, CH_CONTACT, NCH };
static const char *const ch_suffix[NCH] = {"STATUS", "PARAMS", "STATE", "POINCARE", "CONTACT"};
static const char *const key_names[NKEY] = {"omega", "xi_p", "f_m", "f_e", "k_a", "e_m", "b", "b_j"};

static volatile sig_atomic_t g_quit, g_winch; /* set by signal handlers only */

typedef struct opts {
    const char *url, *prefix;
    double window_s, fps, timeout_s, tol;
    int frames;       /* 0: interactive until q */
    int plain;        /* no escape sequences */
    int cols, rows;   /* 0: from the terminal */
} opts;

typedef struct seqc {      /* per-channel counters */
    bus_seq seq;          /* .missing: messages dropped */
    int64_t count, bad;
} seqc;

typedef struct status_copy {
    char scene[64], mode[16], run[16], health[16], fault[160], motion[24], regime[32];
    double rate, tau, t_s, omega, rtf, lag_s, loop_mean_us, loop_max_us, steps_per_s, cpu;
    double imp_pp, uptime_s;
    int64_t period, overruns, dropped, acc, ref;
    int N, ramp;
} status_copy;

typedef struct mon {
    bus c;
    opts o;
    seqc sc[NCH];
    void *subs[NCH];
    int have_status, have_params, restarts;
    double status_at;             /* wall seconds (monotonic) of the last STATUS */
    status_copy st;
    double key[NKEY];
    int has_key[NKEY];
    char stepper[16], ramp_param[16];
    double ramp_from, ramp_to, ramp_tau0, ramp_dur;
    int ramp_active;
    double *tr_t, *tr_x;          /* x_n trace ring: receive time, value */
    long tr_n;                    /* samples ever pushed */
    double *pc_t, *pc_x, *pc_v;   /* Poincare ring: time, x_n, x_n' */
    int *pc_imp, *pc_mot;
    long pc_n;
    double ys[WG_TRACK_LEN * WG_NSTATE_MAX]; /* last consecutive states (stride ydim) */
    int ny, ydim;
    long contacts[WG_NCONTACT][WG_NEVKIND]; /* CONTACT events in the session */
    int rows, cols, frozen;
    struct termios tio;
    int raw;
} mon;

/* ---- options --------------------------------------------------------------- */

static void usage(FILE *f)
{
    fprintf(f,
            "usage: wgmon [options]\n"
            "Live dashboard of a running wormgeard: pacing, parameters, x_n trace, Poincare\n"
            "scatter, impacts, motion and regime, dropped messages. Keys: q quit, c clear,\n"
            "space freeze/unfreeze the display.\n\n"
            "  --url URL          LCM URL (default $WORMGEAR_URL or %s)\n"
            "  --prefix P         channel prefix (default $WORMGEAR_PREFIX or %s)\n"
            "  --window SEC       trace and scatter span, wall seconds (default 5; [0.5, 600])\n"
            "  --fps HZ           frames per second (default 4; [0.2, 30])\n"
            "  --tol X            period-detection tolerance, max norm (default 1e-6; (0, 1])\n"
            "  --once             wait for a STATUS (see --timeout), print one frame, exit\n"
            "  --frames N         print N frames, one per 1/fps s, then exit ([1, 100000])\n"
            "  --timeout SEC      --once/--frames: wait this long for a STATUS (default 5 s)\n"
            "  --size COLSxROWS   frame size in characters (default: the terminal, else 100x32)\n"
            "  --plain            no ANSI escapes (default when stdout is not a terminal)\n"
            "  -h, --help         this text\n\n"
            "Exit status: 0 ok, 1 no STATUS heard (--once/--frames), 2 usage error.\n",
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
    case 'p': o->prefix = a; return 0;
    case 'w': return cli_opt_num(PROG, "--window", a, 0.5, 600, "seconds in [0.5, 600]", &o->window_s);
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
        {"fps", 1, 0, 'f'},    {"tol", 1, 0, 't'},    {"once", 0, 0, '1'},
        {"frames", 1, 0, 'n'}, {"timeout", 1, 0, 'T'}, {"size", 1, 0, 's'},
        {"plain", 0, 0, 'P'},  {"help", 0, 0, 'h'},   {0, 0, 0, 0}};
    *o = (opts){.window_s = 5, .fps = 4, .timeout_s = 5, .tol = 1e-6};
    int rc = cli_getopt(PROG, argc, argv, "h", lo, opt_one, o);
    if (rc)
        return rc;
    if (optind < argc)
        return cli_usage_error(PROG, "argument '%s': wgmon takes no arguments", argv[optind]);
    return 0;
}

/* ---- messages --------------------------------------------------------------- */

static void ask_params(mon *m);

/* Count a message's seq on channel k; a backwards seq is a daemon restart. */
static void seq_note(mon *m, int k, int64_t seq)
{
    m->sc[k].count++;
    int jump = bus_seq_note(&m->sc[k].seq, seq);
    if (jump < 0 && k == CH_STATUS)
        m->restarts++, ask_params(m);
    if (jump && k == CH_POINCARE)
        m->ny = 0; /* the period detection needs consecutive sections */
}

#define CPY(dst, src) snprintf((dst), sizeof(dst), "%s", (src) ? (src) : "")

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
    CPY(c->regime, s->regime);
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
    m->have_params = 1;
}

static void on_state(mon *m, const wormgear_state_t *s)
{
    double t = cli_mono_s();
    for (int i = 0; i < s->n; i++) {
        long j = m->tr_n++ % TR_CAP;
        m->tr_t[j] = t;
        m->tr_x[j] = s->xn[i];
    }
}

static void on_poincare(mon *m, const wormgear_poincare_t *p)
{
    double t = cli_mono_s();
    int dim = p->nstate > WG_NSTATE_MAX ? WG_NSTATE_MAX : p->nstate;
    if (dim != m->ydim)
        m->ny = 0, m->ydim = dim;
    for (int i = 0; i < p->n; i++) {
        long j = m->pc_n++ % PC_CAP;
        m->pc_t[j] = t;
        m->pc_x[j] = p->xn[i];
        m->pc_v[j] = p->dxn[i];
        m->pc_imp[j] = p->impacts[i];
        m->pc_mot[j] = p->motion[i];
        if (m->ny == WG_TRACK_LEN)
            memmove(m->ys, m->ys + dim, sizeof(double) * (size_t)(dim * (WG_TRACK_LEN - 1))), m->ny--;
        for (int k = 0; k < dim; k++)
            m->ys[m->ny * dim + k] = p->y[i][k];
        m->ny++;
    }
}

static void on_contact(mon *m, const wormgear_contact_t *c)
{
    for (int i = 0; i < c->n; i++)
        if (c->contact[i] >= 0 && c->contact[i] < WG_NCONTACT && c->kind[i] >= 0 &&
            c->kind[i] < WG_NEVKIND)
            m->contacts[c->contact[i]][c->kind[i]]++;
}

/* Raw handler: decode by channel, count seq and undecodable messages. */
#define DECODE(T, fn)                                                                      \
    do {                                                                                   \
        T msg;                                                                             \
        if (T##_decode(rb->data, 0, (int)rb->data_size, &msg) < 0) {                       \
            m->sc[k].bad++;                                                                \
            return;                                                                        \
        }                                                                                  \
        seq_note(m, k, msg.seq);                                                           \
        if (!m->frozen)                                                                    \
            fn(m, &msg);                                                                   \
        T##_decode_cleanup(&msg);                                                          \
    } while (0)

static void on_raw(const lcm_recv_buf_t *rb, const char *channel, void *u)
{
    mon *m = u;
    int k = 0;
    while (k < NCH && strcmp(channel + strlen(m->c.prefix), ch_suffix[k]) != 0)
        k++;
    switch (k) {
    case CH_STATUS: DECODE(wormgear_status_t, on_status); break;
    case CH_PARAMS: DECODE(wormgear_params_t, on_params); break;
    case CH_STATE: DECODE(wormgear_state_t, on_state); break;
    case CH_POINCARE: DECODE(wormgear_poincare_t, on_poincare); break;
    case CH_CONTACT: DECODE(wormgear_contact_t, on_contact); break;
    default: break;
    }
}

static void clear_data(mon *m)
{
    m->tr_n = m->pc_n = 0;
    m->ny = 0;
    memset(m->contacts, 0, sizeof m->contacts);
    for (int k = 0; k < NCH; k++)
        m->sc[k] = (seqc){0};
    m->restarts = 0;
}

/* ---- drawing ---------------------------------------------------------------- */

typedef struct frame {  /* the text of one frame, built line by line */
    char *buf;
    size_t len, cap;
    int cols, plain, col; /* visible columns used on the current line */
} frame;

static void fr_raw(frame *f, const char *s, size_t n)
{
    if (f->len + n + 1 > f->cap) {
        size_t cap = (f->cap + n + 1) * 2;
        char *b = realloc(f->buf, cap);
        if (!b)
            return;
        f->buf = b, f->cap = cap;
    }
    memcpy(f->buf + f->len, s, n);
    f->len += n;
    f->buf[f->len] = 0;
}

/* Visible text, cut at the frame width; colour is an SGR code or 0. */
__attribute__((format(printf, 3, 4))) static void fr_put(frame *f, int colour, const char *fmt, ...)
{
    char t[1024], sgr[16];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(t, sizeof t, fmt, ap);
    va_end(ap);
    n = n < 0 ? 0 : n > (int)sizeof t - 1 ? (int)sizeof t - 1 : n;
    if (n > f->cols - f->col)
        n = f->cols - f->col;
    if (n <= 0)
        return;
    if (colour && !f->plain)
        fr_raw(f, sgr, (size_t)snprintf(sgr, sizeof sgr, "\033[%dm", colour));
    fr_raw(f, t, (size_t)n);
    if (colour && !f->plain)
        fr_raw(f, "\033[0m", 4);
    f->col += n;
}

static void fr_nl(frame *f)
{
    if (!f->plain)
        fr_raw(f, "\033[K", 3);
    fr_raw(f, "\n", 1);
    f->col = 0;
}

static int health_colour(const char *h) { return !strcmp(h, "ok") ? 32 : !strcmp(h, "lagging") ? 33 : 31; }

/* Oldest ring index with a time within the window (j0 .. n-1 are recent). */
static long ring_from(const double *t, long n, long cap, double since)
{
    long lo = n > cap ? n - cap : 0, hi = n;
    while (lo < hi) { /* times are non-decreasing along the ring */
        long mid = lo + (hi - lo) / 2;
        if (t[mid % cap] < since)
            lo = mid + 1;
        else
            hi = mid;
    }
    return lo;
}

static void draw_header(mon *m, frame *f, double now)
{
    const status_copy *s = &m->st;
    fr_put(f, 1, "wormgear monitor");
    fr_put(f, 0, "  %s* on %s", m->c.prefix, m->o.url ? m->o.url : bus_default_url());
    fr_nl(f);
    if (!m->have_status) {
        fr_put(f, 33, "waiting for %sSTATUS ... (is wormgeard running with this URL and prefix?)", m->c.prefix);
        fr_nl(f);
        return;
    }
    double age = now - m->status_at;
    fr_put(f, 0, "daemon  %s  %s x%g  %s  ", s->scene, s->mode, s->rate, s->run);
    fr_put(f, health_colour(s->health), "%s", s->health);
    if (s->fault[0])
        fr_put(f, 31, " (%s)", s->fault);
    fr_put(f, 0, "  up %.0f s", s->uptime_s);
    if (age > 3.0)
        fr_put(f, 31, "  NO HEARTBEAT for %.0f s", age);
    if (m->restarts)
        fr_put(f, 33, "  restarted x%d", m->restarts);
    fr_nl(f);
    fr_put(f, 0, "time    t %.6f s  tau %.3f  period %lld  N %d %s", s->t_s, s->tau,
           (long long)s->period, s->N, m->stepper);
    fr_nl(f);
    fr_put(f, 0, "pace    rtf %.4f  lag %.3f ms  ", s->rtf, s->lag_s * 1e3);
    fr_put(f, s->overruns ? 33 : 0, "overruns %lld", (long long)s->overruns);
    fr_put(f, 0, "  loop %.1f/%.1f us  %.0f steps/s  cpu %.1f%%", s->loop_mean_us, s->loop_max_us,
           s->steps_per_s, s->cpu * 100);
    fr_nl(f);
}

static void draw_params(mon *m, frame *f)
{
    fr_put(f, 0, "params ");
    for (int k = 0; k < NKEY; k++)
        if (m->has_key[k])
            fr_put(f, k == 0 ? 1 : 0, " %s %.6g", key_names[k], m->key[k]);
    if (!m->have_params)
        fr_put(f, 0, " omega %.6g (PARAMS not yet heard)", m->st.omega);
    if (m->ramp_active && m->ramp_dur > 0) {
        double fr = (m->st.tau - m->ramp_tau0) / m->ramp_dur;
        fr_put(f, 36, "  ramp %s %.4g->%.4g %.0f%%", m->ramp_param, m->ramp_from, m->ramp_to,
               100 * fmin(1, fmax(0, fr)));
    }
    fr_nl(f);
}

static void draw_motion(mon *m, frame *f, double now)
{
    long j0 = ring_from(m->pc_t, m->pc_n, PC_CAP, now - m->o.window_s), n = m->pc_n - j0;
    long imp = 0, mot[3] = {0, 0, 0};
    for (long j = j0; j < m->pc_n; j++) {
        imp += m->pc_imp[j % PC_CAP];
        int c = m->pc_mot[j % PC_CAP];
        mot[c < 0 ? 0 : c > 2 ? 2 : c]++;
    }
    int worst = mot[2] ? 2 : mot[1] ? 1 : 0;
    fr_put(f, 0, "motion  daemon: %s, %.3g impacts/period", m->st.motion, m->st.imp_pp);
    if (n)
        fr_put(f, 0, "; last %.3g s: %s, %.3g impacts/period (periods none/single/double "
               "%ld/%ld/%ld)", m->o.window_s, wg_motion_name(worst), (double)imp / n, mot[0], mot[1], mot[2]);
    fr_nl(f);
    double resid = 0;
    int per = m->ny >= 16 ? wg_period_detect(m->ys, m->ny, m->ydim, WG_PERIOD_MAX,
                                             m->o.tol, &resid)
                          : -1;
    fr_put(f, 0, "regime  daemon: %s  local: ", m->st.regime);
    if (per > 0)
        fr_put(f, 32, "period-%d", per);
    else if (per == 0)
        fr_put(f, 35, "aperiodic (no period <= %d)", WG_PERIOD_MAX);
    else
        fr_put(f, 0, "(collecting %d/16 sections)", m->ny);
    if (per >= 0)
        fr_put(f, 0, " over %d sections, resid %.2g, tol %.2g", m->ny, resid, m->o.tol);
    fr_nl(f);
}

static void draw_msgs(mon *m, frame *f)
{
    long drop = 0;
    fr_put(f, 0, "msgs   ");
    for (int k = 0; k < NCH; k++) {
        drop += m->sc[k].seq.missing;
        fr_put(f, 0, " %s %lld", ch_suffix[k], (long long)m->sc[k].count);
        if (m->sc[k].seq.missing)
            fr_put(f, 33, " (-%lld)", (long long)m->sc[k].seq.missing);
        if (m->sc[k].bad)
            fr_put(f, 31, " (%lld undecodable)", (long long)m->sc[k].bad);
    }
    fr_put(f, drop ? 33 : 0, "  dropped %ld", drop);
    fr_put(f, 0, "  daemon-side %lld  cmds %lld/%lld refused  mesh impacts %ld",
           (long long)m->st.dropped, (long long)m->st.acc, (long long)m->st.ref,
           m->contacts[WG_C_MESH][WG_EV_DRIVE_IMPACT] + m->contacts[WG_C_MESH][WG_EV_BACK_IMPACT]);
    fr_nl(f);
}

/* A character canvas: w x h cells. */
typedef struct canvas { int w, h; char *c; } canvas;

static void cv_mark(canvas *cv, int x, int y, char ch)
{
    if (x >= 0 && x < cv->w && y >= 0 && y < cv->h)
        cv->c[y * cv->w + x] = ch;
}

/* Scrolling x_n trace: each column the min..max of its samples. */
static void plot_trace(mon *m, canvas *cv, double now, double *lo, double *hi)
{
    long j0 = ring_from(m->tr_t, m->tr_n, TR_CAP, now - m->o.window_s), n = m->tr_n - j0;
    *lo = INFINITY, *hi = -INFINITY;
    for (long j = j0; j < m->tr_n; j++)
        *lo = fmin(*lo, m->tr_x[j % TR_CAP]), *hi = fmax(*hi, m->tr_x[j % TR_CAP]);
    if (n < 1)
        return;
    if (*hi - *lo < 1e-9)
        *lo -= 0.5, *hi += 0.5;
    long per = (n + cv->w - 1) / cv->w;
    int x0 = cv->w - (int)((n + per - 1) / per); /* newest at the right edge */
    for (long b = 0; b * per < n; b++) {
        double a = INFINITY, z = -INFINITY;
        for (long j = j0 + b * per; j < j0 + (b + 1) * per && j < m->tr_n; j++)
            a = fmin(a, m->tr_x[j % TR_CAP]), z = fmax(z, m->tr_x[j % TR_CAP]);
        int ya = (int)lround((*hi - a) / (*hi - *lo) * (cv->h - 1));
        int yz = (int)lround((*hi - z) / (*hi - *lo) * (cv->h - 1));
        for (int y = yz; y <= ya; y++)
            cv_mark(cv, x0 + (int)b, y, ya == yz ? '-' : '|');
    }
}

/* Poincare scatter x_n' (up) against x_n (right), density shaded. */
static void plot_scatter(mon *m, canvas *cv, double now, double box[4], long *npts)
{
    static const char shade[] = ".:oO#@";
    long j0 = ring_from(m->pc_t, m->pc_n, PC_CAP, now - m->o.window_s);
    double x0 = INFINITY, x1 = -INFINITY, v0 = INFINITY, v1 = -INFINITY;
    for (long j = j0; j < m->pc_n; j++) {
        long i = j % PC_CAP;
        x0 = fmin(x0, m->pc_x[i]), x1 = fmax(x1, m->pc_x[i]);
        v0 = fmin(v0, m->pc_v[i]), v1 = fmax(v1, m->pc_v[i]);
    }
    *npts = m->pc_n - j0;
    if (*npts < 1)
        return;
    double px = fmax(1e-6, 0.05 * (x1 - x0)), pv = fmax(1e-6, 0.05 * (v1 - v0));
    x0 -= px, x1 += px, v0 -= pv, v1 += pv;
    box[0] = x0, box[1] = x1, box[2] = v0, box[3] = v1;
    for (long j = j0; j < m->pc_n; j++) {
        long i = j % PC_CAP;
        int x = (int)((m->pc_x[i] - x0) / (x1 - x0) * cv->w);
        int y = (int)((v1 - m->pc_v[i]) / (v1 - v0) * cv->h);
        if (x < 0 || x >= cv->w || y < 0 || y >= cv->h)
            continue;
        char *c = &cv->c[y * cv->w + x];
        const char *p = strchr(shade, *c);
        *c = *c == ' ' ? shade[0] : p && p[1] ? p[1] : *c;
    }
}

static void draw_plots(mon *m, frame *f, double now, int h)
{
    int side = f->cols >= 100, wl = side ? (f->cols - 12) / 2 : f->cols - 9, hh = side ? h - 2 : (h - 4) / 2;
    if (hh < 3 || wl < 20)
        return;
    canvas a = {wl, hh, malloc((size_t)(wl * hh))}, b = {side ? wl : wl, hh, malloc((size_t)(wl * hh))};
    if (!a.c || !b.c) {
        free(a.c), free(b.c);
        return;
    }
    memset(a.c, ' ', (size_t)(wl * hh));
    memset(b.c, ' ', (size_t)(wl * hh));
    double lo, hi, box[4] = {0, 1, 0, 1};
    long np;
    plot_trace(m, &a, now, &lo, &hi);
    plot_scatter(m, &b, now, box, &np);
    const canvas *cv[2] = {&a, &b};
    for (int p = 0; p < (side ? 1 : 2); p++) {
        if (side)
            fr_put(f, 1, "%-*s   %s", wl + 8, "x_n trace", "Poincare section: x_n' (up) vs x_n (right)");
        else
            fr_put(f, 1, p ? "Poincare section: x_n' (up) vs x_n (right)" : "x_n trace");
        fr_put(f, 0, "  last %g s, %ld sections", m->o.window_s, np);
        fr_nl(f);
        for (int y = 0; y < hh; y++) {
            for (int q = side ? 0 : p; q <= (side ? 1 : p); q++) {
                double top = q ? box[3] : hi, bot = q ? box[2] : lo;
                if (y == 0 || y == hh - 1)
                    fr_put(f, 0, "%7.4g ", y ? bot : top);
                else
                    fr_put(f, 0, "        ");
                fr_put(f, 0, "%.*s", cv[q]->w, cv[q]->c + y * cv[q]->w);
                if (side && !q)
                    fr_put(f, 0, "  ");
            }
            fr_nl(f);
        }
        if (side || p)
            fr_put(f, 0, "%*s%-*.4g%*.4g", side ? wl + 18 : 8, "", side ? wl / 2 : wl / 2, box[0],
                   wl - wl / 2, box[1]);
        if (side || p)
            fr_nl(f);
    }
    free(a.c), free(b.c);
}

static void render(mon *m, frame *f)
{
    double now = cli_mono_s();
    f->len = 0, f->col = 0, f->cols = m->cols;
    if (!f->plain)
        fr_raw(f, "\033[H", 3);
    draw_header(m, f, now);
    if (m->have_status) {
        draw_params(m, f);
        draw_motion(m, f, now);
        draw_msgs(m, f);
        draw_plots(m, f, now, m->rows - 10);
    }
    fr_put(f, 0, "%s", f->plain ? "" : m->frozen ? "-- frozen -- space: resume  q: quit  c: clear" : "q: quit  c: clear  space: freeze");
    if (!f->plain)
        fr_raw(f, "\033[K\033[J", 6);
    else
        fr_nl(f);
    fwrite(f->buf, 1, f->len, stdout);
    fflush(stdout);
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

static void term_enter(mon *m)
{
    if (m->o.plain)
        return;
    if (isatty(STDIN_FILENO) && tcgetattr(STDIN_FILENO, &m->tio) == 0) {
        struct termios t = m->tio;
        t.c_lflag &= ~(tcflag_t)(ICANON | ECHO);
        t.c_cc[VMIN] = 0;
        t.c_cc[VTIME] = 0;
        m->raw = tcsetattr(STDIN_FILENO, TCSANOW, &t) == 0;
    }
    fputs("\033[?1049h\033[?25l\033[2J", stdout);
}

static void term_leave(mon *m)
{
    if (m->o.plain)
        return;
    if (m->raw)
        tcsetattr(STDIN_FILENO, TCSANOW, &m->tio);
    fputs("\033[?25h\033[?1049l", stdout);
    fflush(stdout);
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

/* Handle LCM and keys until `until` (monotonic seconds) or quit. */
static void pump(mon *m, double until)
{
    int lfd = lcm_get_fileno(m->c.lcm), kfd = m->raw ? STDIN_FILENO : -1;
    for (double left; !g_quit && (left = until - cli_mono_s()) > 0;) {
        fd_set set;
        FD_ZERO(&set);
        FD_SET(lfd, &set);
        if (kfd >= 0)
            FD_SET(kfd, &set);
        struct timeval tv = {(long)left, (long)((left - floor(left)) * 1e6)};
        int n = select((lfd > kfd ? lfd : kfd) + 1, &set, NULL, NULL, &tv);
        if (n > 0 && FD_ISSET(lfd, &set))
            lcm_handle(m->c.lcm);
        if (n > 0 && kfd >= 0 && FD_ISSET(kfd, &set))
            key(m);
        if (g_winch)
            return;
    }
}

static int run(mon *m)
{
    frame f = {.plain = m->o.plain};
    double next = cli_mono_s();
    if (m->o.frames) { /* headless: first wait for a heartbeat */
        double end = cli_mono_s() + m->o.timeout_s;
        while (!m->have_status && !g_quit && cli_mono_s() < end)
            pump(m, fmin(end, cli_mono_s() + 0.05));
        /* a little data for the plots, PARAMS and the local period detection */
        for (end = cli_mono_s() + 1.5; m->have_status && !g_quit && cli_mono_s() < end &&
                                  (m->ny < 24 || !m->have_params);)
            pump(m, fmin(end, cli_mono_s() + 0.05));
        next = cli_mono_s();
    }
    term_enter(m);
    for (int n = 0; !g_quit && (!m->o.frames || n < m->o.frames); n++) {
        if (g_winch) {
            g_winch = 0;
            term_size(m);
            if (!m->o.plain)
                fputs("\033[2J", stdout);
        }
        render(m, &f);
        next += 1.0 / m->o.fps;
        if (!m->o.frames || n + 1 < m->o.frames)
            pump(m, next);
    }
    term_leave(m);
    free(f.buf);
    return m->o.frames && !m->have_status ? 1 : 0;
}

static int setup(mon *m)
{
    char why[256], ch[128];
    if (bus_open(&m->c, m->o.url, m->o.prefix, "wgmon", why, sizeof why)) {
        fprintf(stderr, "wgmon: %s\n", why);
        return 1;
    }
    for (int k = 0; k < NCH; k++)
        m->subs[k] = lcm_subscribe(m->c.lcm, bus_channel(&m->c, ch_suffix[k], ch, sizeof ch),
                                   on_raw, m);
    ask_params(m);
    m->tr_t = malloc(sizeof(double) * TR_CAP);
    m->tr_x = malloc(sizeof(double) * TR_CAP);
    m->pc_t = malloc(sizeof(double) * PC_CAP);
    m->pc_x = malloc(sizeof(double) * PC_CAP);
    m->pc_v = malloc(sizeof(double) * PC_CAP);
    m->pc_imp = malloc(sizeof(int) * PC_CAP);
    m->pc_mot = malloc(sizeof(int) * PC_CAP);
    if (!m->tr_t || !m->tr_x || !m->pc_t || !m->pc_x || !m->pc_v || !m->pc_imp || !m->pc_mot) {
        fprintf(stderr, "wgmon: out of memory\n");
        return 1;
    }
    return 0;
}

static void teardown(mon *m)
{
    bus_close(&m->c);
    free(m->tr_t), free(m->tr_x), free(m->pc_t), free(m->pc_x), free(m->pc_v);
    free(m->pc_imp), free(m->pc_mot);
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
        struct sigaction sa = {.sa_handler = on_signal};
        sigaction(SIGINT, &sa, NULL);
        sigaction(SIGTERM, &sa, NULL);
        sigaction(SIGWINCH, &sa, NULL);
        signal(SIGPIPE, SIG_IGN);
        term_size(m);
        rc = setup(m);
        if (!rc)
            rc = run(m);
        teardown(m);
    }
    free(m);
    return rc;
}

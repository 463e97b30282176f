/* wgrig - the automated test rig: drive a parameter of a running wormgeard
 * through a range over LCM (stepwise with a settle time in mesh periods, or
 * as a slow ramp), read the POINCARE and CONTACT streams, and write the
 * bifurcation diagram, the points (same CSV/JSON/Markdown/PNG writers and the
 * same per-point analysis as wgsweep), every section received, and the
 * impacts-per-period curve. Dropped messages are counted and the recording
 * re-waited; refusals are reported and the point skipped.
 * Exit 0, 1 runtime error (no daemon, stalled), 2 usage error, 130 Ctrl-C. */
#include "cli.h"
#include "plot.h"
#include "plot_text.h"
#include "rig_ana.h"
#include "rig_imp.h"
#include "rig_opt.h"
#include "sweep_md.h"
#include "sweep_out.h"
#include "bus.h"
#include "bus_msg.h"

#include "lcmtypes/wormgear_contact_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_status.h"
#include "wormgear/wg_writer.h"

#include <math.h>
#include <poll.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>

enum { RAMP_MAX = 1 << 20, STOPPED = -1000 };
enum { OUT_QUEUE = 1 << 16 }; /* bytes of messages the writer holds for stderr */
static volatile sig_atomic_t g_stop; /* set by SIGINT/SIGTERM only */

typedef struct collector { /* what the POINCARE handler does with sections */
    int active, ramp;
    double min_tau, end_tau;  /* sections after min_tau; ramp: until end_tau */
    int skip, want;           /* discard skip sections, then record want */
    int64_t last_period;
    int have_last;
    int64_t after_period;     /* record only periods after this (-1: any) */
    long breaks;              /* recordings restarted on a gap */
    double last_at;           /* wall time of the last section */
} collector;

typedef struct window { int64_t p0, p1; int n; } window; /* periods recorded for a point */

typedef struct rig {
    bus c;
    rig_opts o;
    wg_sweep_opts so;
    wg_params base;
    wg_params scene_p;        /* the figures' reference: the scene's own values */
    units_scale us;           /* the daemon's scale (PARAMS): the figures' Hz and µm */
    int pid, model, stepper, steps, nstate, have_params, have_status;
    char scene[64], mode[16], orig_mode[16];
    double rate, orig_rate, omega_n, orig;
    collector col;
    rig_rec rec;
    double *rval;             /* ramp: value of each recorded section */
    FILE *secf;               /* every section received while collecting */
    const char *phase_dir;
    int phase_idx;
    double phase_value;
    bus_seq pc_seq, ct_seq;   /* POINCARE, CONTACT: .missing = dropped */
    long refusals, timeouts, unsent, skipped, bad_params; /* the last: PARAMS no daemon sends */
    rig_imp imp;              /* mesh impacts from CONTACT */
    double t0;
    int done, total, restoring; /* restoring: finish()'s commands, sent even after a stop */
    int sent;                 /* a set or ramp of the swept parameter went out: restore it */
    wg_writer *out;           /* stderr during the sweep: a terminal that takes nothing stops
                                 no sweep (say) */
} rig;

/* The first Ctrl-C, SIGTERM or SIGHUP stops the sweep, which then puts the
 * daemon back (value, mode) and writes its outputs; a second one ends
 * wgrig at once. */
static void on_signal(int sig) { g_stop = 1, signal(sig, SIG_DFL); }

/* A message's leading newline ends a progress bar: on a terminal only
 * (elsewhere each message had a blank line before it). */
#define NL (isatty(STDERR_FILENO) ? "\n" : "")

#define PROG "wgrig"

/* A message on stderr, through the writer while the sweep runs: a terminal
 * stopped with Ctrl-S, a stalled ssh session or a pipe no one reads would
 * otherwise stop the loop in write(), and with it the sweep (its ACKs and
 * sections unread, the daemon left at one value, in fast mode). A line the
 * writer's queue cannot hold is dropped and counted. */
static void say(rig *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));
static void say(rig *r, const char *fmt, ...)
{
    char line[1024];
    va_list ap;
    va_start(ap, fmt);
    int n = vsnprintf(line, sizeof line, fmt, ap);
    va_end(ap);
    size_t len = n < 0 ? 0 : (size_t)n < sizeof line ? (size_t)n : sizeof line - 1;
    if (!len)
        return;
    if (r->out)
        wg_writer_put(r->out, STDERR_FILENO, line, len);
    else
        fputs(line, stderr);
}

/* ---- messages ---------------------------------------------------------------- */

static void write_section(rig *r, const wormgear_poincare_t *m, int i, const char *what)
{
    if (!r->secf)
        return;
    fprintf(r->secf, "%s,%d,%.10g,%s,%lld,%.12g,%.12g,%.12g,%.12g,%.12g,%.12g,%d,%d\n",
            r->phase_dir, r->phase_idx, r->phase_value, what, (long long)m->period[i],
            m->tau[i], m->omega[i], m->xn[i], m->dxn[i], m->min_xn[i], m->max_xn[i],
            m->motion[i], m->impacts[i]);
}

/* One section into the collector: skip, record, or restart on a gap. */
static void collect_one(rig *r, const wormgear_poincare_t *m, int i)
{
    collector *c = &r->col;
    if (!c->active || m->tau[i] <= c->min_tau || m->nstate != r->nstate ||
        m->period[i] <= c->after_period)
        return;
    c->last_at = cli_mono_s();
    if (c->have_last && m->period[i] != c->last_period + 1 && !c->ramp && c->skip == 0 &&
        r->rec.n > 0) {
        r->rec.n = 0; /* a gap: the period test needs consecutive sections */
        c->breaks++;
    }
    c->last_period = m->period[i], c->have_last = 1;
    if (c->skip > 0) {
        c->skip--;
        write_section(r, m, i, "settle");
        return;
    }
    wg_period st = {(uint64_t)m->period[i], m->min_xn[i], m->max_xn[i], m->motion[i], m->impacts[i],
                    {0}, {0}};
    for (int j = 0; j < m->nbearing && j < WG_NBEARING; j++)
        st.bimpacts[j] = m->bearing_impacts[i][j], st.bvmax[j] = m->bearing_vmax[i][j];
    if (c->ramp) {
        if (m->tau[i] > c->end_tau) {
            c->active = 0;
            return;
        }
        double f = (m->tau[i] - c->min_tau) / (c->end_tau - c->min_tau);
        r->rval[r->rec.n] = r->pid == WG_P_OMEGA ? m->omega[i] : r->o.from + f * (r->o.to - r->o.from);
    }
    write_section(r, m, i, "record");
    rig_rec_push(&r->rec, m->y[i], &st, m->xn[i], m->dxn[i], m->period[i]);
    if (r->rec.n >= c->want)
        c->active = 0;
}

static void on_poincare(rig *r, const wormgear_poincare_t *m)
{
    bus_seq_note(&r->pc_seq, m->seq);
    for (int i = 0; i < m->n; i++)
        collect_one(r, m, i);
}

static void on_contact(rig *r, const wormgear_contact_t *m)
{
    int gap = bus_seq_note(&r->ct_seq, m->seq) > 0;
    if (gap && m->n > 0) /* what was lost lies between the last event heard and this one */
        rig_imp_lose(&r->imp, m->period[0]);
    if (gap && r->col.active && !r->col.ramp && m->n > 0) {
        /* lost impacts: record again, from periods after every event the
         * lost message can have held */
        r->rec.n = 0;
        r->col.breaks++;
        r->col.after_period = m->period[m->n - 1];
    }
    if (m->n > 0)
        rig_imp_heard(&r->imp, m->period[m->n - 1]);
    for (int i = 0; i < m->n; i++) {
        if (m->contact[i] != WG_C_MESH ||
            (m->kind[i] != WG_EV_DRIVE_IMPACT && m->kind[i] != WG_EV_BACK_IMPACT))
            continue; /* mesh drive- or back-side impacts only */
        if (rig_imp_push(&r->imp, m->period[i]))
            return;
    }
}

static void on_params(rig *r, const wormgear_params_t *m)
{
    char line[160];
    if (bus_params_ignore(m, &r->bad_params, "wgrig", line, sizeof line)) {
        say(r, "%s", line);
        return;
    }
    wg_params_default(&r->base);
    for (int i = 0; i < m->n; i++) {
        int id = wg_param_lookup(m->name[i]);
        if (id >= 0)
            r->base.v[id] = m->value[i];
    }
    r->model = wg_model_lookup(m->model); /* known: bus_params_ignore checked it */
    r->stepper = wg_stepper_lookup(m->stepper);
    r->steps = m->steps_per_period;
    r->nstate = wg_model_nstate(r->model);
    r->omega_n = m->omega_n_rad_s;
    r->us = plot_text_scale(m->omega_n_rad_s, m->length_m, m->mesh_stiffness_N_m);
    cli_text(r->scene, sizeof r->scene, m->scene); /* into captions and CSVs: text only */
    r->have_params = 1;
}

static void on_status(rig *r, const wormgear_status_t *m)
{
    snprintf(r->mode, sizeof r->mode, "%s", m->mode);
    r->rate = m->rate;
    r->have_status = 1;
}

#define DECODE(T, TYPE, fn)                                                                \
    do {                                                                                   \
        T msg; /* its bytes checked first: bus_msg.h */                                    \
        if (!BUS_DECODE(T, TYPE, rb, &msg))                                                \
            fn(r, &msg), T##_decode_cleanup(&msg);                                         \
    } while (0)

static void on_raw(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    rig *r = u;
    const char *s = ch + strlen(r->c.prefix);
    /* with a key, the daemon's only: the sections are what it records, and the
     * restore at the end sends what PARAMS and STATUS said */
    if (!strcmp(s, "POINCARE") && bus_signed(&r->c, BUS_POINCARE, rb))
        DECODE(wormgear_poincare_t, BUS_POINCARE, on_poincare);
    else if (!strcmp(s, "CONTACT") && bus_signed(&r->c, BUS_CONTACT, rb))
        DECODE(wormgear_contact_t, BUS_CONTACT, on_contact);
    else if (!strcmp(s, "PARAMS") && bus_signed(&r->c, BUS_PARAMS, rb))
        DECODE(wormgear_params_t, BUS_PARAMS, on_params);
    else if (!strcmp(s, "STATUS") && bus_signed(&r->c, BUS_STATUS, rb))
        DECODE(wormgear_status_t, BUS_STATUS, on_status);
}

/* ---- commands --------------------------------------------------------------------- */

static int flag_true(void *p) { return *(int *)p; }

/* Send cmd and wait for its ACK (re-sent after a timeout). 0 accepted, 1
 * refused (reason printed), -1 no answer. */
static int command(rig *r, wormgear_cmd_t *cmd, const char *what)
{
    int refused = 0;
    int tried = 0, unsent = 0;
    for (int attempt = 0; attempt <= r->o.retries && (!g_stop || r->restoring); attempt++) {
        tried++;
        if (bus_send(&r->c, cmd) < 0) { /* the network, for now: tried again after a wait */
            unsent++;
            r->unsent++;
            if (attempt < r->o.retries) {
                say(r, "%swgrig: %s not sent: %s; trying again in %g s\n", NL, what,
                    r->c.send_why, r->o.timeout_s);
                bus_wait(&r->c, (int)(r->o.timeout_s * 1000), NULL, NULL);
            }
            continue;
        }
        if (bus_wait_ack(&r->c, (int)(r->o.timeout_s * 1000))) {
            r->timeouts++;
            continue;
        }
        if (r->c.ack.accepted)
            return 0;
        r->refusals++, refused = 1;
        say(r, "%swgrig: %s refused (%s): %s\n", NL, what, r->c.ack.code, r->c.ack.message);
        if (strcmp(r->c.ack.code, "ESTATE") != 0 || strstr(r->c.ack.message, "accept_commands"))
            return 1; /* permanent: bad name or value, commands off; ESTATE ("not now") is
                         retried */
        bus_wait(&r->c, 200, NULL, NULL);
    }
    if (refused || !tried) /* !tried: stopped before sending, nothing to say */
        return refused ? 1 : -1;
    char hint[1024];
    if (unsent == tried)
        say(r, "%swgrig: %s: not sent in %d tries: %s\n", NL, what, tried, r->c.send_why);
    else
        say(r, "%swgrig: %s: no ACK after %d tries of %g s%s%s: %s\n", NL, what, tried,
            r->o.timeout_s, unsent ? "; the last that could not be sent: " : "",
            unsent ? r->c.send_why : "", bus_hint(&r->c, hint, sizeof hint));
    return -1;
}

/* Set the swept parameter at the next Poincare section (psi = 0), as the
 * offline chain changes it: each point starts from the previous point's
 * state on the section, not from wherever in the period the command lands. */
static int set_value(rig *r, double v, int at_section)
{
    char *names[1] = {(char *)r->o.param}, what[96];
    wormgear_cmd_t c = bus_cmd("set");
    c.nparams = 1, c.names = names, c.values = &v, c.at_section = (int8_t)at_section;
    snprintf(what, sizeof what, "set %s=%.10g", r->o.param, v);
    return command(r, &c, what);
}

static int set_mode(rig *r, const char *mode, double rate)
{
    wormgear_cmd_t c = bus_cmd("mode");
    c.name = (char *)mode, c.rate = rate;
    return command(r, &c, "mode");
}

/* The daemon's parameters, model and N (a `get` makes PARAMS come now). */
static int fetch_params(rig *r)
{
    wormgear_cmd_t c = bus_cmd("get");
    if (command(r, &c, "get"))
        return -1;
    if (bus_wait(&r->c, (int)(r->o.timeout_s * 1000), flag_true, &r->have_params) ||
        (r->o.fast && bus_wait(&r->c, 3000, flag_true, &r->have_status))) {
        char hint[1024];
        say(r, "wgrig: no %s on %s%s: %s\n", r->have_params ? "STATUS" : "PARAMS", r->c.prefix,
            r->have_params ? "STATUS" : "PARAMS", bus_hint(&r->c, hint, sizeof hint));
        return -1;
    }
    return 0;
}

/* Pump LCM until the collector is done. 0, or -1 stalled/interrupted. */
static int collect(rig *r, int skip, int want)
{
    collector *c = &r->col;
    c->skip = skip, c->want = want, c->have_last = 0, c->active = 1, c->last_at = cli_mono_s();
    c->after_period = -1;
    r->rec.n = 0;
    long breaks0 = c->breaks;
    while (c->active && !g_stop) {
        bus_wait(&r->c, 100, NULL, NULL);
        if (cli_mono_s() - c->last_at > r->o.stall_s) {
            say(r, "%swgrig: no POINCARE section for %g s (daemon paused, stopped, or "
                            "publishing elsewhere?)\n", NL, r->o.stall_s);
            break;
        }
        if (c->ramp && !r->o.quiet && isatty(STDERR_FILENO) && r->rec.n)
            say(r, "\rramp %s: %s = %.6g, %d sections\033[K", r->phase_dir, r->o.param,
                    r->rval[r->rec.n - 1], r->rec.n);
        if (c->breaks - breaks0 > r->o.retries) {
            say(r, "%swgrig: recording broken by dropped sections %ld times\n", NL,
                    c->breaks - breaks0);
            break;
        }
    }
    int ok = !c->active;
    c->active = 0;
    return ok ? 0 : -1;
}

/* ---- points ------------------------------------------------------------------------ */

static void progress(rig *r, const char *dir, const wg_point *pt)
{
    if (r->o.quiet)
        return;
    char lab[32], bar[41];
    int w = 30, k = r->total ? w * r->done / r->total : w;
    for (int i = 0; i < w; i++)
        bar[i] = i < k ? '#' : '.';
    bar[w] = 0;
    int tty = isatty(STDERR_FILENO);
    char what[96] = "refused, not measured";
    if (wg_point_measured(pt))
        snprintf(what, sizeof what, "%s %s %.3g imp/T", out_label(pt, lab, sizeof lab),
                 wg_motion_name(pt->motion), pt->impacts);
    say(r, "%s[%s] %d/%d %s %s=%.6g %s | drops %ld refused %ld | %.0f s%s", tty ? "\r" : "", bar,
        r->done, r->total, dir, r->o.param, pt->value, what, r->pc_seq.missing, r->refusals,
        cli_mono_s() - r->t0, tty ? "\033[K" : "\n");
}

/* Analyse the point at value v the way wg_point_run does: settle, record,
 * period; extend; else LLE, skip lle_periods, record, classify. 0 done, 1
 * skipped (refused), -1 stop the sweep. */
static int run_point(rig *r, double v, wg_point *pt, window *win)
{
    char why[256] = "";
    r->sent = 1;
    int rc = set_value(r, v, 1);
    memset(pt, 0, sizeof *pt);
    pt->value = v, pt->lle = NAN, pt->min_xn = pt->max_xn = NAN;
    if (rc)
        return rc > 0 ? (r->skipped++, 1) : -1;
    r->col.min_tau = r->c.ack.tau;
    rig_ana a;
    wg_params p = r->base;
    p.v[r->pid] = v;
    rig_ana_init(&a, &p, r->model, r->stepper, r->steps, &r->so);
    int n = collect(r, r->o.settle, r->o.record) ? STOPPED : rig_ana_period(&a, &r->rec, 0, pt, why, sizeof why);
    for (int at = 1; n == 0 && at <= r->o.extend; at++)
        n = collect(r, r->o.settle, r->o.record) ? STOPPED : rig_ana_period(&a, &r->rec, at, pt, why, sizeof why);
    if (n == 0 && r->o.lle) {
        n = rig_ana_lle(&a, &r->rec, pt, why, sizeof why);
        if (!n && !(n = collect(r, r->so.lle_periods, r->o.record) ? STOPPED : 0))
            rig_ana_aperiodic(&a, &r->rec, pt);
    }
    rig_ana_fini(&a);
    if (n < 0 && n != WG_ENONFINITE) {
        if (n != STOPPED)
            say(r, "%swgrig: %s=%g: %s\n", NL, r->o.param, v, why);
        return -1;
    }
    rig_rec_fill(&r->rec, pt);
    pt->value = v;
    if (r->rec.n)
        *win = (window){r->rec.period[0], r->rec.period[r->rec.n - 1], r->rec.n};
    return 0;
}

static int run_chain(rig *r, wg_chain *ch, window *win)
{
    const char *dir = ch->dir > 0 ? "up" : "down";
    for (int i = 0; i < ch->npts && !g_stop; i++) {
        r->phase_dir = dir, r->phase_idx = i, r->phase_value = wg_chain_value(ch, i);
        int rc = run_point(r, r->phase_value, &ch->pts[i], &win[i]);
        if (rc < 0)
            return -1;
        ch->ndone = i + 1;
        r->done++;
        progress(r, dir, &ch->pts[i]);
    }
    return g_stop ? -1 : 0;
}

/* Send the ramp a -> b and record its sections (value of each in rval):
 * 0, 1 when the recording was cut short (stalled, interrupted), or -1 with
 * nothing recorded. */
static int ramp_record(rig *r, double a, double b)
{
    char *names[1] = {(char *)r->o.param};
    wormgear_cmd_t c = bus_cmd("ramp");
    c.nparams = 1, c.names = names, c.values = &b, c.has_from = 1, c.from = a;
    c.duration = r->o.ramp, c.unit = (char *)r->o.unit;
    double dur_tau = strcmp(r->o.unit, "tau") ? r->o.ramp * r->omega_n : r->o.ramp;
    r->sent = 1;
    if (command(r, &c, "ramp"))
        return -1;
    r->col = (collector){.ramp = 1, .after_period = -1, .min_tau = r->c.ack.tau,
                         .end_tau = r->c.ack.tau + dur_tau, .breaks = r->col.breaks};
    double save_from = r->o.from, save_to = r->o.to;
    r->o.from = a, r->o.to = b; /* the value of a section of a non-omega ramp */
    int rc = collect(r, 0, r->rec.cap);
    r->o.from = save_from, r->o.to = save_to;
    return !rc ? 0 : r->rec.n ? 1 : -1;
}

/* Point i of a ramped chain from the sections within w/2 of its value. */
static void ramp_bin(rig *r, wg_chain *ch, int i, double w, window *win)
{
    double v = wg_chain_value(ch, i);
    int k0 = -1, k1 = -1; /* sections whose value falls in bin i */
    for (int k = 0; k < r->rec.n; k++)
        if (fabs(r->rval[k] - v) <= w / 2 && (k0 < 0 ? (k0 = k) : 1))
            k1 = k;
    wg_point *pt = &ch->pts[i];
    memset(pt, 0, sizeof *pt);
    pt->value = v, pt->lle = NAN;
    if (k0 < 0)
        return;
    rig_rec view = rig_rec_slice(&r->rec, k0, k1);
    wg_params p = r->base;
    p.v[r->pid] = v;
    rig_ana an;
    char why[160];
    rig_ana_init(&an, &p, r->model, r->stepper, r->steps, &r->so);
    if (view.n >= 2 && rig_ana_period(&an, &view, 0, pt, why, sizeof why) == 0)
        pt->regime = WG_REGIME_NONE; /* no period on a ramp: not classified */
    rig_ana_fini(&an);
    rig_rec_fill(&view, pt);
    pt->value = v;
    win[i] = (window){view.period[0], view.period[view.n - 1], view.n};
}

/* Ramp one direction, then bin the sections into the chain's points. */
static int run_ramp(rig *r, wg_chain *ch, window *win)
{
    double a = wg_chain_value(ch, 0), b = wg_chain_value(ch, ch->npts - 1);
    r->phase_dir = ch->dir > 0 ? "up" : "down", r->phase_idx = -1, r->phase_value = NAN;
    int rc = ramp_record(r, a, b);
    if (rc < 0)
        return -1;
    double w = fabs(b - a) / (ch->npts - 1); /* bins centred on the grid values */
    for (int i = 0; i < ch->npts; i++) {
        ramp_bin(r, ch, i, w, win);
        ch->ndone = i + 1;
        r->done++;
        progress(r, r->phase_dir, &ch->pts[i]);
    }
    return rc ? -1 : 0;
}

/* ---- outputs --------------------------------------------------------------------------- */

static int write_impacts(rig *r, const sweep_study *st, wg_chain *ch[2], window *win[2],
                         char *why, size_t whylen)
{
    char path[1024];
    snprintf(path, sizeof path, "%s-impacts.csv", r->o.out);
    FILE *f = out_open(path, why, whylen);
    if (!f)
        return -1;
    fprintf(f, "dir,index,%s,impacts_per_period,contact_impacts_per_period,periods,motion,regime,"
               "period\n", r->o.param);
    int n = 0, nup = 0, npts = (ch[0] ? ch[0]->ndone : 0) + (ch[1] ? ch[1]->ndone : 0);
    double *x = calloc((size_t)npts + 1, sizeof *x), *y = calloc((size_t)npts + 1, sizeof *y);
    for (int d = 0; d < 2; d++)
        for (int i = 0; ch[d] && i < ch[d]->ndone; i++) {
            const wg_point *p = &ch[d]->pts[i];
            const window *w = &win[d][i];
            /* empty when CONTACT messages were lost inside the window (after
             * its recording ended: no way to record it again) */
            int lost = w->n && rig_imp_lost(&r->imp, w->p0, w->p1);
            double ci = w->n ? (double)rig_imp_count(&r->imp, w->p0, w->p1) / w->n : NAN;
            char cs[32] = "";
            if (!lost)
                snprintf(cs, sizeof cs, "%.6g", ci);
            if (!wg_point_measured(p)) /* refused: its value, no measurement */
                fprintf(f, "%s,%d,%.10g,,,0,,%s,\n", d ? "down" : "up", i, p->value,
                        wg_regime_name(p->regime));
            else
                fprintf(f, "%s,%d,%.10g,%.6g,%s,%d,%s,%s,%d\n", d ? "down" : "up", i, p->value,
                        p->impacts, cs, w->n, wg_motion_name(p->motion),
                        wg_regime_name(p->regime), p->period);
            if (x && y && w->n)
                x[n] = p->value, y[n++] = p->impacts, nup += d == 0;
        }
    int rc = out_close(f, path, why, whylen);
    char title[160], xl[96], x2l[96], cap[2][400] = {"", ""};
    snprintf(title, sizeof title, "%s: mesh impacts per period vs %s (rig: %s)%s", r->scene,
             plot_text_psym(r->pid), r->o.up && r->o.down ? "up, then back down"
             : r->o.up ? "up" : "down", st->partial ? " (partial)" : "");
    const wg_params *p = ch[0] ? &ch[0]->base : ch[1] ? &ch[1]->base : &r->base;
    plot_text_caption_run(cap, r->scene, p, &r->scene_p, r->pid, -1, &r->so, r->steps,
                          r->steps, st->run);
    char note[160]; /* the markers named only when both sweeps are drawn (split) */
    snprintf(note, sizeof note, "counted from POINCARE over each %s%s", st->run ? "bin's sections"
             : "point's recorded periods", nup && nup < n ? "; up: dots, down: rings" : "");
    plot_xy px = {.title = title, .xlabel = plot_text_plabel(r->pid, xl, sizeof xl),
                  .ylabel = "mesh impacts per period  (-)", .x = x, .y = y, .n = n,
                  .split = nup > 0 && nup < n ? nup : 0,
                  .x2 = plot_text_pscale(r->pid, p, &r->us, x2l, sizeof x2l),
                  .pg = {NULL, {cap[0], cap[1], note, NULL}}};
    snprintf(path, sizeof path, "%s-impacts.png", r->o.out);
    if (!rc && n > 0)
        rc = plot_xy_write(path, &px, why, whylen);
    free(x), free(y);
    return rc;
}

static int write_outputs(rig *r, wg_chain *ch[2], window *win[2], int partial, const char *cmdline)
{
    char why[512] = "", path[1024], run[320];
    sweep_study st = {.scene = r->scene, .command = cmdline, .param = r->pid, .gparam = -1,
                      .ngroups = 1, .b = r->base.v[WG_P_B], .o = &r->so, .partial = partial,
                      .wall_s = cli_mono_s() - r->t0, .threads = 1, .pair = 1, .ranks = 1,
                      .scene_p = &r->scene_p, .us = r->us};
    if (r->o.ramp > 0) /* no per-point transient and record: the captions and .md say so */
        st.run = rig_ramp_text(&r->o, r->pid, r->base.v[WG_P_OMEGA], r->omega_n, run,
                               sizeof run);
    st.g[0] = (sweep_group){0, ch[0], ch[1]};
    int rc = 0;
    snprintf(path, sizeof path, "%s.csv", r->o.out);
    rc = rc ? rc : out_points_csv(path, &st, why, sizeof why);
    snprintf(path, sizeof path, "%s-poincare.csv", r->o.out);
    rc = rc ? rc : out_poincare_csv(path, &st, why, sizeof why);
    snprintf(path, sizeof path, "%s.json", r->o.out);
    rc = rc ? rc : out_json(path, &st, why, sizeof why);
    snprintf(path, sizeof path, "%s.md", r->o.out);
    rc = rc ? rc : md_write(path, &st, why, sizeof why);
    rc = rc ? rc : out_pngs(r->o.out, &st, NULL, why, sizeof why);
    rc = rc ? rc : write_impacts(r, &st, ch, win, why, sizeof why);
    if (rc)
        say(r, "wgrig: %s\n", why);
    return rc ? 1 : 0;
}

/* ---- main -------------------------------------------------------------------------------- */

/* Sections the record must hold: one point's, or a whole ramp's (counted
 * at its highest omega). 0, or 2 when the ramp is too long or too short. */
static int record_cap(const rig *r, int *cap)
{
    *cap = RIG_REC_CAP;
    if (r->o.ramp <= 0)
        return 0;
    double om = r->pid == WG_P_OMEGA ? fmax(r->o.from, r->o.to) : r->base.v[WG_P_OMEGA];
    double per = (strcmp(r->o.unit, "tau") ? r->o.ramp * r->omega_n : r->o.ramp) * om / (2 * M_PI);
    if (per > RAMP_MAX)
        return fprintf(stderr, "wgrig: --ramp: %.0f mesh periods per ramp, more than %d: "
                               "use a shorter ramp\n", per, RAMP_MAX), 2;
    if (per < 4.0 * r->o.bins)
        return fprintf(stderr, "wgrig: --ramp: %.0f mesh periods per ramp for %d bins: use a "
                               "longer ramp (at least 4 periods per bin)\n", per, r->o.bins), 2;
    *cap = (int)(1.1 * per) + 1000;
    return 0;
}

/* Open LCM, subscribe raw to what the rig reads, and ask for PARAMS. */
static int open_bus(rig *r)
{
    static const char *const chans[] = {"POINCARE", "CONTACT", "PARAMS", "STATUS"};
    char why[256];
    int brc = bus_open(&r->c, r->o.url, r->o.prefix, "wgrig", why, sizeof why);
    if (brc || (r->o.key_file && bus_set_key(&r->c, r->o.key_file, why, sizeof why)))
        return fprintf(stderr, "wgrig: %s\n", why), bus_exit_status(brc);
    for (int k = 0; k < 4; k++)
        bus_subscribe(&r->c, chans[k], on_raw, r, 4096);
    return fetch_params(r) ? 1 : 0;
}

static int setup(rig *r)
{
    char path[1024];
    int rc, cap;
    if ((rc = rig_check_opts(&r->o, &r->so, &r->pid)) || (rc = open_bus(r)))
        return rc;
    r->orig = r->base.v[r->pid];
    /* captions say what differs from the scene: its file when this host has it
     * (the name off the bus taken as a name, never a path), else the daemon's values */
    wg_scene sc;
    char why[300];
    int name = r->scene[0] && !wg_scene_is_file(r->scene);
    r->scene_p = name && wg_scene_open(&sc, r->scene, why, sizeof why) == WG_OK ? sc.p : r->base;
    r->so.steps = r->steps, r->so.model = r->model, r->so.stepper = r->stepper; /* the daemon's */
    if ((rc = record_cap(r, &cap)))
        return rc;
    if (rig_rec_init(&r->rec, r->nstate, cap) ||
        !(r->rval = malloc(sizeof(double) * (size_t)r->rec.cap)))
        return fprintf(stderr, "wgrig: out of memory\n"), 1;
    snprintf(path, sizeof path, "%s-sections.csv.part", r->o.out); /* renamed: sections_end */
    if (!(r->secf = fopen(path, "w")))
        return fprintf(stderr, "wgrig: cannot write %s\n", path), 1;
    fprintf(r->secf, "dir,index,%s,phase,period,tau,omega,x_n,dx_n,min_xn,max_xn,motion,impacts\n",
            r->o.param);
    snprintf(r->orig_mode, sizeof r->orig_mode, "%s", r->mode);
    r->orig_rate = r->rate;
    if (r->o.fast && set_mode(r, "fast", 0))
        return 1;
    return 0;
}

static void finish(rig *r)
{
    if (!r->c.lcm)
        return;
    r->restoring = 1; /* sent even after a stop (they were skipped: the daemon stayed fast,
                         at the sweep's last value) */
    if (g_stop && (r->o.fast || !r->o.keep))
        say(r, "%swgrig: stopped; putting the daemon back (a second Ctrl-C skips it)\n",
                NL);
    if (r->o.fast && r->have_status)
        set_mode(r, r->orig_mode, r->orig_rate);
    /* after a ramp too (it left the ramp's end value; a ramp still running when stopped is
     * cancelled by the set); after a point stopped before its end too */
    if (!r->o.keep && r->have_params && r->sent)
        set_value(r, r->orig, 0); /* now: at a section it would wait on a paused daemon */
    bus_wait(&r->c, 300, NULL, NULL); /* CONTACT batches still on their way */
}

/* The up and down chains asked for (ch[d] NULL when not), with a window
 * per point. */
static void make_chains(rig *r, wg_chain chains[2], wg_chain *ch[2], window *win[2])
{
    int npts = r->o.ramp > 0 ? r->o.bins : r->o.points;
    for (int d = 0; d < 2; d++) {
        if (!(d ? r->o.down : r->o.up))
            continue;
        chains[d] = (wg_chain){.base = r->base, .param = r->pid, .v0 = fmin(r->o.from, r->o.to),
                               .v1 = fmax(r->o.from, r->o.to), .npts = npts, .dir = d ? -1 : 1,
                               .param2 = -1, .pts = calloc((size_t)npts, sizeof(wg_point))};
        win[d] = calloc((size_t)npts, sizeof(window));
        ch[d] = &chains[d];
        r->total += npts;
    }
}

/* Close the sections file: PREFIX-sections.csv when keep (its error in why, -1), else
 * removed (an earlier run's file stays). */
static int sections_end(rig *r, int keep, char *why, size_t whylen)
{
    char part[1024], path[1024];
    snprintf(part, sizeof part, "%s-sections.csv.part", r->o.out);
    snprintf(path, sizeof path, "%s-sections.csv", r->o.out);
    int rc = out_close(r->secf, part, why, whylen);
    r->secf = NULL;
    if (!keep || rc)
        return remove(part), rc;
    if (rename(part, path))
        return snprintf(why, whylen, "cannot rename %s-sections.csv.part: %m", r->o.out), -1;
    return 0;
}

/* Points with recorded periods (not refused, not stopped before their record, not an
 * empty bin). */
static int measured(wg_chain *ch[2], window *win[2])
{
    int n = 0;
    for (int d = 0; d < 2; d++)
        for (int i = 0; ch[d] && i < ch[d]->ndone; i++)
            n += win[d][i].n > 0;
    return n;
}

/* The sweep is over, the daemon put back, the outputs written: the last
 * lines (the summary) are waited for as long as stderr takes (Ctrl-Q), or
 * until a second Ctrl-C or SIGTERM ends wgrig (the first stopped the
 * sweep; on_signal left the default action behind it). */
static void out_end(rig *r)
{
    struct pollfd p = {.fd = wg_writer_fd(r->out), .events = POLLIN};
    while (!wg_writer_idle(r->out))
        poll(&p, 1, -1);
    wg_writer_stop(r->out, 0);
    r->out = NULL;
}

/* Run the sweep, restore the daemon and write everything: the exit code. */
static int sweep(rig *r, wg_chain chains[2], window *win[2], const char *cmdline)
{
    wg_chain *ch[2] = {NULL, NULL};
    make_chains(r, chains, ch, win);
    if (!(r->out = wg_writer_start(OUT_QUEUE)) ||
        wg_writer_note(r->out, STDERR_FILENO, "wgrig: %lu lines not written: stderr took nothing "
                                              "(a stopped terminal, a pipe no one reads)\n")) {
        if (r->out)
            wg_writer_stop(r->out, 0);
        r->out = NULL;
        return fprintf(stderr, "wgrig: cannot start the writer of its messages\n"), 1;
    }
    int failed = 0;
    for (int d = 0; d < 2 && !failed; d++)
        if (ch[d])
            failed = r->o.ramp > 0 ? run_ramp(r, ch[d], win[d]) : run_chain(r, ch[d], win[d]);
    if (!r->o.quiet)
        say(r, "%s", isatty(STDERR_FILENO) ? "\n" : "");
    finish(r);
    /* nothing measured: nothing written, so an earlier run's outputs stay */
    int any = measured(ch, win) > 0, rc = 0;
    char why[512];
    if (!any) {
        sections_end(r, 0, why, sizeof why);
        say(r, "wgrig: no point measured: no outputs written (%s.* left as they were)\n",
            r->o.out);
    } else if ((rc = sections_end(r, 1, why, sizeof why))) {
        say(r, "wgrig: %s\n", why);
    } else {
        rc = write_outputs(r, ch, win, failed || g_stop, cmdline);
    }
    say(r, "wgrig: %d/%d points, %ld skipped (refused), %ld refusals, %ld ACK timeouts, "
           "%ld commands not sent, %ld POINCARE and %ld CONTACT messages dropped, %ld "
           "recordings re-waited; %.1f s; outputs %s%s\n", r->done, r->total, r->skipped,
        r->refusals, r->timeouts, r->unsent, r->pc_seq.missing, r->ct_seq.missing,
        r->col.breaks, cli_mono_s() - r->t0, any ? r->o.out : "none", any ? ".*" : "");
    out_end(r);
    return g_stop ? 130 : failed || !any ? 1 : rc ? 1 : 0;
}

static void teardown(rig *r, wg_chain chains[2], window *win[2])
{
    char why[512];
    if (r->secf) /* setup failed after opening it */
        sections_end(r, 0, why, sizeof why);
    bus_close(&r->c);
    rig_rec_fini(&r->rec);
    free(r->rval);
    rig_imp_fini(&r->imp);
    for (int d = 0; d < 2; d++)
        free(chains[d].pts), free(win[d]);
}

int main(int argc, char **argv)
{
    rig *r = calloc(1, sizeof *r);
    if (!r)
        return 1;
    rig_imp_init(&r->imp);
    char *cmdline = cli_join_args(argc, argv);
    int rc = rig_parse_opts(argc, argv, &r->o);
    cli_on_stop_signals(on_signal);
    signal(SIGHUP, on_signal);   /* a closed terminal: stop and put the daemon back */
    signal(SIGPIPE, SIG_IGN);    /* a closed stderr pipe killed it mid-sweep */
    r->t0 = cli_mono_s();
    wg_chain chains[2];
    window *win[2] = {NULL, NULL};
    memset(chains, 0, sizeof chains);
    if (!rc && !(rc = setup(r)))
        rc = sweep(r, chains, win, cmdline ? cmdline : "");
    teardown(r, chains, win);
    free(r);
    free(cmdline);
    plot_fini(); /* cairo and fontconfig caches: a clean exit under ASan */
    return rc;
}

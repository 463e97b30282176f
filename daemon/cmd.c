/* cmd.c - CMD: raw subscription, decode, validate, apply, ACK. */
#include "cmd.h"

#include "engine.h"
#include "report.h"
#include "snap.h"
#include "wgd.h"
#include "wire.h"
#include "wormgear/wg_status.h"

#include <ctype.h>
#include <errno.h>
#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

enum { CMD_PENDING = 1, ACK_TEXT = 640, /* ACK_TEXT: room for an ACK's message */
       CMD_QUEUE = 16384 };                 /* CMD messages LCM may hold for us */
#define STEP_MAX 1e12

typedef int (*op_fn)(wgd *d, const wormgear_cmd_t *c, char *why, size_t len);

/* Printable, bounded copy of untrusted text for messages and logs. */
static const char *clean(const char *s, char *out, size_t n)
{
    size_t i = 0;
    for (; s && s[i] && i + 1 < n; i++)
        out[i] = isprint((unsigned char)s[i]) ? s[i] : '?';
    out[i] = 0;
    if (s && s[i] && n > 4)
        memcpy(out + n - 4, "...", 4);
    return out;
}

/* ---- ACK ------------------------------------------------------------------ */

/* At most n - 1 bytes of s, byte for byte (what an ACK echoes). */
static const char *echo(const char *s, char *out, size_t n)
{
    snprintf(out, n, "%s", s ? s : "");
    return out;
}

void cmd_answer(wgd *d, const char *client, int64_t seq, int64_t utime, const char *op, int rc,
                const char *msg)
{
    wormgear_ack_t a = {.client = (char *)client, .cmd_seq = seq, .cmd_utime = utime,
                        .op = (char *)op, .accepted = rc == WG_OK, .status = rc,
                        .code = (char *)wg_status_name(rc), .message = (char *)msg,
                        .tau = d->sim.tau, .t_s = wg_scale_seconds(&d->scene.scale, d->sim.tau),
                        .steps = (int64_t)d->sim.steps};
    lcmio_pub_ack(&d->io, &a);
}

static void ack(wgd *d, const char *client, int64_t seq, int64_t utime, const char *op, int rc,
                const char *msg)
{
    char cl_buf[WIRE_MAX_CLIENT + 1], op_buf[33];
    const char *cl = echo(client, cl_buf, sizeof cl_buf), *o = echo(op, op_buf, sizeof op_buf);
    cmd_answer(d, cl, seq, utime, o, rc, msg);
    if (rc == WG_OK) {
        d->stat.cmds_accepted++;
        if (strcmp(op, "get") && strcmp(op, "step")) { /* a state change: never lost */
            char what[ACK_TEXT + 40];
            snprintf(what, sizeof what, "%s: %s", o, msg);
            log_change(&d->log, LOG_INFO, what, "%s from %s (seq %" PRId64 "): %s", o,
                       cl, seq, msg);
        } else {
            log_msg(&d->log, LOG_DEBUG, "%s from %s (seq %" PRId64 "): %s", o, cl,
                    seq, msg);
        }
    } else {
        d->stat.cmds_refused++;
        log_msg(&d->log, LOG_WARNING, "refused %s from %s (seq %" PRId64 "): %s: %s",
                *o ? o : "?", *cl ? cl : "?", seq, wg_status_name(rc), msg);
    }
}

/* ---- changes: PARAMS after the ACK ---------------------------------------- */

/* Note what a command changed; report_change runs after its ACK. */
static void changed(wgd *d, int what, const char *reason)
{
    d->changed = (change){.due = 1, .what = what, .reason = reason};
}

/* The noted change, reported (regime restart, decimation, PARAMS) with the
 * client, seq and utime of the command that made it. */
static void report_changed(wgd *d, const char *client, int64_t seq, int64_t utime)
{
    change c = d->changed;
    d->changed.due = 0;
    if (c.due)
        report_change(d, c.what, c.reason, client, seq, utime);
}

/* ---- parameters ------------------------------------------------------------ */

/* Ids of the named parameters: EINVAL (count, duplicates) or EUNKNOWN. */
static int lookup_all(const wormgear_cmd_t *c, int ids[WG_NPARAM], char *why, size_t len)
{
    char nm[48];
    if (c->nparams < 1 || c->nparams > WG_NPARAM) {
        snprintf(why, len, "%s needs 1 to %d parameters, got %d", c->op, WG_NPARAM, c->nparams);
        return WG_EINVAL;
    }
    for (int i = 0; i < c->nparams; i++) {
        if ((ids[i] = wg_param_lookup(c->names[i])) < 0) {
            snprintf(why, len, "unknown parameter '%s' (wgctl params lists them)",
                     clean(c->names[i], nm, sizeof nm));
            return WG_EUNKNOWN;
        }
        for (int j = 0; j < i; j++)
            if (ids[j] == ids[i]) {
                snprintf(why, len, "parameter %s given twice", c->names[i]);
                return WG_EINVAL;
            }
    }
    return WG_OK;
}

/* The parameters of d->sim with n of them replaced. */
static wg_params with_values(const wgd *d, const int *ids, const double *values, int n)
{
    wg_params p = d->sim.p;
    for (int i = 0; i < n; i++)
        p.v[ids[i]] = values[i];
    return p;
}

/* Apply n values at once (atomic) and note the change for after the ACK;
 * why gets the answer's text. */
static int apply_set(wgd *d, const int *ids, const double *values, int n, char *why,
                     size_t len)
{
    wg_params p = with_values(d, ids, values, n);
    int ramp = d->sim.ramp.active ? d->sim.ramp.id : -1;
    int rc = wg_sim_set_params(&d->sim, &p, why, len);
    if (rc)
        return rc;
    size_t k = (size_t)snprintf(why, len, "set");
    char num[32];
    for (int i = 0; i < n && k < len; i++) /* exact, in the fewest digits */
        k += (size_t)snprintf(why + k, len - k, " %s=%s", wg_param_info_get(ids[i])->name,
                              wg_num_format(values[i], num, sizeof num));
    if (ramp >= 0 && k < len)
        snprintf(why + k, len - k, " (cancelled the ramp of %s at %.9g)",
                 wg_param_info_get(ramp)->name, d->sim.p.v[ramp]);
    changed(d, REPORT_ORBIT | REPORT_RATE, "set");
    return WG_OK;
}

/* Steps from the current one to the next Poincare section (1 ... N-1 when
 * mid-period, 0 on one). */
static uint64_t steps_to_section(const wgd *d)
{
    uint32_t N = (uint32_t)d->sim.cfg.steps_per_period;
    return (N - d->sim.k) % N;
}

/* Does the next section come without another command: the run goes on
 * (in lockstep it waits for steps, legitimately), or, paused, a running
 * step command reaches it. A set waiting on a paused run went unanswered
 * (wgctl timed out, "is wormgeard running?") and applied at some resume:
 * a set at the section is taken only while this holds, and refused as
 * soon as it stops holding (pause, a fault, cmd_sync_check). */
static int section_comes(const wgd *d)
{
    return d->run == RUN_RUNNING || (d->step.active && d->step.left >= steps_to_section(d));
}

/* Why no section comes, for a set at the section refused or cancelled. */
static void no_section_why(const wgd *d, char *why, size_t len)
{
    snprintf(why, len, "no Poincare section comes while the run is paused (tau %.9g, %" PRIu64
             " steps before the next section)", d->sim.tau, steps_to_section(d));
}

/* A set for the next Poincare section: validated now, applied by cmd_run
 * when the phase index reaches 0. */
static int defer_set(wgd *d, const wormgear_cmd_t *c, const int *ids, char *why, size_t len)
{
    syncjob *j = &d->sync;
    if (j->active) {
        snprintf(why, len, "a set at the next section is already pending (from %s, seq %" PRId64
                           ")", j->client, j->seq);
        return WG_ESTATE;
    }
    wg_params p = with_values(d, ids, c->values, c->nparams);
    int rc = wg_sim_check_params(&d->sim, &p, why, len);
    if (rc)
        return rc;
    if (!section_comes(d)) {
        char none[200];
        no_section_why(d, none, sizeof none);
        snprintf(why, len, "%s: resume first, or set without at_section (wgctl: without "
                 "--at-section) to apply it now", none);
        return WG_ESTATE;
    }
    *j = (syncjob){.active = 1, .n = c->nparams, .seq = c->seq, .utime = c->utime};
    memcpy(j->ids, ids, sizeof(int) * (size_t)c->nparams);
    memcpy(j->values, c->values, sizeof(double) * (size_t)c->nparams);
    snprintf(j->client, sizeof j->client, "%s", c->client);
    return CMD_PENDING;
}

static int op_set(wgd *d, const wormgear_cmd_t *c, char *why, size_t len)
{
    int ids[WG_NPARAM], rc = lookup_all(c, ids, why, len);
    if (rc)
        return rc;
    for (int i = 0; i < c->nparams; i++)
        if ((rc = wg_param_check(ids[i], c->values[i], why, len)))
            return rc;
    if (c->at_section && d->sim.k != 0)
        return defer_set(d, c, ids, why, len);
    return apply_set(d, ids, c->values, c->nparams, why, len);
}

/* Apply and ACK the set waiting for the section (phase index 0). */
static void sync_apply(wgd *d)
{
    syncjob *j = &d->sync;
    if (!j->active || d->sim.k != 0)
        return;
    j->active = 0;
    char why[ACK_TEXT];
    int rc = apply_set(d, j->ids, j->values, j->n, why, sizeof why);
    ack(d, j->client, j->seq, j->utime, "set", rc, why);
    report_changed(d, j->client, j->seq, j->utime);
}

/* Refuse a set waiting for the section (reset, restore, shutdown). */
static void sync_cancel(wgd *d, int code, const char *why)
{
    syncjob *j = &d->sync;
    if (!j->active)
        return;
    j->active = 0;
    ack(d, j->client, j->seq, j->utime, "set", code, why);
}

void cmd_sync_check(wgd *d, const char *cause)
{
    if (!d->sync.active || section_comes(d))
        return;
    char none[200], why[ACK_TEXT];
    no_section_why(d, none, sizeof none);
    snprintf(why, sizeof why, "set at the next section cancelled by %s: %s; set it again after "
             "resume, or without at_section to apply it now", cause, none);
    sync_cancel(d, WG_ESTATE, why);
}

/* n steps on the engine, then what they did announced: the end of a ramp
 * (a new orbit, PARAMS "ramp-end"), a blow-up (STATUS with the fault). */
static uint64_t run_steps(wgd *d, uint64_t n)
{
    int events;
    uint64_t done = engine_run(d, n, &events);
    if (events & ENGINE_RAMP_ENDED)
        report_change(d, REPORT_ORBIT, "ramp-end", "", -1, 0);
    if (events & ENGINE_FAULTED) {
        report_fault(d);
        sync_cancel(d, WG_ESTATE, "set at the next section cancelled: the run faulted and "
                    "paused (STATUS says why); set it again after resume, reset or restore");
    }
    return done;
}

uint64_t cmd_run(wgd *d, uint64_t n)
{
    uint64_t to = steps_to_section(d);
    if (!d->sync.active || to > n)
        return run_steps(d, n);
    uint64_t done = run_steps(d, to);
    if (done < to)
        return done;
    sync_apply(d);
    return done + run_steps(d, n - to);
}

/* Ramp duration in tau from the command's duration and unit. */
/* Ramp duration in tau from the command's duration and unit, inside the
 * library's [WG_RAMP_TAU_MIN, WG_RAMP_TAU_MAX], the limits said in the
 * command's own unit. */
static int ramp_duration(const wgd *d, const wormgear_cmd_t *c, double *dur, char *why,
                         size_t len)
{
    char u[16], v[32], lo[32], hi[32];
    int secs = !strcmp(c->unit, "s");
    if (!secs && strcmp(c->unit, "tau")) {
        snprintf(why, len, "ramp unit '%s' must be s (simulated seconds) or tau",
                 clean(c->unit, u, sizeof u));
        return WG_EINVAL;
    }
    double per = secs ? d->scene.scale.omega_n_rad_s : 1.0; /* tau per unit */
    *dur = c->duration * per;
    if (!(*dur >= WG_RAMP_TAU_MIN && *dur <= WG_RAMP_TAU_MAX)) {
        snprintf(why, len, "ramp duration %s %s out of range [%s, %s] %s%s",
                 wg_num_format(c->duration, v, sizeof v), c->unit,
                 wg_num_format(WG_RAMP_TAU_MIN / per, lo, sizeof lo),
                 wg_num_format(WG_RAMP_TAU_MAX / per, hi, sizeof hi), c->unit,
                 secs ? " (1e-06 to 1e+15 tau)" : "");
        return WG_ERANGE;
    }
    return WG_OK;
}

/* Validate what is the command's own: count, name, unit and duration; the
 * values (both ends, the stability limit) are wg_sim_ramp's. */
static int ramp_check(wgd *d, const wormgear_cmd_t *c, int *id, double *dur, char *why,
                      size_t len)
{
    int ids[WG_NPARAM], rc;
    if (c->nparams != 1) { /* the count first: nothing is looked up for a wrong one */
        snprintf(why, len, "ramp takes exactly one parameter, got %d", c->nparams);
        return WG_EINVAL;
    }
    if ((rc = lookup_all(c, ids, why, len)) || (rc = ramp_duration(d, c, dur, why, len)))
        return rc;
    *id = ids[0];
    return WG_OK;
}

static int op_ramp(wgd *d, const wormgear_cmd_t *c, char *why, size_t len)
{
    int id, rc;
    double dur;
    if (c->at_section) {
        snprintf(why, len, "at_section applies to set only (a ramp is already phase-continuous)");
        return WG_EINVAL;
    }
    if ((rc = ramp_check(d, c, &id, &dur, why, len)))
        return rc;
    const wg_ramp was = d->sim.ramp;
    if ((rc = wg_sim_ramp(&d->sim, id, c->has_from ? &c->from : NULL, c->values[0], dur, why,
                          len)))
        return rc; /* nothing applied */
    double v0 = d->sim.ramp.v0;
    int n = snprintf(why, len, "ramp %s %.9g -> %.9g over %.9g tau (%.6g s simulated)",
                     c->names[0], v0, c->values[0], dur, wg_scale_seconds(&d->scene.scale, dur));
    if (was.active && n > 0 && (size_t)n < len) { /* never silently: say what it replaced */
        const char *old = wg_param_info_get(was.id)->name;
        double left = was.tau0 + was.dur - d->sim.tau;
        double left_s = wg_scale_seconds(&d->scene.scale, left > 0 ? left : 0);
        if (was.id == id)
            snprintf(why + n, len - (size_t)n, "; it replaces the running ramp of %s to %.9g, "
                     "%.6g s simulated before its end, from where that ramp had taken it", old,
                     was.v1, left_s);
        else
            snprintf(why + n, len - (size_t)n, "; it replaces the running ramp of %s to %.9g, "
                     "%.6g s simulated before its end: %s stays at %.9g", old, was.v1, left_s,
                     old, d->sim.p.v[was.id]);
    }
    changed(d, REPORT_ORBIT, "ramp");
    return WG_OK;
}

/* ---- run control ----------------------------------------------------------- */

/* pause stops all stepping (PROTOCOL.md): a running `step` command too,
 * which is cancelled (its own ACK: ESTATE), as reset and a mode change
 * cancel it; it would otherwise go on under a "paused". */
static int op_pause(wgd *d, const wormgear_cmd_t *c, char *why, size_t len)
{
    (void)c;
    int was = d->run == RUN_PAUSED, stepping = d->step.active;
    uint64_t done = d->step.total - d->step.left, total = d->step.total;
    cmd_step_cancel(d, WG_ESTATE, "cancelled by pause");
    engine_pause(d);
    /* a set waiting for the section: none comes now (it was applied at a
     * later resume, long after its sender stopped waiting) */
    sync_cancel(d, WG_ESTATE, "set at the next section cancelled by pause (no section comes "
                "while paused): set it again after resume, or without at_section");
    if (stepping)
        snprintf(why, len, "paused at tau %.9g; the step command was cancelled after %" PRIu64
                 " of %" PRIu64 " steps", d->sim.tau, done, total);
    else
        snprintf(why, len, "%s at tau %.9g", was ? "already paused" : "paused", d->sim.tau);
    return WG_OK;
}

/* resume while a `step` command runs is refused: the run would continue
 * under the step (which goes first) and neither would mean what it says. */
static int op_resume(wgd *d, const wormgear_cmd_t *c, char *why, size_t len)
{
    (void)c;
    if (d->step.active) {
        snprintf(why, len, "a step command is running (%" PRIu64 " of %" PRIu64 " steps left): "
                 "resume once its ACK has come, or stop it first: pause cancels it (so do "
                 "reset, restore and a mode change)", d->step.left, d->step.total);
        return WG_ESTATE;
    }
    int fault = d->fault;
    engine_resume(d);
    snprintf(why, len, "running from tau %.9g%s", d->sim.tau,
             fault ? " (fault cleared: continuing from the last good state)" : "");
    return WG_OK;
}

static int op_reset(wgd *d, const wormgear_cmd_t *c, char *why, size_t len)
{
    int params = strcmp(c->name, "params") == 0;
    if (!params && c->name[0]) {
        snprintf(why, len, "reset takes no name, or \"params\" to restore the scene's "
                           "parameters too");
        return WG_EINVAL;
    }
    cmd_step_cancel(d, WG_ESTATE, "cancelled by reset");
    sync_cancel(d, WG_ESTATE, "set at the next section cancelled by reset");
    engine_reset(d, params);
    changed(d, REPORT_ORBIT | REPORT_RATE, "reset");
    snprintf(why, len, "reset to the scene's initial state%s",
             params ? " and parameters" : " (parameters kept)");
    return WG_OK;
}

static int op_step(wgd *d, const wormgear_cmd_t *c, char *why, size_t len)
{
    if (c->nsteps < 1 || (double)c->nsteps > STEP_MAX) {
        snprintf(why, len, "nsteps = %" PRId64 " out of range [1, %g]", c->nsteps, STEP_MAX);
        return WG_ERANGE;
    }
    if (d->step.active) {
        snprintf(why, len, "a step command is in progress (%" PRIu64 " of %" PRIu64 " left)",
                 d->step.left, d->step.total);
        return WG_ESTATE;
    }
    if (d->conf.mode != MODE_LOCKSTEP && d->run != RUN_PAUSED) {
        snprintf(why, len, "step needs lockstep mode or a paused simulation (mode %s, running)",
                 conf_mode_name(d->conf.mode));
        return WG_ESTATE;
    }
    stepjob *j = &d->step;
    *j = (stepjob){.active = 1, .left = (uint64_t)c->nsteps, .total = (uint64_t)c->nsteps,
                   .seq = c->seq, .utime = c->utime};
    snprintf(j->client, sizeof j->client, "%s", c->client);
    snprintf(j->op, sizeof j->op, "%s", c->op);
    cmd_step_progress(d, 1000); /* small steps answer at once; the rest from the loop */
    return CMD_PENDING;
}

uint64_t cmd_step_progress(wgd *d, uint64_t max)
{
    stepjob *j = &d->step;
    if (!j->active)
        return 0;
    uint64_t n = j->left < max ? j->left : max, done = cmd_run(d, n);
    j->left -= done;
    if (done < n) {
        j->active = 0;
        ack(d, j->client, j->seq, j->utime, j->op, WG_ENONFINITE, d->fault_msg);
    } else if (!j->left) {
        char msg[96];
        j->active = 0;
        snprintf(msg, sizeof msg, "stepped %" PRIu64 " steps", j->total);
        ack(d, j->client, j->seq, j->utime, j->op, WG_OK, msg);
    }
    return done;
}

void cmd_step_cancel(wgd *d, int code, const char *why)
{
    stepjob *j = &d->step;
    if (!j->active)
        return;
    char msg[160];
    snprintf(msg, sizeof msg, "%s after %" PRIu64 " of %" PRIu64 " steps", why,
             j->total - j->left, j->total);
    j->active = 0;
    ack(d, j->client, j->seq, j->utime, j->op, code, msg);
}

void cmd_mode_changed(wgd *d, const char *cause)
{
    char msg[96];
    snprintf(msg, sizeof msg, "cancelled by %s", cause);
    if (d->conf.mode != MODE_LOCKSTEP) {
        int stepping = d->step.active;
        cmd_step_cancel(d, WG_ESTATE, msg);
        d->owed.ticks = 0;
        /* paused, that step was what a set at the section waited for: it
         * was left unanswered and applied at a later resume */
        char what[160];
        snprintf(what, sizeof what, "%s, which cancelled the step command that was to reach "
                 "it", cause);
        cmd_sync_check(d, stepping ? what : cause);
    }
    if (d->conf.mode != MODE_REALTIME)
        d->owed.realtime = 0;
}

static int op_mode(wgd *d, const wormgear_cmd_t *c, char *why, size_t len)
{
    char nm[24];
    int mode = conf_mode_lookup(c->name);
    if (mode < 0) {
        snprintf(why, len, "mode '%s' is not one of realtime, fast, lockstep",
                 clean(c->name, nm, sizeof nm));
        return WG_EINVAL;
    }
    if (c->rate != 0.0 && conf_check_number("rate", c->rate, why, len)) /* 0: keep the rate */
        return WG_ERANGE;
    d->conf.mode = mode;
    cmd_mode_changed(d, "a mode change");
    if (c->rate != 0.0)
        d->conf.rate = c->rate;
    pace_configure(&d->pace, &d->conf, d->scene.scale.omega_n_rad_s, log_now_ns(),
                   d->sim.tau);
    report_decimation(d);
    if (mode == MODE_REALTIME)
        snprintf(why, len, "mode realtime, rate %g (%g x physical real time)", d->conf.rate,
                 d->conf.rate);
    else if (mode == MODE_FAST)
        snprintf(why, len, "mode fast: as fast as one core allows (the rate, %g, applies to "
                 "realtime only)", d->conf.rate);
    else
        snprintf(why, len, "mode lockstep: the simulation advances only by step commands and "
                 "TICK messages");
    return WG_OK;
}

/* ---- state files and queries ---------------------------------------------- */

static int op_save(wgd *d, const wormgear_cmd_t *c, char *why, size_t len)
{
    snap s;
    char path[600];
    snap_take(&s, &d->sim, d->scene.name);
    int rc = snap_write(&s, d->conf.state_dir, c->name, path, sizeof path, why, len);
    if (!rc)
        snprintf(why, len, "saved %s at tau %.9g", path, d->sim.tau);
    return rc;
}

static int op_restore(wgd *d, const wormgear_cmd_t *c, char *why, size_t len)
{
    static const snap zero;
    snap s = zero;
    int rc = snap_read(&s, d->conf.state_dir, c->name, why, len);
    if (rc)
        return rc;
    stream_flush(d);
    if ((rc = snap_apply(&s, &d->sim, why, len)))
        return rc;
    cmd_step_cancel(d, WG_ESTATE, "cancelled by restore");
    sync_cancel(d, WG_ESTATE, "set at the next section cancelled by restore");
    engine_restore(d);
    changed(d, REPORT_ORBIT | REPORT_RATE, "restore");
    snprintf(why, len, "restored %s: tau %.9g, step %" PRIu64 "%s%s", c->name, d->sim.tau,
             d->sim.steps, strcmp(s.scene, d->scene.name) ? ", taken with scene " : "",
             strcmp(s.scene, d->scene.name) ? s.scene : "");
    return WG_OK;
}

static int op_get(wgd *d, const wormgear_cmd_t *c, char *why, size_t len)
{
    report_params(d, "get", c->client, c->seq, c->utime);
    snprintf(why, len, "parameters published on %s", d->io.ch[CH_PARAMS]);
    return WG_OK;
}

/* contacts all|mesh|none [N]: which CONTACT events are published (nsteps:
 * bearing_every, 0 = keep). */
static int op_contacts(wgd *d, const wormgear_cmd_t *c, char *why, size_t len)
{
    char nm[24];
    int which = conf_contacts_lookup(c->name);
    if (which < 0) {
        snprintf(why, len, "contacts '%s' is not one of all, mesh, none",
                 clean(c->name, nm, sizeof nm));
        return WG_EINVAL;
    }
    if (c->nsteps != 0 && conf_check_number("bearing_every", (double)c->nsteps, why, len))
        return WG_ERANGE;
    stream_flush(d); /* what was collected goes out under the old setting */
    d->conf.contacts = which;
    if (c->nsteps != 0)
        d->conf.bearing_every = (int)c->nsteps;
    stream_set_contacts(&d->st, which, d->conf.bearing_every);
    if (which == CONTACTS_ALL && d->conf.bearing_every > 1)
        snprintf(why, len, "contacts all: every mesh event, 1 in %d events of each bearing",
                 d->conf.bearing_every);
    else
        snprintf(why, len, "contacts %s: %s", conf_contacts_name(which),
                 which == CONTACTS_ALL    ? "every mesh and bearing event"
                 : which == CONTACTS_MESH ? "mesh events only, no bearing events"
                                          : "no CONTACT messages");
    return WG_OK;
}

static const struct {
    const char *op;
    op_fn fn;
    int readonly;
} ops[] = {{"set", op_set, 0},         {"ramp", op_ramp, 0},     {"pause", op_pause, 0},
           {"resume", op_resume, 0},   {"reset", op_reset, 0},   {"step", op_step, 0},
           {"save", op_save, 0},       {"restore", op_restore, 0}, {"get", op_get, 1},
           {"mode", op_mode, 0},       {"contacts", op_contacts, 0}};

static void dispatch(wgd *d, const wormgear_cmd_t *c)
{
    char why[ACK_TEXT], op[24];
    size_t len = sizeof why;
    int rc = WG_EINVAL;
    unsigned i;
    for (i = 0; i < sizeof ops / sizeof ops[0]; i++)
        if (strcmp(ops[i].op, c->op) == 0)
            break;
    if (i == sizeof ops / sizeof ops[0])
        snprintf(why, len, "unknown op '%s' (set ramp pause resume reset step save restore "
                           "get mode contacts)", clean(c->op, op, sizeof op));
    else if ((c->has_from != 0 && c->has_from != 1) || (c->at_section != 0 && c->at_section != 1))
        snprintf(why, len, "has_from %d, at_section %d: each flag is 0 or 1", c->has_from,
                 c->at_section); /* 7 or -3 was taken as 1 */
    else if (!d->conf.accept_commands && !ops[i].readonly) {
        snprintf(why, len, "commands are disabled on this daemon (accept_commands = no)");
        rc = WG_ESTATE;
    } else
        rc = ops[i].fn(d, c, why, len);
    if (rc != CMD_PENDING)
        ack(d, c->client, c->seq, c->utime, c->op, rc, why);
    report_changed(d, c->client, c->seq, c->utime); /* PARAMS right behind the ACK */
}

/* ---- decoding --------------------------------------------------------------- */

/* Answer a message that does not decode, addressed to its sender when the
 * header survived. */
static void undecodable(wgd *d, const void *buf, size_t len, const char *reason)
{
    char client[WIRE_MAX_CLIENT + 1], msg[400];
    int64_t seq, utime;
    wire_cmd_header(buf, len, client, sizeof client, &seq, &utime);
    snprintf(msg, sizeof msg, "undecodable CMD message (%zu bytes): %s%s", len, reason,
             seq < 0 ? "; client and seq unknown" : "");
    ack(d, client, seq, utime, "", WG_EDECODE, msg);
}

void cmd_handle(wgd *d, const void *buf, size_t len)
{
    wormgear_cmd_t c;
    char why[160];
    if (len > INT32_MAX) {
        undecodable(d, buf, len, "too large");
        return;
    }
    int32_t mac_len;
    if (wire_cmd_check(buf, len, &mac_len, why, sizeof why)) { /* decode only what decodes whole */
        undecodable(d, buf, len, why);
        return;
    }
    if (wormgear_cmd_t_decode(buf, 0, (int)len, &c) < 0) {
        undecodable(d, buf, len, "rejected by the decoder");
        return;
    }
    char awhy[ACK_TEXT];
    if (auth_check(&d->auth, AUTH_CMD, buf, len, mac_len, c.client, c.seq, c.utime,
                   lcmio_now_us(), awhy, sizeof awhy))
        ack(d, c.client, c.seq, c.utime, c.op, WG_EAUTH, awhy);
    else
        dispatch(d, &c);
    wormgear_cmd_t_decode_cleanup(&c);
}

/* Copy the message into the inbox and give LCM its buffer back at once;
 * cmd_process handles it. Too large to queue: answered now (cheap). */
static void on_cmd(const lcm_recv_buf_t *rb, const char *channel, void *user)
{
    (void)channel;
    wgd *d = user;
    if (rb->data_size > INBOX_MSG_MAX) {
        char why[96];
        snprintf(why, sizeof why, "message of %u bytes, the limit is %d", rb->data_size,
                 INBOX_MSG_MAX);
        undecodable(d, rb->data, rb->data_size, why);
    } else if (inbox_push(&d->in, rb->data, rb->data_size)) {
        log_msg(&d->log, LOG_WARNING, "CMD message dropped: the inbox is full (%d bytes); "
                "counted in STATUS cmds_dropped", INBOX_BYTES);
    }
}

int cmd_process(wgd *d, int64_t budget_ns)
{
    int64_t now = log_now_ns();
    int64_t end = budget_ns > INT64_MAX - now ? INT64_MAX : now + budget_ns;
    int n = 0;
    size_t len;
    while (inbox_pop(&d->in, d->cmdbuf, &len)) {
        cmd_handle(d, d->cmdbuf, len);
        n++;
        if (log_now_ns() >= end)
            break;
    }
    return n;
}

/* Sleep until the wall clock passes t_us (at most AUTH_AHEAD_S here). Before
 * then auth refuses a command signed now (it cannot tell it from one an
 * earlier run accepted); subscribing after it, the daemon never answers a
 * client whose clock agrees with that refusal. */
static void wait_until_us(int64_t t_us)
{
    int64_t left = t_us - lcmio_now_us() + 1;
    struct timespec ts = {left / 1000000, left % 1000000 * 1000};
    while (left > 0 && nanosleep(&ts, &ts) != 0 && errno == EINTR)
        ;
}

int cmd_key_load(wgd *d, char *why, size_t whylen)
{
    int rc = auth_load(&d->auth, d->conf.command_key_file, lcmio_now_us(), why, whylen);
    lcmio_sign_with(&d->io, auth_key(&d->auth)); /* the key in use, new or kept, or none */
    return rc;
}

int cmd_key_init(wgd *d)
{
    int rc = cmd_key_load(d, d->init_why, sizeof d->init_why);
    if (rc) {
        cmd_key_fini(d); /* what a failed load left: nothing taken */
        return rc;
    }
    if (d->auth.on) {
        log_msg(&d->log, LOG_INFO, "signed commands only (key %s)", d->auth.path);
        if (!d->conf.check_only) /* --check-config takes no command to wait for */
            wait_until_us(auth_open_us(&d->auth));
    }
    return WG_OK;
}

void cmd_key_fini(wgd *d)
{
    lcmio_sign_with(&d->io, NULL);
    auth_fini(&d->auth);
}

int cmd_init(wgd *d)
{
    if (inbox_init(&d->in, INBOX_BYTES)) {
        snprintf(d->init_why, sizeof d->init_why, "out of memory for the command inbox");
        return WG_ENOMEM;
    }
    /* room for a burst (PROTOCOL.md: 2,000 commands at once are all
     * answered); what the kernel still drops is counted (rx_dropped) */
    int rc = lcmio_subscribe(&d->io, CH_CMD, on_cmd, d, CMD_QUEUE, d->init_why,
                             sizeof d->init_why);
    if (rc)
        inbox_fini(&d->in); /* a module that fails leaves nothing behind */
    return rc;
}

void cmd_fini(wgd *d)
{
    cmd_step_cancel(d, WG_ESTATE, "cancelled: the daemon is stopping");
    sync_cancel(d, WG_ESTATE, "set at the next section cancelled: the daemon is stopping");
    inbox_fini(&d->in);
}

/* report.c - STATUS, PARAMS, foreground line and periodic bookkeeping. */
#include "report.h"

#include "sdn.h"
#include "wgd.h"
#include "wire.h"

#include <errno.h>
#include <math.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

enum { FLUSH_NS = 20000000, SEC_NS = 1000000000 };

static double cpu_seconds(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

const char *report_health_name(int h)
{
    return h == HEALTH_FAULT ? "fault" : h == HEALTH_LAGGING ? "lagging" : "ok";
}

const char *report_run_name(const wgd *d)
{
    if (d->step.active)
        return "stepping";
    if (d->run != RUN_RUNNING)
        return "paused";
    if (d->conf.mode != MODE_LOCKSTEP)
        return "running";
    return d->owed.ticks ? "stepping" : "waiting"; /* working off TICKs, or idle */
}

/* Over the tracked orbit once there is one (a period-2 orbit alternating
 * an impacting and a free period is single_sided, not whichever came
 * last); before, the last period's; "unknown" before the first. */
static const char *motion_name(const wgd *d)
{
    return d->st.trk.n ? wg_motion_name(d->st.trk.motion)
           : d->sim.period ? wg_motion_name(d->st.motion) : "unknown";
}

static void interval_start(wgd *d, int64_t now)
{
    stats *s = &d->stat;
    s->t_ns = now;
    s->tau = 0;
    s->steps = 0;
    s->cpu_s = cpu_seconds();
    s->loop_sum_ns = s->loop_max_ns = 0;
    s->loops = 0;
    stream_stats_reset(&d->st);
}

/* A STATUS on our own channel that we did not send: another daemon with
 * this URL and prefix (both answer every command), or a sender posing as
 * one. Only its header is read (fingerprint, utime, seq); counted and
 * logged, at most 5 times per 10 s. */
static void on_status_echo(const lcm_recv_buf_t *rb, const char *channel, void *user)
{
    wgd *d = user;
    int64_t seq, utime;
    if (!wire_status_header(rb->data, rb->data_size, &seq, &utime) ||
        lcmio_sent(&d->io, CH_STATUS, seq, utime))
        return;
    d->stat.status_foreign++;
    log_msg(&d->log, LOG_WARNING, "another sender publishes STATUS on %s (seq %lld): a second "
            "wormgeard with this URL and prefix? Both would answer every command; give each "
            "daemon its own --prefix (or URL)", channel, (long long)seq);
}

void report_init(wgd *d)
{
    int64_t now = log_now_ns();
    memset(&d->stat, 0, sizeof d->stat);
    char why[160];
    if (lcmio_subscribe(&d->io, CH_STATUS, on_status_echo, d, 64, why, sizeof why))
        log_msg(&d->log, LOG_WARNING, "%s: a second daemon on this prefix will not be noticed",
                why);
    interval_start(d, now);
    d->stat.next_status_ns = now + (int64_t)(SEC_NS / d->conf.status_hz);
    d->stat.next_params_ns = now + SEC_NS;
    d->stat.next_fg_ns = now + SEC_NS;
    d->stat.next_flush_ns = now + FLUSH_NS;
    report_decimation(d);
}

void report_fini(wgd *d) { (void)d; }

void report_loop(wgd *d, int64_t dur_ns)
{
    stats *s = &d->stat;
    s->loop_sum_ns += (double)dur_ns;
    s->loop_max_ns = fmax(s->loop_max_ns, (double)dur_ns);
    s->loops++;
    s->busiest_ns = dur_ns > s->busiest_ns ? dur_ns : s->busiest_ns;
}

/* Steps per wall second the current mode aims at (0: unknown). */
static double step_rate(const wgd *d)
{
    if (d->conf.mode == MODE_REALTIME)
        return d->pace.cfg.tau_per_ns * 1e9 / wg_sim_step_tau(&d->sim);
    return d->stat.ns_per_step > 0 ? 1e9 / d->stat.ns_per_step : 0.0;
}

void report_decimation(wgd *d)
{
    int dec = d->conf.state_decimation;
    if (dec <= 0) {
        double r = step_rate(d), want = d->conf.state_rate_hz;
        dec = r > 0 && want > 0 ? (int)fmin(1e9, fmax(1.0, round(r / want)))
                                : d->sim.cfg.steps_per_period / 8;
    }
    stream_set_decimation(&d->st, dec);
}

static void compute(wgd *d, int64_t now)
{
    stats *s = &d->stat;
    double wall = (double)(now - s->t_ns) * 1e-9;
    if (wall <= 0)
        return;
    s->rtf = wg_scale_seconds(&d->scene.scale, s->tau) / wall;
    s->steps_per_s = (double)s->steps / wall;
    s->cpu_share = (cpu_seconds() - s->cpu_s) / wall;
    s->loop_mean_us = s->loops ? s->loop_sum_ns / (double)s->loops * 1e-3 : 0.0;
    s->loop_max_us = s->loop_max_ns * 1e-3;
    /* over the periods the motion and the regime describe (the tracker's,
     * since the last change): the interval's count said 0 beside a
     * single_sided motion whose impacts had left the interval */
    const wg_tracker *t = &d->st.trk;
    s->impacts_per_period = t->n ? (double)t->impacts / t->n
                            : d->st.sections ? (double)d->st.impacts / (double)d->st.sections
                                             : 0.0;
    for (int j = 0; j < WG_NBEARING; j++) {
        s->bearing_ipp[j] = d->st.sections ? (double)d->st.bimp[j] / (double)d->st.sections : 0.0;
        s->bearing_vmax[j] = d->st.bvmax[j];
    }
    int late = d->conf.mode == MODE_REALTIME && d->run == RUN_RUNNING &&
               (pace_lag_s(&d->pace) * 1e3 > d->conf.lag_warn_ms ||
                d->pace.consecutive > 0);
    s->health = d->fault ? HEALTH_FAULT : late ? HEALTH_LAGGING : HEALTH_OK;
}

static const char *regime_name(const wgd *d, char *buf, unsigned len)
{
    return d->sim.ramp.active ? "ramping" : stream_regime(&d->st, buf, len);
}

static void fill_status(const wgd *d, wormgear_status_t *m, char *regime, unsigned rlen)
{
    const stats *s = &d->stat;
    *m = (wormgear_status_t){
        .scene = (char *)d->scene.name, .mode = (char *)conf_mode_name(d->conf.mode),
        .rate = d->conf.rate, .run = (char *)report_run_name(d),
        .health = (char *)report_health_name(s->health), .fault = (char *)d->fault_msg,
        .tau = d->sim.tau, .t_s = wg_scale_seconds(&d->scene.scale, d->sim.tau),
        .omega = d->sim.p.v[WG_P_OMEGA], .steps = (int64_t)d->sim.steps,
        .period = (int64_t)d->sim.period, .steps_per_period = d->sim.cfg.steps_per_period,
        .rtf = s->rtf, .lag_s = d->conf.mode == MODE_REALTIME ? pace_lag_s(&d->pace) : 0.0,
        .overruns = (int64_t)d->pace.overruns, .loop_mean_us = s->loop_mean_us,
        .loop_max_us = s->loop_max_us, .steps_per_s = s->steps_per_s,
        .cpu_share = s->cpu_share, .msgs_dropped = (int64_t)d->io.dropped,
        .cmds_dropped = (int64_t)d->in.dropped, .rx_dropped = (int64_t)lcmio_rx_dropped(),
        .ticks_refused = (int64_t)s->ticks_refused, .tick_refusal = (char *)s->tick_why,
        .ticks_lost = (int64_t)s->tick_gaps,
        .cmds_accepted = (int64_t)s->cmds_accepted, .cmds_refused = (int64_t)s->cmds_refused,
        .motion = (char *)motion_name(d), .impacts_per_period = s->impacts_per_period,
        .regime = (char *)regime_name(d, regime, rlen), .nbearing = WG_NBEARING,
        .bearing_impacts_per_period = (double *)s->bearing_ipp,
        .bearing_impact_vmax = (double *)s->bearing_vmax, .ramp_active = (int8_t)d->sim.ramp.active,
        .uptime_s = (double)(log_now_ns() - d->start_ns) * 1e-9};
}

void report_status(wgd *d)
{
    int64_t now = log_now_ns();
    compute(d, now);
    wormgear_status_t m;
    char regime[24];
    fill_status(d, &m, regime, sizeof regime);
    lcmio_pub_status(&d->io, &m);
}

void report_fault(wgd *d)
{
    stream_flush(d);
    report_status(d);
}

void report_line(const wgd *d, char *buf, unsigned len)
{
    const stats *s = &d->stat;
    char mode[32], regime[24];
    if (d->conf.mode == MODE_REALTIME)
        snprintf(mode, sizeof mode, "realtime x%g", d->conf.rate);
    else
        snprintf(mode, sizeof mode, "%s", conf_mode_name(d->conf.mode));
    snprintf(buf, len,
             "%s %s %s | t %.4f s tau %.6g | omega %.4g | rtf %.3f lag %.1f ms | %.3g steps/s "
             "cpu %.0f%% | %s %s %.2f impacts/period | overruns %llu | cmds %llu/%llu refused",
             mode, report_run_name(d), report_health_name(s->health),
             wg_scale_seconds(&d->scene.scale, d->sim.tau), d->sim.tau, d->sim.p.v[WG_P_OMEGA],
             s->rtf, d->conf.mode == MODE_REALTIME ? pace_lag_s(&d->pace) * 1e3 : 0.0,
             s->steps_per_s, s->cpu_share * 100.0, regime_name(d, regime, sizeof regime),
             motion_name(d), s->impacts_per_period, (unsigned long long)d->pace.overruns,
             (unsigned long long)s->cmds_accepted, (unsigned long long)s->cmds_refused);
}

void report_params(wgd *d, const char *reason, const char *client, int64_t cmd_seq,
                   int64_t cmd_utime)
{
    char *name[WG_NPARAM], *unit[WG_NPARAM];
    double val[WG_NPARAM], lo[WG_NPARAM], hi[WG_NPARAM], def[WG_NPARAM];
    int8_t ramp[WG_NPARAM];
    for (int i = 0; i < WG_NPARAM; i++) {
        const wg_param_info *r = wg_param_info_get(i);
        name[i] = (char *)r->name;
        unit[i] = (char *)r->unit;
        val[i] = d->sim.p.v[i];
        lo[i] = r->min;
        hi[i] = r->max;
        def[i] = r->def;
        ramp[i] = (int8_t)((r->flags & WG_PF_RAMP) != 0);
    }
    const wg_ramp *rp = &d->sim.ramp;
    wormgear_params_t m = {
        .reason = (char *)reason, .cmd_client = (char *)client, .cmd_seq = cmd_seq,
        .cmd_utime = cmd_utime,
        .scene = d->scene.name, .model = (char *)wg_model_name(d->sim.cfg.model),
        .stepper = (char *)wg_stepper_name(d->sim.cfg.stepper),
        .steps_per_period = d->sim.cfg.steps_per_period,
        .omega_n_rad_s = d->scene.scale.omega_n_rad_s, .length_m = d->scene.scale.length_m,
        .mesh_stiffness_N_m = d->scene.scale.mesh_stiffness_N_m, .tau = d->sim.tau,
        .n = WG_NPARAM, .name = name, .unit = unit, .value = val, .min = lo, .max = hi,
        .def = def, .rampable = ramp, .ramp_active = (int8_t)rp->active,
        .ramp_param = rp->active ? (char *)wg_param_info_get(rp->id)->name : (char *)"",
        .ramp_from = rp->v0, .ramp_to = rp->v1, .ramp_tau0 = rp->tau0,
        .ramp_duration_tau = rp->dur};
    lcmio_pub_params(&d->io, &m);
}

void report_change(wgd *d, int what, const char *reason, const char *client, int64_t cmd_seq,
                   int64_t cmd_utime)
{
    if (what & REPORT_ORBIT)
        stream_regime_reset(&d->st);
    if (what & REPORT_RATE)
        report_decimation(d);
    report_params(d, reason, client, cmd_seq, cmd_utime);
}

/* The status line on stdout; once a write fails (a closed pipe: EPIPE, a
 * full disk) it stops, with one warning rather than one a second. */
static void foreground(wgd *d)
{
    char line[400];
    if (d->stat.fg_failed)
        return;
    report_line(d, line, sizeof line);
    int e = log_stdout(&d->log, line);
    if (e) {
        d->stat.fg_failed = 1;
        log_msg(&d->log, LOG_WARNING, "foreground: cannot write the status line to stdout "
                "(%s): not printed from now on", strerror(e));
    }
}

/* Publishing that starts or stops failing (the network gone: no route, the
 * interface down) is said in the log once each way, looked at each second:
 * meanwhile no STATUS reaches anyone, so the log is the one place it shows.
 * The simulation runs on; STATUS msgs_dropped counts what was lost. */
static void publishing(wgd *d)
{
    stats *s = &d->stat;
    uint64_t now = d->io.dropped, lost = now - s->pub_dropped;
    s->pub_dropped = now;
    if (lost && !s->pub_failing) {
        s->pub_failing = 1, s->pub_failed_from = now - lost;
        log_msg(&d->log, LOG_WARNING, "publishing on LCM fails: %s (%llu messages in the last "
                "second); the simulation runs on, and a line here says when messages go out "
                "again", strerror(d->io.send_errno), (unsigned long long)lost);
    } else if (!lost && s->pub_failing) {
        s->pub_failing = 0;
        log_msg(&d->log, LOG_NOTICE, "publishing on LCM works again: %llu messages were not "
                "published (STATUS msgs_dropped counts them)",
                (unsigned long long)(now - s->pub_failed_from));
    }
}

void report_tick(wgd *d, int64_t now)
{
    stats *s = &d->stat;
    if (now >= s->next_flush_ns) {
        stream_flush(d);
        report_decimation(d);
        s->next_flush_ns = now + FLUSH_NS;
    }
    if (d->conf.scope_hz > 0 && now >= s->next_scope_ns) {
        stream_scope(d);
        s->next_scope_ns = now + (int64_t)(SEC_NS / d->conf.scope_hz);
    }
    if (now >= s->next_status_ns) {
        compute(d, now);
        wormgear_status_t m;
        char regime[24];
        fill_status(d, &m, regime, sizeof regime);
        lcmio_pub_status(&d->io, &m);
        interval_start(d, now);
        s->next_status_ns = now + (int64_t)(SEC_NS / d->conf.status_hz);
    }
    if (now >= s->next_params_ns) {
        report_params(d, "periodic", "", -1, 0);
        publishing(d);
        s->next_params_ns = now + SEC_NS;
        char line[400];
        report_line(d, line, sizeof line);
        sdn_status(line);
    }
    if (d->conf.foreground && now >= s->next_fg_ns) {
        foreground(d);
        s->next_fg_ns = now + SEC_NS;
    }
}

/* loop.c - libev loop: LCM, timerfd pacing, fast-mode idle, signals. */
#include "loop.h"

#include "cmd.h"
#include "engine.h"
#include "lockstep.h"
#include "report.h"
#include "sdn.h"
#include "snap.h"
#include "wgd.h"
#include "wormgear/wg_status.h"

#include <errno.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <string.h>
#include <sys/timerfd.h>
#include <unistd.h>

/* The most stepping one handler does before the loop polls again, and
 * the slices it runs in: between slices a message waiting on the LCM
 * descriptor (one poll, ~1.4 us here) ends the chunk, so a command waits
 * at most about one slice behind the integrator, not a whole chunk. */
enum { WORK_CHUNK_NS = 1000000, WORK_SLICE_NS = 100000 };

static int arm_timer(wgd *d)
{
    struct timespec now;
    clock_gettime(CLOCK_MONOTONIC, &now);
    long tick = d->conf.tick_us * 1000L;
    struct itimerspec its = {.it_interval = {tick / 1000000000L, tick % 1000000000L}};
    its.it_value = now;
    its.it_value.tv_nsec += tick;
    its.it_value.tv_sec += its.it_value.tv_nsec / 1000000000L;
    its.it_value.tv_nsec %= 1000000000L;
    return timerfd_settime(d->tfd, TFD_TIMER_ABSTIME, &its, NULL);
}

/* Steps a chunk (a slice) of work may run, from the measured cost of a
 * step. */
static uint64_t chunk(const wgd *d, int64_t ns)
{
    return pace_fast_chunk(d->stat.ns_per_step, ns);
}

static int running_in(const wgd *d, int mode)
{
    return d->run == RUN_RUNNING && d->conf.mode == mode;
}

/* Is there stepping to do: a step job, owed ticks or realtime steps, or
 * fast mode? */
static int work_pending(const wgd *d)
{
    return inbox_waiting(&d->in) || d->step.active ||
           (d->owed.ticks && running_in(d, MODE_LOCKSTEP)) ||
           (d->owed.realtime && running_in(d, MODE_REALTIME)) || running_in(d, MODE_FAST);
}

/* Start or stop the work watcher to match what is pending. Called at the
 * end of each handler, as redis runs its before-sleep hook: whatever a
 * command, a reload or a fault changed is matched before the loop polls
 * again, and no module below the loop knows the watcher. */
static void sync_work(wgd *d)
{
    int want = work_pending(d);
    if (want && !ev_is_active(&d->work_w))
        ev_idle_start(d->loop, &d->work_w);
    else if (!want && ev_is_active(&d->work_w))
        ev_idle_stop(d->loop, &d->work_w);
}

/* At most n steps of the most urgent stepping: a step job, owed ticks,
 * realtime steps due, fast mode. 0 when there was none to do. */
static int step_slice(wgd *d, uint64_t n)
{
    if (d->step.active) {
        cmd_step_progress(d, n);
    } else if (d->owed.ticks && running_in(d, MODE_LOCKSTEP)) {
        lockstep_progress(d, n);
    } else if (d->owed.realtime && running_in(d, MODE_REALTIME)) {
        n = n < d->owed.realtime ? n : d->owed.realtime;
        uint64_t done = cmd_run(d, n);
        d->owed.realtime = done < n ? 0 : d->owed.realtime - done;
    } else if (running_in(d, MODE_FAST)) {
        cmd_run(d, n);
    } else {
        return 0;
    }
    return 1;
}

/* One chunk of the most urgent work: commands waiting, else stepping, in
 * slices; a message on the LCM descriptor ends the chunk early (the
 * higher-priority LCM watcher runs next, the work watcher after it). */
static void work_chunk(wgd *d)
{
    if (inbox_waiting(&d->in)) {
        cmd_process(d, WORK_CHUNK_NS);
        return;
    }
    uint64_t left = chunk(d, WORK_CHUNK_NS), slice = chunk(d, WORK_SLICE_NS);
    while (left && step_slice(d, left < slice ? left : slice)) {
        left -= left < slice ? left : slice;
        if (left && lcmio_waiting(&d->io))
            break;
    }
}

/* The interval since the last tick: wall time, the loop's CPU time and
 * its longest handler, measured from the start of that tick to the start
 * of this one (both clocks over the same span: the CPU time used to start
 * after the last tick's own stepping, so a loop that did nothing but step
 * read as "not scheduled"); then the marks move to now. */
static pace_load interval(wgd *d, int64_t now)
{
    stats *s = &d->stat;
    int64_t cpu = log_cpu_ns();
    pace_load l = {.gap_ns = s->tick_ns ? now - s->tick_ns : 0,
                   .cpu_ns = s->tick_ns ? cpu - s->tick_cpu_ns : 0,
                   .busiest_ns = s->busiest_ns, .steps = d->sim.steps - s->tick_steps,
                   .ns_per_step = s->ns_per_step, .h = wg_sim_step_tau(&d->sim),
                   .rate = d->conf.rate};
    s->tick_ns = now, s->tick_cpu_ns = cpu, s->busiest_ns = 0, s->tick_steps = d->sim.steps;
    return l;
}

/* Realtime: run the steps due now; apply the overrun policy. */
static void realtime(wgd *d, int64_t now, const pace_load *load)
{
    pace_due due = pace_steps_due(&d->pace, now, d->sim.tau, wg_sim_step_tau(&d->sim));
    if (due.overrun) { /* how far behind, and whose time it was */
        char text[640];
        pace_overrun_text(&d->pace, load, text, sizeof text);
        log_msg(&d->log, LOG_WARNING, "overrun: %s", text); /* its own rate-limit slot */
    }
    d->owed.realtime = due.steps; /* recomputed from tau each tick: never counted twice */
    work_chunk(d);
    if (due.stop && !d->fault) {
        char msg[160];
        snprintf(msg, sizeof msg, "stopped after %d consecutive overruns (overrun_policy = "
                 "stop): cannot keep up with rate %g", d->conf.overrun_stop_after, d->conf.rate);
        engine_fault(d, msg);
        report_fault(d);
        /* paused: a set waiting for the section would wait for a resume */
        cmd_sync_check(d, "the overrun stop (the run faulted and paused: STATUS says why)");
    }
}

static void first_ready(wgd *d)
{
    char line[800];
    if (d->sd.ready || (d->sim.steps == 0 && d->run == RUN_RUNNING &&
                        d->conf.mode != MODE_LOCKSTEP))
        return;
    snprintf(line, sizeof line, "scene %s, %s rate %g, N = %d, channels %s* on %s",
             d->scene.name, conf_mode_name(d->conf.mode), d->conf.rate,
             d->sim.cfg.steps_per_period, d->conf.prefix, d->conf.url);
    sdn_ready(&d->sd, line);
    log_msg(&d->log, LOG_INFO, "ready: %s", line);
}

static void reload(wgd *d);

static void on_tick(struct ev_loop *loop, ev_io *w, int revents)
{
    (void)loop;
    (void)revents;
    wgd *d = w->data;
    uint64_t expirations;
    if (read(d->tfd, &expirations, sizeof expirations) < 0 && errno != EAGAIN)
        log_msg(&d->log, LOG_ERR, "timerfd read: %s", strerror(errno));
    int64_t t0 = log_now_ns();
    pace_load load = interval(d, t0);
    if (d->reload)
        reload(d);
    if (running_in(d, MODE_REALTIME))
        realtime(d, t0, &load);
    report_tick(d, t0);
    sdn_watchdog(&d->sd, t0); /* only a loop that steps reaches this */
    first_ready(d);
    report_loop(d, log_now_ns() - t0);
    sync_work(d);
}

/* Idle (no I/O pending): one chunk of work. Commands, which arrive on the
 * higher-priority LCM watcher, are handled between chunks. */
static void on_work(struct ev_loop *loop, ev_idle *w, int revents)
{
    (void)loop;
    (void)revents;
    wgd *d = w->data;
    int64_t t0 = log_now_ns();
    work_chunk(d);
    report_loop(d, log_now_ns() - t0);
    sync_work(d);
}

static void on_lcm(struct ev_loop *loop, ev_io *w, int revents)
{
    (void)loop;
    (void)revents;
    wgd *d = w->data;
    lcmio_drain(&d->io, 256); /* CMD (cmd.c) and TICK (lockstep.c) handlers: quick */
    cmd_process(d, WORK_CHUNK_NS);
    sync_work(d);
}

static void on_signal(struct ev_loop *loop, ev_signal *w, int revents)
{
    (void)revents;
    wgd *d = w->data;
    if (w->signum == SIGHUP) {
        d->reload = 1; /* the next tick reloads */
        return;
    }
    d->stop = w->signum;
    ev_break(loop, EVBREAK_ALL);
}

/* Apply hooks of the live keys (conf_reload calls them when one changed). */
static void apply_mode(void *ctx, const conf *was)
{
    wgd *d = ctx;
    (void)was;
    cmd_mode_changed(d, "a mode change (reload)");
}

static void apply_tick(void *ctx, const conf *was)
{
    wgd *d = ctx;
    (void)was;
    if (arm_timer(d))
        log_msg(&d->log, LOG_ERR, "reload: timerfd: %s", strerror(errno));
}

static void apply_verbose(void *ctx, const conf *was)
{
    wgd *d = ctx;
    (void)was;
    log_configure(&d->log, d->conf.verbose, d->conf.log_prefix);
}

static void apply_key(void *ctx, const conf *was)
{
    wgd *d = ctx;
    char why[640];
    if (cmd_key_load(d, why, sizeof why)) {
        log_msg(&d->log, LOG_ERR, "reload: %s; keeping the previous key", why);
        snprintf(d->conf.command_key_file, sizeof d->conf.command_key_file, "%s",
                 was->command_key_file);
    } else {
        log_msg(&d->log, LOG_NOTICE, "reload: %s", d->auth.on ? "signed commands only, new key"
                                                               : "unsigned commands accepted");
    }
}

/* SIGHUP with the same command_key_file: the file read again, so a key
 * rotated in place (a new key written over the file) takes effect; the
 * same key keeps the clients' counters (auth_load), a file that cannot be
 * read keeps the running key. */
static void reread_key(wgd *d)
{
    char why[640];
    int64_t since = d->auth.since_us;
    if (cmd_key_load(d, why, sizeof why))
        log_msg(&d->log, LOG_ERR, "reload: %s; keeping the running key", why);
    else if (d->auth.since_us != since)
        log_msg(&d->log, LOG_NOTICE, "reload: %s holds a new key: signed commands only under it "
                "(from %g s on)", d->auth.path, AUTH_AHEAD_S);
}

static void apply_contacts(void *ctx, const conf *was)
{
    wgd *d = ctx;
    (void)was;
    stream_flush(d); /* a CONTACT message holds one setting */
    stream_set_contacts(&d->st, d->conf.contacts, d->conf.bearing_every);
}

static const conf_apply_fn hooks[CONF_NAPPLY] = {
    [CONF_APPLY_MODE] = apply_mode, [CONF_APPLY_TICK] = apply_tick,
    [CONF_APPLY_VERBOSE] = apply_verbose, [CONF_APPLY_KEY] = apply_key,
    [CONF_APPLY_CONTACTS] = apply_contacts};

/* SIGHUP: re-read the configuration; live keys now, restart-only ones
 * logged. Pacing re-anchors and PARAMS goes out as after any reload. */
static void reload(wgd *d)
{
    conf c;
    char why[640], kept[200], held[200];
    int state;
    d->reload = 0;
    sdn_reloading(&d->sd);
    if (conf_load(&c, d->argc, d->argv, why, sizeof why) ||
        (strcmp(c.state_dir, d->conf.state_dir) && /* a new one is checked as at start */
         snap_dir_check(c.state_dir, 1, &state, why, sizeof why))) {
        log_msg(&d->log, LOG_ERR, "reload: %s; keeping the running configuration", why);
    } else {
        int same_key = !strcmp(c.command_key_file, d->conf.command_key_file);
        conf_reload(&d->conf, &d->conf_loaded, &c, hooks, d, kept, sizeof kept, held,
                    sizeof held);
        if (held[0])
            log_msg(&d->log, LOG_NOTICE, "reload: %s kept as set by command (the configuration "
                    "did not change %s)", held, strchr(held, ' ') ? "them" : "it");
        if (same_key && d->conf.command_key_file[0])
            reread_key(d);
        if (kept[0])
            log_msg(&d->log, LOG_WARNING, "reload: %s changes take effect at the next restart",
                    kept);
        pace_configure(&d->pace, &d->conf, d->scene.scale.omega_n_rad_s, log_now_ns(),
                       d->sim.tau);
        report_change(d, REPORT_RATE, "reload", "", -1, 0);
        log_msg(&d->log, LOG_NOTICE, "reloaded %s: mode %s, rate %g",
                d->conf.path[0] ? d->conf.path : "(no config file)",
                conf_mode_name(d->conf.mode), d->conf.rate);
    }
    char line[400];
    report_line(d, line, sizeof line);
    sdn_ready(&d->sd, line);
}

static void start_signal(wgd *d, ev_signal *w, int signum)
{
    ev_signal_init(w, on_signal, signum);
    w->data = d;
    ev_signal_start(d->loop, w);
}

void loop_hold_signals(int hold)
{
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT), sigaddset(&set, SIGTERM), sigaddset(&set, SIGHUP);
    pthread_sigmask(hold ? SIG_BLOCK : SIG_UNBLOCK, &set, NULL);
}

int loop_init(wgd *d)
{
    d->tfd = -1;
    d->loop = ev_loop_new(EVFLAG_AUTO);
    if (!d->loop) {
        snprintf(d->init_why, sizeof d->init_why, "libev: cannot create the event loop");
        return WG_EIO;
    }
    d->tfd = timerfd_create(CLOCK_MONOTONIC, TFD_NONBLOCK | TFD_CLOEXEC);
    if (d->tfd < 0 || arm_timer(d)) {
        snprintf(d->init_why, sizeof d->init_why, "timerfd: %s", strerror(errno));
        return WG_EIO;
    }
    ev_io_init(&d->tick_w, on_tick, d->tfd, EV_READ);
    ev_io_init(&d->lcm_w, on_lcm, lcmio_fileno(&d->io), EV_READ);
    ev_idle_init(&d->work_w, on_work);
    d->tick_w.data = d->lcm_w.data = d->work_w.data = d;
    ev_set_priority(&d->lcm_w, EV_MAXPRI); /* commands before stepping */
    ev_io_start(d->loop, &d->tick_w);
    ev_io_start(d->loop, &d->lcm_w);
    start_signal(d, &d->sig_int, SIGINT);
    start_signal(d, &d->sig_term, SIGTERM);
    start_signal(d, &d->sig_hup, SIGHUP);
    loop_hold_signals(0); /* libev's handlers take them from here */
    /* A closed stdout or stderr (`wormgeard -F | head`) killed the daemon
     * with no clean shutdown; ignored, a write fails with EPIPE instead,
     * which the log and the foreground line take in their stride. */
    signal(SIGPIPE, SIG_IGN);
    pace_configure(&d->pace, &d->conf, d->scene.scale.omega_n_rad_s, log_now_ns(),
                   d->sim.tau);
    sync_work(d);
    return WG_OK;
}

void loop_fini(wgd *d)
{
    if (d->loop) {
        ev_io_stop(d->loop, &d->tick_w);
        ev_io_stop(d->loop, &d->lcm_w);
        ev_idle_stop(d->loop, &d->work_w);
        ev_signal_stop(d->loop, &d->sig_int);
        ev_signal_stop(d->loop, &d->sig_term);
        ev_signal_stop(d->loop, &d->sig_hup);
        ev_loop_destroy(d->loop);
        d->loop = NULL;
    }
    if (d->tfd >= 0)
        close(d->tfd);
    d->tfd = -1;
}

void loop_run(wgd *d) { ev_run(d->loop, 0); }

/* main.c - wormgeard: start the modules in dependency order, run the loop,
 * finalise in reverse. Exit 0 on SIGTERM/SIGINT, 1 on a runtime failure at
 * start, 2 on a usage or configuration error. */
#include "cmd.h"
#include "engine.h"
#include "lockstep.h"
#include "loop.h"
#include "report.h"
#include "sdn.h"
#include "snap.h"
#include "wgd.h"
#include "wormgear/wg_status.h"

#include <errno.h>
#include <pthread.h>
#include <sched.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/mman.h>

static int m_engine(wgd *d)
{
    int rc = engine_init(d);
    return rc == WG_OK ? 0 : rc == WG_ENOMEM ? 1 : 2; /* bad scene/params: config error */
}

/* Real-time scheduling before LCM starts its receive thread, which inherits
 * it (as does every later thread): a command waits for no CPU hog. */
static void rt_sched(wgd *d)
{
    struct sched_param sp = {.sched_priority = d->conf.rt_priority};
    int e = pthread_setschedparam(pthread_self(), SCHED_FIFO, &sp);
    if (e)
        log_msg(&d->log, LOG_WARNING, "rt_priority %d: SCHED_FIFO refused: %s (needs CAP_SYS_NICE "
                "or ulimit -r; under systemd: CPUSchedulingPolicy=fifo, RestrictRealtime=no); "
                "running on the normal scheduler", d->conf.rt_priority, strerror(e));
    else
        log_msg(&d->log, LOG_INFO, "rt_priority %d: every thread runs SCHED_FIFO",
                d->conf.rt_priority);
}

static int m_lcm(wgd *d)
{
    if (d->conf.mlock && !d->conf.check_only && mlockall(MCL_CURRENT | MCL_FUTURE) != 0)
        log_msg(&d->log, LOG_WARNING, "mlockall: %s (raise LimitMEMLOCK=)", strerror(errno));
    if (d->conf.rt_priority > 0 && !d->conf.check_only)
        rt_sched(d);
    if (!d->conf.check_only && log_start(&d->log)) /* after rt_sched: the writer inherits it */
        log_msg(&d->log, LOG_WARNING, "log: no writer thread (%s): lines are written in the "
                "loop, which a stalled stderr or stdout stops", strerror(errno));
    /* --check-config sends and writes nothing. The URL is opened, so that
     * LCM judges it (and a udpm:// one's multicast route), but nothing is
     * subscribed: LCM's self-test datagram, sent at the first subscription,
     * stays unsent. A file:// URL is not opened (in mode w it makes a log),
     * nor a tcpq:// one (it connects to its server). */
    if (d->conf.check_only &&
        (!strncmp(d->conf.url, "file://", 7) || !strncmp(d->conf.url, "tcpq://", 7))) {
        log_msg(&d->log, LOG_INFO, "url %s: not opened by --check-config (a file:// URL may "
                "write its file, a tcpq:// one connects)", d->conf.url);
        return 0;
    }
    int rc = lcmio_init(&d->io, d->conf.url, d->conf.prefix, d->init_why, sizeof d->init_why);
    return rc == WG_OK ? 0 : rc == WG_EINVAL ? 2 : 1; /* a URL LCM refuses: a config error */
}

static int m_stream(wgd *d)
{
    int on = d->conf.state_rate_hz > 0 || d->conf.state_decimation > 0;
    stream_init(&d->st, d->sim.nstate, &d->scene.scale, on);
    stream_set_contacts(&d->st, d->conf.contacts, d->conf.bearing_every);
    return 0;
}

/* The state directory, checked at start so that a save does not fail for
 * it much later (made if missing, as systemd's StateDirectory= would;
 * --check-config changes nothing and says it would be made), then the
 * temporary files of saves killed mid-write. */
static int m_snap(wgd *d)
{
    int n = 0, state;
    char why[sizeof d->init_why];
    if (snap_dir_check(d->conf.state_dir, !d->conf.check_only, &state, d->init_why,
                       sizeof d->init_why))
        return 2;
    if (state != SNAP_DIR_OK)
        log_msg(&d->log, LOG_INFO, "state dir %s %s", d->conf.state_dir,
                state == SNAP_DIR_MADE ? "made" : "does not exist yet: it is made at start");
    if (d->conf.check_only)
        return 0;
    if (snap_init(d->conf.state_dir, &n, why, sizeof why))
        log_msg(&d->log, LOG_WARNING, "%s: save and restore will fail", why);
    else if (n > 0)
        log_msg(&d->log, LOG_INFO, "state dir %s: removed %d temporary file%s of interrupted "
                "saves", d->conf.state_dir, n, n == 1 ? "" : "s");
    return 0;
}

static int m_key(wgd *d) { return cmd_key_init(d) ? 2 : 0; } /* the config's key file */
static int m_cmd(wgd *d) { return cmd_init(d) ? 1 : 0; }
static int m_lockstep(wgd *d) { return lockstep_init(d) ? 1 : 0; }
static int m_loop(wgd *d) { return loop_init(d) ? 1 : 0; }
static int m_report(wgd *d) { return report_init(d), 0; }
static int m_sdn(wgd *d) { return sdn_init(&d->sd), 0; }
static void f_lcm(wgd *d) { lcmio_fini(&d->io); }
static void f_stream(wgd *d) { stream_fini(&d->st); }
static void f_sdn(wgd *d) { sdn_fini(&d->sd); }
static void f_none(wgd *d) { (void)d; }

/* In dependency order; finalised in reverse. --check-config runs those that
 * check (a prefix): the rest subscribe, arm timers and take signals. */
static const struct module {
    const char *name;
    int (*init)(wgd *d); /* 0, 1 runtime failure, 2 config error */
    void (*fini)(wgd *d);
    int check; /* run by --check-config */
} modules[] = {
    {"snap", m_snap, f_none, 1},
    {"engine", m_engine, engine_fini, 1},
    {"lcm", m_lcm, f_lcm, 1},
    {"stream", m_stream, f_stream, 1},
    {"key", m_key, cmd_key_fini, 1},
    {"cmd", m_cmd, cmd_fini, 0},
    {"lockstep", m_lockstep, f_none, 0},
    {"loop", m_loop, loop_fini, 0},
    {"report", m_report, report_fini, 0},
    {"sdn", m_sdn, f_sdn, 0},
};
enum { NMOD = sizeof modules / sizeof modules[0] };

static void finish(wgd *d, int up_to)
{
    for (int i = up_to - 1; i >= 0; i--)
        modules[i].fini(d);
}

static void started(wgd *d)
{
    char kn[64];
    log_msg(&d->log, LOG_INFO,
            "scene %s (%s, kernel %s on %s, stepper %s, N = %d), mode %s rate %g, url %s, "
            "channels %s*, state dir %s", d->scene.name, wg_model_name(d->sim.cfg.model),
            wg_sim_kernel_name(&d->sim, kn, sizeof kn), wg_sim_isa_name(&d->sim),
            wg_stepper_name(d->sim.cfg.stepper),
            d->sim.cfg.steps_per_period, conf_mode_name(d->conf.mode), d->conf.rate,
            d->conf.url, d->conf.prefix, d->conf.state_dir);
    report_params(d, "start", "", -1, 0);
}

static int run(wgd *d)
{
    int i, rc = 0;
    for (i = 0; i < NMOD && !rc && (modules[i].check || !d->conf.check_only); i++)
        if ((rc = modules[i].init(d))) /* a config error: from which file, if one */
            log_msg(&d->log, LOG_ERR, "%s: %s%s%s%s", modules[i].name, d->init_why,
                    rc == 2 && d->conf.path[0] ? " (configuration: " : "",
                    rc == 2 && d->conf.path[0] ? d->conf.path : "",
                    rc == 2 && d->conf.path[0] ? " and the options)" : "");
    if (rc) {
        finish(d, i - 1);
        return rc;
    }
    d->conf_loaded = d->conf; /* what a reload compares its load with */
    if (d->conf.check_only) {
        printf("configuration ok: scene %s, N = %d, mode %s, rate %g, url %s, prefix %s, "
               "state dir %s%s%s\n", d->scene.name, d->sim.cfg.steps_per_period,
               conf_mode_name(d->conf.mode), d->conf.rate, d->conf.url, d->conf.prefix,
               d->conf.state_dir, d->conf.path[0] ? ", config " : "", d->conf.path);
        finish(d, i);
        return 0;
    }
    started(d);
    loop_run(d);
    log_msg(&d->log, LOG_INFO, "stopping on %s", strsignal(d->stop));
    stream_flush(d);
    report_status(d);
    finish(d, NMOD);
    sdn_stopping();
    return 0;
}

int main(int argc, char **argv)
{
    /* until the loop's watchers take them; a thread started before then (the
     * log's writer) could take one with the default action */
    loop_hold_signals(1);
    wgd *d = calloc(1, sizeof *d);
    if (!d) {
        fprintf(stderr, "wormgeard: out of memory\n");
        return 1;
    }
    d->argc = argc;
    d->argv = argv;
    d->tfd = -1;
    d->start_ns = log_now_ns();
    log_init(&d->log, 0);
    int rc = conf_load(&d->conf, argc, argv, d->init_why, sizeof d->init_why);
    if (rc == 2) /* one hint, whether or not the message names one already */
        fprintf(stderr, "wormgeard: %s%s\n", d->init_why,
                strstr(d->init_why, "--help") ? "" : " (see wormgeard --help)");
    if (rc == 0) {
        log_configure(&d->log, d->conf.verbose, d->conf.log_prefix);
        rc = run(d);
    } else if (rc == 1) {
        rc = 0;
    }
    log_fini(&d->log);
    free(d);
    return rc;
}

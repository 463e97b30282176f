/* engine.c - scene, sim, the step path and blow-up handling. */
#include "engine.h"

#include "wgd.h"
#include "wormgear/wg_status.h"

#include <inttypes.h>
#include <stdio.h>
#include <string.h>

static int apply_sets(wgd *d)
{
    const char *sets[CONF_MAX_SETS];
    for (int i = 0; i < d->conf.nsets; i++)
        sets[i] = d->conf.sets[i];
    return wg_scene_apply_sets(&d->scene, sets, d->conf.nsets, d->init_why,
                               sizeof d->init_why);
}

int engine_init(wgd *d)
{
    int rc = wg_scene_open(&d->scene, d->conf.scene, d->init_why, sizeof d->init_why);
    if (rc || (rc = apply_sets(d)))
        return rc;
    d->scene_params = d->scene.p;
    wg_sim_config cfg = {d->scene.model, d->conf.stepper, d->conf.steps_per_period};
    if ((rc = wg_sim_init(&d->sim, &d->scene.p, &cfg, d->init_why, sizeof d->init_why)))
        return rc;
    d->sim_ok = 1;
    double y[WG_NSTATE_MAX];
    wg_scene_initial(&d->scene, y);
    wg_sim_set_state(&d->sim, y, 0, 0.0);
    d->run = d->conf.start_paused ? RUN_PAUSED : RUN_RUNNING;
    return WG_OK;
}

void engine_fini(wgd *d)
{
    if (d->sim_ok)
        wg_sim_fini(&d->sim);
    d->sim_ok = 0;
}

uint64_t engine_run(wgd *d, uint64_t n, int *events)
{
    *events = 0;
    if (!n)
        return 0;
    wg_sink sink = stream_sink(d);
    uint64_t done = 0;
    int ramping = d->sim.ramp.active;
    double tau0 = d->sim.tau;
    int64_t t0 = log_now_ns();
    int rc = wg_sim_run(&d->sim, n, &sink, &done);
    d->stat.tau += d->sim.tau - tau0, d->stat.steps += done; /* the STATUS interval's run */
    double c = (double)(log_now_ns() - t0) / (double)(done ? done : 1);
    if (done >= 16) /* smoothed cost per step (drives fast-mode chunks) */
        d->stat.ns_per_step = d->stat.ns_per_step > 0 ? 0.8 * d->stat.ns_per_step + 0.2 * c : c;
    if (ramping && !d->sim.ramp.active)
        *events |= ENGINE_RAMP_ENDED;
    if (rc) {
        char msg[sizeof d->fault_msg];
        snprintf(msg, sizeof msg, "integration blew up after step %" PRIu64 " (tau = %.9g): %s;"
                 " kept the last good state and paused", d->sim.steps, d->sim.tau,
                 wg_status_str(rc));
        engine_fault(d, msg);
        *events |= ENGINE_FAULTED;
    }
    return done;
}

void engine_fault(wgd *d, const char *msg)
{
    d->fault = 1;
    engine_pause(d);
    snprintf(d->fault_msg, sizeof d->fault_msg, "%s", msg);
    log_msg(&d->log, LOG_ERR, "FAULT: %s", msg);
}

/* Owed steps lapse here (PROTOCOL.md, TICK): were they kept, a resume would
 * run them, and steps owed to a 1e9-step backlog of ticks would go on long
 * after the driver stopped. */
void engine_pause(wgd *d)
{
    d->run = RUN_PAUSED;
    d->owed = (backlog){0, 0};
}

void engine_restore(wgd *d)
{
    d->fault = 0;
    d->fault_msg[0] = 0;
    pace_anchor(&d->pace, log_now_ns(), d->sim.tau);
}

void engine_resume(wgd *d)
{
    d->run = RUN_RUNNING;
    engine_restore(d);
}

void engine_reset(wgd *d, int params)
{
    char why[320];
    stream_flush(d);
    if (params)
        wg_sim_set_params(&d->sim, &d->scene_params, why, sizeof why); /* valid at start */
    double y[WG_NSTATE_MAX];
    if (d->scene.has_state)
        wg_scene_initial(&d->scene, y);
    else
        wg_equilibrium(d->sim.cfg.model, &d->sim.p, y);
    wg_sim_reset(&d->sim);
    wg_sim_set_state(&d->sim, y, 0, 0.0);
    engine_restore(d);
}

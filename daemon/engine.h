/* engine.h - the simulation inside the daemon: scene, wg_sim, the step
 * path, blow-up handling.
 *
 * engine_run integrates with the stream sink and, on a non-finite or absurd
 * state (WG_ENONFINITE from wg_sim_run, which keeps the last good step),
 * raises a fault: the simulation paused on its last good state, health
 * FAULT until a resume, reset or restore. The daemon never exits on it.
 * The engine calls nothing above it: what a run did besides stepping (a
 * ramp ended, a fault was raised) is returned for the caller to announce
 * (cmd_run publishes PARAMS and STATUS). */
#ifndef WGD_ENGINE_H
#define WGD_ENGINE_H

#include <stdint.h>

struct wgd;

/* Load the scene, apply the --set overrides, set up the sim at the scene's
 * initial state. WG_OK or a return code (WG_E*) with d->init_why. */
int engine_init(struct wgd *d);

/* Free the sim. */
void engine_fini(struct wgd *d);

/* What engine_run did besides stepping (bits of *events). */
enum { ENGINE_RAMP_ENDED = 1, ENGINE_FAULTED = 2 };

/* Run n steps with the stream sink. Returns the steps done; on a blow-up
 * raises the fault (engine_fault) and returns fewer. *events receives the
 * ENGINE_* bits. Updates the step cost estimate. */
uint64_t engine_run(struct wgd *d, uint64_t n, int *events);

/* Back to the scene's initial state (tau = 0); with params also the scene's
 * parameters. Clears a fault and re-anchors pacing (engine_restore). */
void engine_reset(struct wgd *d, int params);

/* The state was put back (reset, restore, resume): clear a fault and
 * re-anchor pacing at the current simulated time. */
void engine_restore(struct wgd *d);

/* Pause with a fault message and log it (health FAULT until a resume,
 * reset or restore); the caller announces it (report_fault). */
void engine_fault(struct wgd *d, const char *msg);

/* Pause (the steps owed to TICKs and to realtime pacing lapse) or resume;
 * resume clears a fault and re-anchors pacing (engine_restore). */
void engine_pause(struct wgd *d);
void engine_resume(struct wgd *d);

#endif

/* engine.h - the simulation inside the daemon: scene, wg_sim, the step
 * path, blow-up handling.
 *
 * The step path is engine_run: it integrates with the stream sink and, on
 * a non-finite or absurd state (WG_ENONFINITE from wg_sim_run, which keeps
 * the last good step), raises a fault: health FAULT on STATUS at once, the
 * simulation paused on its last good state. The daemon never exits on it. */
#ifndef WGD_ENGINE_H
#define WGD_ENGINE_H

#include <stdint.h>

struct wgd;

/* Load the scene, apply the --set overrides, set up the sim at the scene's
 * initial state. WG_OK or a return code (WG_E*) with d->why. */
int engine_init(struct wgd *d);

/* Free the sim. */
void engine_fini(struct wgd *d);

/* Run n steps (the step path). Returns the steps done; on a blow-up raises
 * the fault and returns fewer. Updates the step cost estimate. */
uint64_t engine_run(struct wgd *d, uint64_t n);

/* Back to the scene's initial state (tau = 0); with params also the scene's
 * parameters. Clears a fault and re-anchors pacing (engine_restore). */
void engine_reset(struct wgd *d, int params);

/* The state was put back (reset, restore, resume): clear a fault and
 * re-anchor pacing at the current simulated time. */
void engine_restore(struct wgd *d);

/* Pause with a fault message (health FAULT until a resume/reset/restore). */
void engine_fault(struct wgd *d, const char *msg);

/* Pause or resume; resume clears a fault and re-anchors pacing
 * (engine_restore). */
void engine_pause(struct wgd *d);
void engine_resume(struct wgd *d);

#endif

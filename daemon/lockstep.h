/* lockstep.h - TICK, external lockstep (co-simulation, HIL): each tick_t a
 * driver sends owes nsteps more steps, which the loop runs in bounded
 * chunks through cmd_run. A tick taken has no answer; a tick not taken
 * (undecodable; with a key, not signed, stale or replayed; too many steps
 * owed) gets one ACK (op "tick"), is counted and told on STATUS and logged
 * with why, and changes nothing. Semantics:
 * lcmtypes/PROTOCOL.md, "TICK (external lockstep)" and "Signed ticks". */
#ifndef WGD_LOCKSTEP_H
#define WGD_LOCKSTEP_H

#include <stdint.h>

struct wgd;

/* Subscribe TICK (after cmd_init, which loads the key ticks are checked
 * with). WG_OK or WG_EIO with d->init_why. */
int lockstep_init(struct wgd *d);

/* Run at most max of the steps TICK messages asked for (lockstep and
 * running; otherwise they lapse); returns the steps run. */
uint64_t lockstep_progress(struct wgd *d, uint64_t max);

#endif

/* ctl_tick.h - `wgctl tick N [--wait]`: one TICK (lockstep) and, with
 * --wait, what came of it. A tick taken has no answer (lcmtypes/PROTOCOL.md,
 * "TICK"); a refused one an ACK with op "tick" naming it; STATUS shows the
 * steps run, or a mode or run in which a tick lapses (not lockstep, or
 * paused). */
#ifndef WG_CTL_TICK_H
#define WG_CTL_TICK_H

#include "bus.h"

#include <stdint.h>

/* Send one TICK owing nsteps on c. Without wait: say what was sent, 0 (or
 * 1 if it could not be published). With wait: take the STATUS before it
 * as the baseline (none within timeout_s: 1, nothing sent), send, and
 * watch STATUS for up to timeout_s more: 0 when the steps ran, 1 refused
 * (with why), lapsed or nothing seen. json: one object on stdout. */
int ctl_tick(bus *c, int64_t nsteps, int wait, double timeout_s, int json);

#endif

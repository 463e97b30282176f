/* cmd.h - the command channel: raw CMD subscription, manual decode,
 * validation through the parameter table, atomic apply, one ACK each.
 *
 * Subscribed raw (never the generated typed subscribe, which drops
 * undecodable messages silently): a message that does not decode is still
 * answered (EDECODE; client and seq recovered when the header is intact,
 * else "" / -1). Validation happens completely before anything changes;
 * refusals are logged (rate-limited) and counted. Also subscribes TICK for
 * external lockstep. Semantics and codes: lcmtypes/PROTOCOL.md. */
#ifndef WGD_CMD_H
#define WGD_CMD_H

#include <stddef.h>
#include <stdint.h>

struct wgd;

/* Subscribe CMD and TICK. WG_OK or WG_EIO with d->why. */
int cmd_init(struct wgd *d);

/* Nothing to release (subscriptions end with the lcm instance). */
void cmd_fini(struct wgd *d);

/* Handle one raw CMD payload (the subscription calls this; tests may too). */
void cmd_handle(struct wgd *d, const void *buf, size_t len);

/* Advance a pending `step` command by at most max steps; ACKs it when done
 * (or refuses it on a blow-up). Returns the steps run. */
uint64_t cmd_step_progress(struct wgd *d, uint64_t max);

/* Refuse a pending `step` (pause, reset, mode change) with return code
 * code (WG_E*) and why. */
void cmd_step_cancel(struct wgd *d, int code, const char *why);

/* Apply and ACK a `set` waiting for the Poincare section (at_section), if
 * one is pending and the phase index is 0 (the engine calls this). */
void cmd_sync_apply(struct wgd *d);

/* Refuse a `set` waiting for the section (reset, restore, shutdown). */
void cmd_sync_cancel(struct wgd *d, int code, const char *why);

#endif

/* cmd.h - the command channel: raw CMD subscription, manual decode,
 * validation through the parameter table, atomic apply, one ACK each.
 *
 * Subscribed raw (never the generated typed subscribe, which drops
 * undecodable messages silently): a message that does not decode is still
 * answered (EDECODE; client and seq recovered when the header is intact,
 * else "" / -1). Validation happens completely before anything changes;
 * refusals are logged (rate-limited) and counted. TICK (external lockstep)
 * is lockstep.h's. Semantics and codes: lcmtypes/PROTOCOL.md. */
#ifndef WGD_CMD_H
#define WGD_CMD_H

#include <stddef.h>
#include <stdint.h>

struct wgd;

/* The command inbox, and CMD subscribed. WG_OK, or WG_ENOMEM or WG_EIO
 * with d->init_why and nothing left behind. */
int cmd_init(struct wgd *d);

/* The key of conf.command_key_file at the start (cmd_key_load), and once
 * it is in use the wait for its first second (auth_open_us). WG_OK, or
 * the load's error with d->init_why (a config error: nothing kept). */
int cmd_key_init(struct wgd *d);

/* Signing off, the key released. */
void cmd_key_fini(struct wgd *d);

/* Publish the one answer to a message on ACK: its client, seq and utime
 * echoed (client at most WIRE_MAX_CLIENT bytes, op 32), accepted when rc
 * is WG_OK, code and msg, the simulation's time and step count now. No
 * count or log line (the caller's: a command's or a tick's). */
void cmd_answer(struct wgd *d, const char *client, int64_t seq, int64_t utime, const char *op,
                int rc, const char *msg);

/* Take the key of conf.command_key_file ("" = none) for commands and
 * ticks (auth_load) and sign every message published with the key then in
 * use (lcmio_sign_with): at the start and at each reload. WG_OK, or
 * auth_load's error with why (the previous key kept, and still signing). */
int cmd_key_load(struct wgd *d, char *why, size_t whylen);

/* Pending step and set answers cancelled, the inbox released
 * (subscriptions end with the lcm instance). */
void cmd_fini(struct wgd *d);

/* Handle the commands waiting in the inbox, oldest first, until it is
 * empty or budget_ns has passed; returns how many were handled. */
int cmd_process(struct wgd *d, int64_t budget_ns);

/* Handle one raw CMD payload (cmd_process calls this; tests may too). */
void cmd_handle(struct wgd *d, const void *buf, size_t len);

/* The daemon's step path: run n steps, cut at the Poincare section when a
 * set waits for it (applied and ACKed on the section's step boundary, then
 * the rest run), and announce what the engine reports (a ramp's end on
 * PARAMS, a fault on STATUS at once). Returns the steps done: fewer after a
 * blow-up. */
uint64_t cmd_run(struct wgd *d, uint64_t n);

/* Advance a pending `step` command by at most max steps; ACKs it when done
 * (or refuses it on a blow-up). Returns the steps run. */
uint64_t cmd_step_progress(struct wgd *d, uint64_t max);

/* Refuse a pending `step` (pause, reset, mode change) with return code
 * code (WG_E*) and why. */
void cmd_step_cancel(struct wgd *d, int code, const char *why);

/* A set waiting for the next Poincare section, when what it waited for
 * may have gone (a step command cancelled while paused, a fault): if no
 * section comes now, it is refused (ESTATE, "set at the next section
 * cancelled by " cause, why none comes and what to do) and never applied
 * later; if one still comes, it waits on. */
void cmd_sync_check(struct wgd *d, const char *cause);

/* The mode has just changed (d->conf.mode is the new one; the mode command,
 * a reload): outside lockstep a `step` is cancelled (ESTATE, "cancelled by
 * " cause), the steps owed to TICKs lapse, and a set waiting for the
 * section that step was to reach is refused (cmd_sync_check); outside
 * realtime the steps the pace owed lapse. */
void cmd_mode_changed(struct wgd *d, const char *cause);

#endif

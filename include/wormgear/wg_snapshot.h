/* wg_snapshot.h - the snapshot file format: a wg_snapshot (wg_sim.h) and the
 * name of its scene as text, for the daemon's save/restore and for any tool
 * that reads a saved state.
 *
 * Format 3: one "key = value" per line (LF), every field exactly once, in
 * this order:
 *   # wormgeard snapshot, format 3
 *   scene = table3                1-63 printable ASCII characters
 *   model = consistent            consistent | printed
 *   stepper = rk4-event           rk4 | rk4-event
 *   steps_per_period = 128
 *   param omega = 0x1.599999999999ap+0     every parameter, in the table's order
 *                                 (format 2: without the body rows z1 ... j2)
 *   y 0 = ...                     the model's 14 or 16 state values
 *   k, tau, tau_c, period, steps
 *   ramp = none | NAME            with a NAME: ramp.from, ramp.to, ramp.tau0,
 *                                 ramp.duration (an inactive ramp's old fields
 *                                 are not state: they read back as 0)
 *   cur.period, cur.min_xn, cur.max_xn, cur.motion, then per bearing
 *   cur.x1.impacts, cur.x1.vmax ... cur.z2.vmax (format 2: none, read as
 *   0), cur.impacts, and last.*
 *   blake2b-256 = <64 lowercase hex digits>
 * Reals are C99 hex floats as printf's %a writes them (a restore is
 * bit-exact), counters are decimal, motions are names. The parser accepts
 * exactly what the formatter writes: no other spelling of a number, no sign,
 * leading zero, space or CR, no missing, extra, repeated or reordered line.
 * The last line is the BLAKE2b-256 (libsodium's crypto_generichash, no key)
 * of every byte before it, so `head -n -1 FILE | b2sum -l 256` shows it.
 * Format 2 (before the body data joined the table) is read too, its body
 * rows taken from the table's defaults; format 1 (earlier releases: no
 * checksum) is refused, since it cannot be verified. The parser checks syntax; whether the values make a run is
 * wg_sim_restore's to decide. Neither function prints, and no message ever
 * quotes the text it was given. */
#ifndef WG_SNAPSHOT_H
#define WG_SNAPSHOT_H

#include <stddef.h>

#include "wg_sim.h"

enum {
    WG_SNAPSHOT_FORMAT = 3,     /* the version written (3 and 2 are read) */
    WG_SNAPSHOT_MAX = 8192,     /* bytes: no snapshot is longer (they are ~2 kB) */
    WG_SNAPSHOT_SCENE_MAX = 64  /* scene name buffer, NUL included */
};

/* Write snap, taken in scene `scene`, as format 3 into buf (cap bytes;
 * WG_SNAPSHOT_MAX always suffices), NUL-terminated. Scene bytes outside
 * printable ASCII are written as '?', beyond 63 dropped. Returns the length
 * (without the NUL), or WG_ERANGE if cap is too small, or WG_EINVAL with why
 * when the text would not parse back (a value not finite, a model, stepper,
 * motion or ramp parameter without a name): a written snapshot always reads
 * back. */
int wg_snapshot_format(const wg_snapshot *snap, const char *scene, char *buf, size_t cap,
                       char *why, size_t whylen);

/* Read len bytes of text (no NUL needed) as format 3 or 2 into *snap and scene
 * (scenelen bytes, NUL-terminated; WG_SNAPSHOT_SCENE_MAX holds any). WG_OK,
 * or WG_EINVAL with why ("line 12: expected 'param xi_p = <hex float>'",
 * "checksum mismatch: ...", "a format 1 snapshot ...") and snap and scene
 * untouched; WG_EUNSUPPORTED if libsodium cannot start. */
int wg_snapshot_parse(const char *text, size_t len, wg_snapshot *snap, char *scene,
                      size_t scenelen, char *why, size_t whylen);

/* Read the snapshot file path and parse it (as wg_snapshot_parse). Only a
 * regular file of at most WG_SNAPSHOT_MAX bytes is read: judged before it
 * is opened (a FIFO or device is never opened), opened without following a
 * link or blocking, judged again once open. WG_OK; WG_EIO with why saying
 * what is there ("PATH is a FIFO, not a regular file", its size, the
 * error); or parse's codes, why prefixed with the path. No message quotes
 * the file's content. */
int wg_snapshot_load(const char *path, wg_snapshot *snap, char *scene, size_t scenelen,
                     char *why, size_t whylen);

#endif

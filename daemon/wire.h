/* wire.h - checks of raw CMD and TICK bytes before the generated decoder
 * sees them.
 *
 * lcm-gen 1.3.1's C decoders trust the wire: a negative or huge array or
 * string length is passed to malloc, a string need not be NUL-terminated,
 * and a decode that fails half-way leaks what it allocated. The command
 * and tick channels are open to anyone on the bus, so wormgeard walks the
 * cmd_t and tick_t layouts with bounds checks first (lcmtypes/msg_check.h,
 * the walk the clients run on what the daemon publishes; no allocation)
 * and decodes only messages
 * that will decode completely and exactly: no byte after the message, no
 * NUL inside a string, a MAC of 0 or 32 bytes. */
#ifndef WGD_WIRE_H
#define WGD_WIRE_H

#include "msg_check.h"

#include <stddef.h>
#include <stdint.h>

enum {
    WIRE_MAX_PARAMS = MSG_CMD_MAX_PARAMS, /* names[] / values[] on the wire (the table has 29) */
    WIRE_MAX_STRING = MSG_CMD_MAX_STRING, /* bytes of any string, without its NUL */
    WIRE_MAX_CLIENT = MSG_CMD_MAX_CLIENT, /* bytes of a client id (echoed in its ACK) */
    WIRE_MAC_BYTES = MSG_CMD_MAC_BYTES    /* a signed command's MAC (crypto_auth) */
};

/* WG_OK if buf holds exactly one complete, well-formed wormgear.cmd_t
 * (fingerprint, lengths in range: a client id of at most WIRE_MAX_CLIENT
 * bytes, other strings WIRE_MAX_STRING; strings NUL-terminated with no NUL
 * inside, at most WIRE_MAX_PARAMS names, mac_len 0 or WIRE_MAC_BYTES, no
 * trailing bytes), with *mac_len (may be NULL) set: a signed message ends
 * in its MAC (wg_mac_sealed); else WG_EDECODE and why names the field, what
 * was wrong and the limit ("field names[0]: a string of 5000 bytes, the
 * limit is 4096 (at byte 58 of 5104)"). */
int wire_cmd_check(const void *buf, size_t len, int32_t *mac_len, char *why, size_t whylen);

/* The same for a wormgear.tick_t (its client id at most WIRE_MAX_CLIENT
 * bytes). */
int wire_tick_check(const void *buf, size_t len, int32_t *mac_len, char *why, size_t whylen);

/* What an answer to a bad message can be addressed to: the seq and utime
 * (-1 and 0 if the fingerprint or the first 24 bytes are not there) and
 * the client id's first bytes, up to clen - 1 and the first NUL ("" if
 * unreadable), even when the id is longer than any limit. */
void wire_cmd_header(const void *buf, size_t len, char *client, size_t clen, int64_t *seq,
                     int64_t *utime);

/* The same for a wormgear.tick_t. */
void wire_tick_header(const void *buf, size_t len, char *client, size_t clen, int64_t *seq,
                      int64_t *utime);

/* A wormgear.status_t's seq and utime: 1, or 0 (and -1, 0) if the bytes do
 * not begin as one. */
int wire_status_header(const void *buf, size_t len, int64_t *seq, int64_t *utime);

#endif

/* wire.h - checks of raw CMD bytes before the generated decoder sees them.
 *
 * lcm-gen 1.3.1's C decoders trust the wire: a negative or huge array or
 * string length is passed to malloc, a string need not be NUL-terminated,
 * and a decode that fails half-way leaks what it allocated. The command
 * channel is open to anyone on the bus, so wormgeard walks the cmd_t layout
 * with bounds checks first (no allocation) and decodes only messages that
 * will decode completely. The layout below mirrors lcmtypes/cmd_t.lcm; a
 * unit test encodes a full cmd_t and checks the walk lands on its end. */
#ifndef WGD_WIRE_H
#define WGD_WIRE_H

#include <stddef.h>
#include <stdint.h>

enum { WIRE_MAX_PARAMS = 64, WIRE_MAX_STRING = 4096 };

/* WG_OK if buf holds a complete, well-formed wormgear.cmd_t (fingerprint,
 * lengths, NUL-terminated strings, at most WIRE_MAX_PARAMS names); else
 * WG_EDECODE with the reason in why ("truncated at byte 50 of 50", ...). */
int wire_cmd_check(const void *buf, size_t len, char *why, size_t whylen);

/* Best effort for an answer to a bad message: the client id and seq from an
 * intact header (fingerprint, utime, seq, client), else "" and -1. */
void wire_cmd_header(const void *buf, size_t len, char *client, size_t clen, int64_t *seq);

#endif

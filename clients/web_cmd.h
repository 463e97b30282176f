/* web_cmd.h - a Foxglove client's JSON command or setParameters request
 * turned into the daemon's cmd_t. Shape only: names, ranges and states are
 * the daemon's to judge (its ACK says why), so nothing is decided twice;
 * but mode's rate, whose 0 on the wire means "keep", is checked against
 * WG_RATE_MIN, WG_RATE_MAX (wg_sim.h, the daemon's bounds too).
 *
 * The /cmd topic's messages (clientPublish, encoding json):
 *   {"op":"set","params":{"omega":1.3},"at_section":true}
 *   {"op":"ramp","param":"omega","to":1.5,"duration":2,"unit":"s","from":0.5}
 *   {"op":"pause"}  {"op":"resume"}  {"op":"get"}  {"op":"step","nsteps":100}
 *   {"op":"reset","what":"params"}   {"op":"save","name":"a"}  {"op":"restore","name":"a"}
 *   {"op":"mode","mode":"fast","rate":1}
 * An optional "id" (string) comes back as request_id in the /ack message. */
#ifndef WEB_CMD_H
#define WEB_CMD_H

#include <cjson/cJSON.h>
#include <stddef.h>

#include "lcmtypes/wormgear_cmd_t.h"

#define WEB_CMD_MAX_PARAMS 64

/* Storage a cmd_t points into (strings and arrays). */
typedef struct web_cmd {
    wormgear_cmd_t cmd;
    char op[16], name[72], unit[8], id[64];
    char names[WEB_CMD_MAX_PARAMS][48];
    char *name_ptr[WEB_CMD_MAX_PARAMS];
    double values[WEB_CMD_MAX_PARAMS];
} web_cmd;

/* Fill c from a /cmd JSON object. 0, or -1 with the reason in why (the
 * field and what it must be). */
int web_cmd_from_json(web_cmd *c, const cJSON *j, char *why, size_t whylen);

/* What a client sends, parsed strictly (every text frame and /cmd payload):
 * one JSON value and nothing after it but white space, no object with a
 * key twice or more than WEB_JSON_MEMBERS_MAX members, no string holding
 * a NUL (\u0000), well-formed UTF-8 throughout (web_utf8_bad_at). cJSON
 * alone took '{"op":"get"}garbage' as a get, the first of two "op" keys
 * where JavaScript takes the last, "omega\u0000x" as omega, and invalid
 * UTF-8 (answered with U+FFFD in its place). The value (cJSON_Delete
 * it), or NULL with why. */
enum { WEB_JSON_MEMBERS_MAX = WEB_CMD_MAX_PARAMS }; /* no message has a larger object */
cJSON *web_json_parse(const void *p, size_t len, char *why, size_t whylen);

/* The offset of the first byte of p[0, len) that is not part of well-formed
 * UTF-8 (overlong forms, surrogates, above U+10FFFF and a sequence cut off
 * at the end included), or -1 when it is all well-formed. */
long web_utf8_bad_at(const void *p, size_t len);

/* Fill c with one atomic `set` from a setParameters `parameters` array
 * ([{name, value}], value a number). 0, or -1 with why. */
int web_cmd_from_setparams(web_cmd *c, const cJSON *params, char *why, size_t whylen);

#endif

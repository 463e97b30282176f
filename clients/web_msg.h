/* web_msg.h - wgweb's channels: the JSON form of each LCM message and the
 * JSON Schema advertised for it (Foxglove "json" encoding).
 *
 * One record per sample: a STATE sample becomes one /scope message, a
 * Poincare section one /poincare message, a contact event one /contact
 * message, so Foxglove's Plot panel plots `/scope.x_n` against the message
 * time (the simulated time t_s). Values stay dimensionless as on the wire;
 * each schema property's description gives its unit, and /params carries
 * the physical scale. */
#ifndef WEB_MSG_H
#define WEB_MSG_H

#include "lcmtypes/wormgear_ack_t.h"
#include "lcmtypes/wormgear_contact_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "web_json.h"

/* The server channels, ids as advertised (1..CHAN_N-1). */
enum msg_chan {
    CHAN_STATUS = 1, CHAN_PARAMS, CHAN_SCOPE, CHAN_POINCARE, CHAN_CONTACT, CHAN_ACK, CHAN_BRIDGE,
    CHAN_N
};

/* Topic ("/scope"), schema name ("wormgear.Scope") of channel c; NULL if
 * c is not a channel. */
const char *msg_topic(int c);
const char *msg_schema_name(int c);

/* The JSON Schemas of the channels (text), built once. */
typedef struct msg_schemas {
    char *text[CHAN_N];
} msg_schemas;

/* Build every schema (the /params one lists the parameter table's names).
 * 0, or -1 when out of memory (nothing kept). msg_schemas_fini frees them. */
int msg_schemas_init(msg_schemas *s);
void msg_schemas_fini(msg_schemas *s);

/* The JSON Schema of channel c; NULL if c is not a channel. */
const char *msg_schema(const msg_schemas *s, int c);

/* Names of the codes on the wire: motion (0..2), contact (0..6), contact
 * kind (0..3); "unknown" outside. */
const char *msg_motion_name(int code);
const char *msg_contact_name(int code);
const char *msg_kind_name(int code);

/* Append the JSON object of sample i of a STATE message. */
void msg_scope(jbuf *b, const wormgear_state_t *m, int i);

/* Append section i of a POINCARE message, with the daemon's latest regime. */
void msg_poincare(jbuf *b, const wormgear_poincare_t *m, int i, const char *regime);

/* Append event i of a CONTACT message. */
void msg_contact(jbuf *b, const wormgear_contact_t *m, int i);

/* Append a STATUS message (every field). */
void msg_status(jbuf *b, const wormgear_status_t *m);

/* Append a PARAMS message: scale, ramp, `values` {name: value} and the
 * table `params` [{name, unit, value, min, max, def, rampable}]. */
void msg_params(jbuf *b, const wormgear_params_t *m);

/* Append an ACK, with the Foxglove request it answers (request_id "" and
 * ws_client 0 when it answers no request of this bridge). */
void msg_ack(jbuf *b, const wormgear_ack_t *m, const char *request_id, unsigned ws_client);

#endif

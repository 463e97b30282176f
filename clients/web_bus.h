/* web_bus.h - wgweb's side of LCM: the daemon's channels in, commands out.
 *
 * Built on the clients' bus (bus.h: URL and prefix defaults, client id,
 * publishing a command); every received message is handed to a hook, and
 * seq gaps and restarts are counted per channel with bus_seq. */
#ifndef WEB_BUS_H
#define WEB_BUS_H

#include <stddef.h>
#include <stdint.h>

#include "bus.h"
#include "lcmtypes/wormgear_ack_t.h"
#include "lcmtypes/wormgear_cmd_t.h"
#include "lcmtypes/wormgear_contact_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "lcmtypes/wormgear_status_t.h"

/* Where each received message goes (any hook may be NULL). */
typedef struct web_bus_hooks {
    void *ctx;
    void (*state)(void *ctx, const wormgear_state_t *m);
    void (*poincare)(void *ctx, const wormgear_poincare_t *m);
    void (*contact)(void *ctx, const wormgear_contact_t *m);
    void (*status)(void *ctx, const wormgear_status_t *m);
    void (*params)(void *ctx, const wormgear_params_t *m);
    void (*ack)(void *ctx, const wormgear_ack_t *m);
    void (*ack_unverified)(void *ctx, const wormgear_ack_t *m); /* with a key: one it did not verify */
} web_bus_hooks;

enum { WEB_BUS_STATE, WEB_BUS_POINCARE, WEB_BUS_CONTACT, WEB_BUS_STATUS, WEB_BUS_PARAMS,
       WEB_BUS_ACK, WEB_BUS_NCH };

typedef struct web_bus {
    bus c;
    web_bus_hooks h;
    char url[256];
    lcm_subscription_t *sub[WEB_BUS_NCH];
    bus_seq seq[WEB_BUS_NCH];
    uint64_t msgs;             /* messages received, all channels */
} web_bus;

/* Open LCM on url with prefix (NULL: the defaults) and subscribe the
 * daemon's output channels. 0, or bus_open's -1 or BUS_EURL with a message
 * in why. */
int web_bus_open(web_bus *b, const char *url, const char *prefix, const web_bus_hooks *h,
                 char *why, size_t whylen);

/* Unsubscribe and close. Safe after a failed open. */
void web_bus_close(web_bus *b);

/* The LCM socket to watch for reading. */
int web_bus_fileno(const web_bus *b);

/* Handle up to max messages that are ready now (never blocks); the count. */
int web_bus_drain(web_bus *b, int max);

/* Publish a command on <prefix>CMD, stamped with this bridge's client id,
 * utime and the next seq: the one place where a command leaves wgweb.
 * Returns the seq, or -1. */
int64_t web_bus_send(web_bus *b, wormgear_cmd_t *cmd);

/* Why the last web_bus_send failed (bus_send's reason). */
const char *web_bus_send_why(const web_bus *b);

/* Messages missing in seq gaps, all channels; restarts of one channel. */
uint64_t web_bus_gaps(const web_bus *b);
uint64_t web_bus_restarts(const web_bus *b, int ch);

/* This bridge's client id ("wgweb-PID@host") and prefix. */
const char *web_bus_client_id(const web_bus *b);
const char *web_bus_prefix(const web_bus *b);

#endif

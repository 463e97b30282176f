/* web_bus.h - wgweb's side of LCM: the daemon's channels in, commands out.
 *
 * The only wgweb file that uses the shared client helpers (wgcli: URL and
 * prefix defaults, client id, publishing a command), so a rename there
 * touches one file here. Every received message is handed to a hook; seq
 * gaps and restarts (seq going backwards) are counted per channel. */
#ifndef WEB_BUS_H
#define WEB_BUS_H

#include <stddef.h>
#include <stdint.h>

#include "lcmtypes/wormgear_ack_t.h"
#include "lcmtypes/wormgear_cmd_t.h"
#include "lcmtypes/wormgear_contact_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "wgcli.h"

/* Where each received message goes (any hook may be NULL). */
typedef struct bus_hooks {
    void *ctx;
    void (*state)(void *ctx, const wormgear_state_t *m);
    void (*poincare)(void *ctx, const wormgear_poincare_t *m);
    void (*contact)(void *ctx, const wormgear_contact_t *m);
    void (*status)(void *ctx, const wormgear_status_t *m);
    void (*params)(void *ctx, const wormgear_params_t *m);
    void (*ack)(void *ctx, const wormgear_ack_t *m);
} bus_hooks;

enum { BUS_STATE, BUS_POINCARE, BUS_CONTACT, BUS_STATUS, BUS_PARAMS, BUS_ACK, BUS_NCH };

typedef struct bus {
    wgcli c;
    bus_hooks h;
    char url[256];
    void *sub[BUS_NCH];
    int64_t last_seq[BUS_NCH]; /* -1 before the first */
    uint64_t msgs;             /* messages received, all channels */
    uint64_t gaps;             /* messages missing in seq gaps, all channels */
    uint64_t restarts[BUS_NCH];
} bus;

/* $WORMGEAR_URL / $WORMGEAR_PREFIX or the daemon's defaults. */
const char *bus_default_url(void);
const char *bus_default_prefix(void);

/* Open LCM on url with prefix (NULL: the defaults) and subscribe the
 * daemon's output channels. 0, or -1 with a message in why. */
int bus_open(bus *b, const char *url, const char *prefix, const bus_hooks *h, char *why,
             size_t whylen);

/* Unsubscribe and close. Safe after a failed open. */
void bus_close(bus *b);

/* The LCM socket to watch for reading. */
int bus_fileno(const bus *b);

/* Handle up to max messages that are ready now (never blocks); the count. */
int bus_drain(bus *b, int max);

/* Publish a command on <prefix>CMD, stamped with this bridge's client id,
 * utime and the next seq. The one place where a command leaves wgweb (a
 * MAC will be added here, issue 10). Returns the seq, or -1. */
int64_t bus_send(bus *b, wormgear_cmd_t *cmd);

/* This bridge's client id ("wgweb-PID@host") and prefix. */
const char *bus_client_id(const bus *b);
const char *bus_prefix(const bus *b);

#endif

/* web_srv.h - wgweb's HTTP + WebSocket server (libwebsockets on the
 * program's libev loop): static files from the web root, and the
 * foxglove.websocket.v1 subprotocol handed to web_fox.
 *
 * Incoming frames are reassembled up to max_frame bytes; a larger one is
 * discarded with a status error on that client. Outgoing frames are taken
 * from the client's queues only when its socket is writable, so a client
 * that does not read only fills its own bounded queue. */
#ifndef WEB_SRV_H
#define WEB_SRV_H

#include <ev.h>
#include <libwebsockets.h>
#include <stddef.h>
#include <stdint.h>

#include "web_fox.h"
#include "web_json.h"

typedef struct srv_conf {
    const char *iface;    /* listen address, e.g. "127.0.0.1" */
    int port;             /* TCP port (0: any free one) */
    const char *web_root; /* directory of the dashboard's files (NULL: serve none) */
    size_t max_frame;     /* largest accepted incoming frame, bytes */
    const char *const *origins; /* web origins allowed besides our own (norigins) */
    int norigins;
} srv_conf;

typedef struct srv {
    struct lws_context *ctx;
    fox *fox;
    srv_conf conf;
    char root[4096];
    struct lws_http_mount mount;
    struct lws_protocols protos[3];
    jbuf out;          /* the frame being written (LWS_PRE in front) */
    int port;          /* the port bound */
    uint64_t oversized;
    uint64_t bad_origin;   /* WebSockets refused for their Origin */
    void *loops[1];
} srv;

/* Listen on conf's address and port, on loop. 0, or -1 with why. */
int srv_init(srv *s, struct ev_loop *loop, const srv_conf *conf, fox *f, char *why,
             size_t whylen);

/* Close every connection and the listener. */
void srv_fini(srv *s);

/* Ask for a writable callback on connection conn (a fox_client's conn). */
void srv_wake(srv *s, void *conn);

/* Close connection conn at its next writable callback. */
void srv_kick(srv *s, void *conn);

#endif

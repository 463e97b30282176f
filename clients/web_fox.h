/* web_fox.h - the Foxglove WebSocket protocol v1 (foxglove.websocket.v1),
 * server side, independent of the transport.
 *
 * The transport (web_srv) opens a client per connection, hands it every
 * complete frame it receives and asks for frames to send when the socket
 * is writable. Server channels are wgweb's (web_msg.h), JSON encoded with a
 * JSON Schema each. Capabilities: parameters, parametersSubscribe, time,
 * and clientPublish when commands are allowed. Every client has a control
 * queue (server info, advertise, status, parameter values; a client that
 * lets it overflow is disconnected) and a bounded data queue (messages and
 * time; oldest dropped and counted). Bad input from a client - not JSON,
 * unknown op, unknown channel or subscription id, oversized frames - gets
 * a status error on that client and changes nothing else. */
#ifndef WEB_FOX_H
#define WEB_FOX_H

#include <stddef.h>
#include <stdint.h>

#include "lcmtypes/wormgear_ack_t.h"
#include "lcmtypes/wormgear_cmd_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "web_json.h"
#include "web_msg.h"
#include "web_queue.h"

#define FOX_MAX_CLIENTS 64
#define FOX_MAX_CCHAN 16
#define FOX_RX_SAID_MAX 8 /* statuses one client message may get; the rest in one line */
#define FOX_MAX_PENDING 64
#define FOX_MAX_PARAMS 64

/* What the protocol needs from the program (registered, never called up). */
typedef struct fox_hooks {
    void *ctx;
    void (*wake)(void *ctx, void *conn);                 /* conn has frames to send */
    void (*kick)(void *ctx, void *conn);                 /* close conn */
    /* publish: its seq, or -1 with why (one phrase: the client's status says it) */
    int64_t (*command)(void *ctx, wormgear_cmd_t *cmd, char *why, size_t whylen);
} fox_hooks;

typedef struct fox_conf {
    const char *name;          /* serverInfo name */
    const char *prefix, *url;  /* serverInfo metadata */
    int allow_commands;        /* setParameters and clientPublish accepted */
    int max_clients;           /* 1 .. FOX_MAX_CLIENTS */
    size_t queue_len;          /* data queue bound per client, messages */
    size_t queue_bytes;        /* ... and payload bytes */
    double ack_timeout_s;      /* a command without ACK after this: status error */
    const msg_schemas *schemas;
} fox_conf;

typedef struct fox_client {
    int used;
    unsigned id;                 /* from 1, never reused */
    void *conn;                  /* the transport's handle */
    int64_t sub[CHAN_N];      /* subscription id per channel, -1 none */
    int64_t cchan[FOX_MAX_CCHAN]; /* client-advertised /cmd channel ids, -1 none */
    int psub_all;                /* subscribed to every parameter's updates */
    uint64_t psub_mask;          /* ... or to these (snapshot index) */
    wq ctrl, data;
    uint64_t sent, errors;
} fox_client;

typedef struct fox_pending {
    int used;
    int64_t seq, utime; /* cmd seq and utime on the bus (its ACK echoes both) */
    unsigned client;   /* fox_client id */
    int setparams;     /* a setParameters request (answer with parameterValues) */
    char id[64];       /* the request's id ("" none) */
    double deadline_s;
    int n;             /* setParameters: the names and values asked for */
    char name[FOX_MAX_PARAMS][48];
    double value[FOX_MAX_PARAMS];
    char unverified[200]; /* an answer the bridge's key did not verify: "CODE: message" */
    char op[16];       /* "setParameters" or the /cmd op, for the client's statuses */
    int late;          /* answered only when done (a step, a set at_section): kept past */
    int overdue;       /* ... its deadline, so that its ACK still reaches the client */
} fox_pending;

typedef struct fox {
    fox_conf conf;
    fox_hooks hooks;
    fox_client cl[FOX_MAX_CLIENTS];
    unsigned next_id;
    wq_msg *advertise;   /* the advertise message, built once */
    fox_pending pend[FOX_MAX_PENDING];
    int np;              /* the daemon's parameter table, last PARAMS */
    char pname[FOX_MAX_PARAMS][32];
    double pvalue[FOX_MAX_PARAMS];
    uint64_t queue_drops, kicked, bad_frames;
    char session[32];
    char name[160], prefix[64], url[256]; /* copies of the conf strings */
    double now_s;        /* wall time of the last fox_tick */
    int rx_in, rx_ci;    /* in fox_rx, for client rx_ci: */
    int rx_said, rx_unsaid; /* its statuses so far, and those held back */
    jbuf tmp;
} fox;

/* Build the advertise message and empty client table. 0, or -1. */
int fox_init(fox *f, const fox_conf *conf, const fox_hooks *hooks);

/* Release every client's queues and the pending table. */
void fox_fini(fox *f);

/* A new connection: sends serverInfo and advertise. The client index, or
 * -1 when the table is full (the transport closes the connection). */
int fox_open(fox *f, void *conn);

/* The connection of client ci is gone: its subscriptions and queues go. */
void fox_close(fox *f, int ci);

/* One complete text (binary = 0) or binary frame from client ci. */
void fox_rx(fox *f, int ci, const unsigned char *p, size_t len, int binary);

/* Send a status message (level 0 info, 1 warning, 2 error) to client ci,
 * or to every client when ci < 0. */
void fox_status(fox *f, int ci, int level, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* The next frame for client ci into out (reset first): 1 with *binary set,
 * or 0 when nothing is queued. */
int fox_frame(fox *f, int ci, jbuf *out, int *binary);

/* Whether client ci has frames queued. */
int fox_has_frames(const fox *f, int ci);

/* Whether any subscriber of channel c exists (to skip encoding). */
int fox_wanted(const fox *f, int c);

/* A message of JSON text on channel c, message time ts_ns, to every
 * subscriber of c (encoded once, shared). */
void fox_publish(fox *f, int c, const char *json, size_t len, uint64_t ts_ns);

/* A Time message to every client. */
void fox_time(fox *f, uint64_t ts_ns);

/* Send the advertise message again to every client (daemon restart). */
void fox_readvertise(fox *f);

/* A PARAMS message: the snapshot for getParameters, and parameterValues
 * of the changed parameters to their subscribers. */
void fox_params(fox *f, const wormgear_params_t *m);

/* The request an ACK answers: copies its id (or "") and returns the client
 * id (0 none). Does not consume it. */
unsigned fox_ack_owner(const fox *f, const wormgear_ack_t *a, const char *client_id, char *id,
                       size_t idlen);

/* An ACK of one of our commands (client_id: this bridge's): a refused
 * setParameters or command becomes a status error on the client that sent
 * it, with the daemon's code and reason; setParameters gets its
 * parameterValues. */
void fox_ack(fox *f, const wormgear_ack_t *a, const char *client_id);

/* An answer to one of our commands that this bridge's key did not verify
 * (lcmtypes/PROTOCOL.md, "Signed answers"): not taken, but kept, so that
 * the timeout says what came instead of asking whether a daemon runs. */
void fox_ack_unverified(fox *f, const wormgear_ack_t *a, const char *client_id);

/* Wall time now_s: a command without ACK by its deadline gets a status
 * naming its op and id; one answered only when done (a step, a set at the
 * next section) may still be running, so it is kept, and its ACK, when it
 * comes, is a second and final status for that id. */
void fox_tick(fox *f, double now_s);

/* Number of connected clients. */
int fox_nclients(const fox *f);

/* Append "per_client":[{id, queue, queue_bytes, ctrl, drops, sent, errors}]. */
void fox_stats(const fox *f, jbuf *b);

#endif

/* bus.h - the daemon as the LCM clients (wgctl, wgmon, wgrig; the system
 * test and the daemon benchmark) see it: the URL/prefix defaults, channel
 * names, a client id, sending a command and waiting for its ACK.
 *
 * Defaults match wormgeard: URL $WORMGEAR_URL or udpm://239.255.76.67:7667?ttl=0,
 * prefix $WORMGEAR_PREFIX or WORMGEAR_. A command is matched to its ACK by
 * (client id, seq); see lcmtypes/PROTOCOL.md. */
#ifndef WG_BUS_H
#define WG_BUS_H

#include <lcm/lcm.h>
#include <stddef.h>
#include <stdint.h>

#include "cli.h"
#include "lcmtypes/wormgear_ack_t.h"
#include "lcmtypes/wormgear_cmd_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_tick_t.h"
#include "wormgear/wg_key.h"

#define BUS_DEFAULT_URL "udpm://239.255.76.67:7667?ttl=0"
#define BUS_DEFAULT_PREFIX "WORMGEAR_"

/* A received ACK, copied out of the LCM message. */
typedef struct bus_ack {
    int got;
    int accepted;
    int rc;                   /* the wire's status: 0 or a negative wg_status */
    int64_t cmd_seq, steps;
    int64_t utime;            /* the daemon's wall clock when it sent the ACK, us */
    double tau, t_s;
    char code[32];
    char op[16];
    char message[768];
    int old;                  /* signed, but older than bus_signed takes (c->old_s behind) */
} bus_ack;

typedef struct bus {
    lcm_t *lcm;
    int signing;              /* commands carry a MAC (bus_set_key) */
    unsigned char key[WG_KEY_BYTES];
    char url[256];            /* the LCM URL opened, for messages */
    char prefix[64];
    char client[96];          /* "<name>-<pid>@<host>" */
    int64_t seq;              /* last command seq sent */
    int64_t cmd_utime;        /* ... and its utime: an ACK echoes both (and the client) */
    int64_t tick_seq;         /* last TICK seq sent (a counter of its own) ... */
    int64_t tick_utime;       /* ... and its utime (a refused tick's ACK echoes both); no two
                                 messages sent share a utime, so a tick's ACK never answers
                                 a command */
    bus_ack ack;              /* the ACK of the last command, once it came */
    bus_ack tick_ack;         /* the ACK refusing the last tick, if one came (op "tick") */
    bus_ack unverified;       /* signing: the last answer to our command that the key did not
                                 verify (not taken: unsigned, another key, made up) */
    long unverified_n;        /* signing: messages not verified (bus_signed) */
    const char *unverified_type; /* the last one's channel suffix */
    int64_t opened_us;        /* wall clock at bus_open */
    int64_t newest_us[9];     /* signing: the newest utime taken of each type (BUS_NTYPE) */
    long old_n;               /* signing: signed ones not taken as older (bus_signed) */
    const char *old_type;     /* the last one's channel suffix ... */
    double old_s;             /* ... how far behind the newest taken, else the start, s */
    lcm_subscription_t *ack_sub;
    char send_why[320];       /* why bus_send or bus_tick last failed */
} bus;

/* The seq counter of one channel (every wormgear message has one, see
 * lcmtypes/PROTOCOL.md): a jump forward is messages lost, a step back or a
 * repeat is a daemon restart. */
typedef struct bus_seq {
    int64_t last;
    int have;
    long gaps, missing, restarts;
} bus_seq;

/* Count seq: 1 after a gap (missing grows by the messages lost), -1 after
 * a restart, 0 in order or on the first message. */
int bus_seq_note(bus_seq *s, int64_t seq);

/* ---- senders: telling apart what shares a channel ------------------------
 * A channel may carry more than one sender: a daemon restarted under the
 * receiver, a log played back (lcm-logplayer) into a live bus, a second
 * daemon on the same prefix. What the messages carry today tells them
 * apart: each sender's seq runs up by one (gaps: messages lost), and its
 * utime keeps a steady offset to the receiver's wall clock (about 0 for a
 * live sender on this host; the age of the recording for a replay). A
 * message joins the sender whose seq it continues with a clock that agrees;
 * if none, it starts a new one. When the messages carry a sender id
 * (pass it; 0: none), the id decides alone. */
enum { BUS_NSTREAM = 4 };

/* The seconds |utime - wall clock| beyond which a sender is a replay (or
 * its clock is that far off). */
#define BUS_REPLAY_S 2.0

typedef struct bus_stream {
    int64_t sender;          /* the id messages carried (0: none) */
    int64_t first_seq, last_seq;
    double offset_s;         /* utime - our wall clock, at the last message */
    double seen_s;           /* our monotonic clock at the last message */
    double born_s;
    long msgs, gaps, missing;
    long id;                 /* 1, 2, ... in the order lines were heard */
    long replaced_by;        /* id of a line that started below this one (0: none) */
} bus_stream;

/* The senders heard on one channel, and what they did. */
typedef struct bus_streams {
    bus_stream s[BUS_NSTREAM];
    int n;                   /* lines alive (heard within the expiry) */
    long gaps, missing;      /* inside lines, over the session */
    long restarts;           /* a line started again below an old one that then fell silent */
    long senders;            /* new lines that were not restarts (the first counts) */
    long concurrent;         /* times two lines were alive and both sending */
    long ids;                /* lines ever heard */
} bus_streams;

/* What a message did to its channel's senders. */
enum { BUS_IN_ORDER = 0, BUS_GAP = 1, BUS_NEW = 2, BUS_RESTART = 3 };

/* Note a message (seq; utime_us, its send time) received at our monotonic
 * now_s and wall clock now_us (the log's timestamp when reading a log);
 * sender its id or 0. Lines silent for more than 5 s expire first.
 * Returns BUS_IN_ORDER, BUS_GAP (messages lost before it), BUS_NEW (a new
 * sender: another clock, or a line no sender continues) or BUS_RESTART (a
 * new line below an old one on the same clock); *line is the index of its
 * line in b->s. A "restart" whose old line then goes on is taken back:
 * it was a second sender (restarts - 1, senders + 1, concurrent + 1). */
int bus_streams_note(bus_streams *b, int64_t seq, int64_t utime_us, int64_t sender,
                     double now_s, int64_t now_us, int *line);

/* 1 when a line's send clock is more than BUS_REPLAY_S from ours. */
int bus_stream_replayed(const bus_stream *s);

/* $WORMGEAR_URL or the default; $WORMGEAR_PREFIX or the default. */
const char *bus_default_url(void);
const char *bus_default_prefix(void);

/* 1 if p is a channel prefix the daemon accepts: [A-Za-z0-9_.-]{0,40}. */
enum { BUS_PREFIX_MAX = 40 };

/* bus_open's status when LCM refuses the URL (a misspelt one: LCM's reason
 * is on stderr), or it has port 0: a usage error, which the clients exit 2
 * for. */
enum { BUS_EURL = -2 };
int bus_prefix_ok(const char *p);

/* Open LCM on url (NULL: default) with prefix (NULL: default); name is the
 * program name used in the client id. Commands are signed with the key in
 * $WORMGEAR_KEY_FILE when that is set (bus_set_key). 0, BUS_EURL if LCM
 * refuses the URL or its port is 0, or -1 for anything else (a bad prefix,
 * an empty URL, no route to its group, the key file refused); why says
 * which. */
int bus_open(bus *c, const char *url, const char *prefix, const char *name, char *why,
             size_t whylen);

/* LCM on url for a process that listens on it: its multicast route
 * checked first (wg_mcast_route), then lcm_create. The caller subscribes,
 * then filters the socket with wg_mcast_guard in the mode it needs (the
 * clients WG_MCAST_WHOLE, bus_open; a recorder WG_MCAST_FRAGMENTS). The
 * handle, or NULL with *rc BUS_EURL (LCM refuses the URL, or port 0) or -1
 * (no route to the group), and why. */
lcm_t *bus_lcm_open(const char *url, int *rc, char *why, size_t whylen);

/* A client's exit status after bus_open (or bus_set_key) failed with brc:
 * CLI_EUSAGE for BUS_EURL (a usage error), else 1. */
static inline int bus_exit_status(int brc)
{
    return brc == BUS_EURL ? CLI_EUSAGE : 1;
}

/* Sign every command from now on with the key in path (wormgear/wg_key.h;
 * the daemon's command_key_file); NULL or "" turns signing off. 0, or -1
 * with why. */
int bus_set_key(bus *c, const char *path, char *why, size_t whylen);

/* What to ask when the daemon does not answer: "is wormgeard running on
 * URL with prefix P? (--url, --prefix or $WORMGEAR_URL, $WORMGEAR_PREFIX
 * choose another)", into buf; when an answer came that the key did not
 * verify, what it said and why it was not taken instead. Returns buf. */
const char *bus_hint(const bus *c, char *buf, size_t len);

/* Close LCM. Safe on a failed open. */
void bus_close(bus *c);

/* "<prefix><suffix>" into buf (e.g. suffix "STATUS"). */
const char *bus_channel(const bus *c, const char *suffix, char *buf, size_t len);

/* fn (a BUS_RAW_HANDLER) subscribed to PREFIX+suffix, with room for queue
 * messages waiting (0: LCM's default, 30); NULL if LCM refused. */
lcm_subscription_t *bus_subscribe(bus *c, const char *suffix, lcm_msg_handler_t fn, void *user,
                                  int queue);

/* A command op with every string field "" and every number 0, to fill in. */
wormgear_cmd_t bus_cmd(const char *op);

/* Stamp cmd (utime, seq = ++c->seq, client), sign it when a key is set
 * (mac over every byte before mac_len, PROTOCOL.md) and publish it on CMD.
 * Returns the seq, or -1 with c->send_why saying why: it did not encode, it
 * would not fit one datagram with its channel (WG_MCAST_WHOLE_MAX: the
 * daemon's socket filter drops fragments), or LCM could not send it. */
int64_t bus_send(bus *c, wormgear_cmd_t *cmd);

/* Publish one TICK owing nsteps (lockstep: a tick taken has no answer, a
 * refused one an ACK with op "tick", taken into c->tick_ack as bus_wait
 * handles messages), stamped (utime, seq = ++c->tick_seq, client) and
 * signed as bus_send signs a command. Returns the seq, or -1 as bus_send
 * (c->send_why). */
int64_t bus_tick(bus *c, int64_t nsteps);

/* Handle LCM messages until done(ctx) is true or timeout_ms passes.
 * Returns 0 when done, -1 on timeout. done may be NULL (just wait). */
int bus_wait(bus *c, int timeout_ms, int (*done)(void *ctx), void *ctx);

/* Wait for the ACK of the last command sent; 0 when it came (c->ack), -1
 * on timeout. With a key (bus_set_key) only an ACK that carries its MAC
 * under that key is taken (PROTOCOL.md, "Signed answers"): any sender on
 * the group can answer a command it saw, "accepted" or not; others are
 * counted and kept in c->unverified for bus_hint. */
int bus_wait_ack(bus *c, int timeout_ms);

/* 1 if the message of type (any the daemon publishes: ACK, PARAMS and
 * STATUS, and the streams STATE, POINCARE, CONTACT, SCOPE), received in rb
 * and already checked (BUS_DECODE), carries the MAC of its bytes under c's
 * key, or c signs nothing (nothing to verify); else 0, counted in
 * c->unverified_n. A client with a key takes nothing else: what it does
 * (restore a mode, a value; record a section; show the daemon's state)
 * must be the daemon's, not what any sender on the group says it is
 * (PROTOCOL.md, "Signed answers", "Signed streams"). Nor does it take a
 * signed one played back: its utime (the daemon's clock) must be at most
 * BUS_AHEAD_S before bus_open, and not before the newest of its type
 * taken; else 0, counted in c->old_n. */
#define BUS_AHEAD_S 1.0 /* the daemon's clock may lag a client's this much (its AUTH_AHEAD_S) */
int bus_signed(bus *c, int type, const lcm_recv_buf_t *rb);

/* Why m is not a PARAMS a daemon sends (any sender on the group can
 * publish one), in why, or NULL: its scale positive and finite, N in
 * [WG_STEPS_MIN, WG_STEPS_MAX], a model and a stepper this build knows,
 * every value finite. */
const char *bus_params_odd(const wormgear_params_t *m, char *why, size_t len);

/* 1 when m is such a PARAMS, to be ignored: counted in *count, and for
 * the first three the line to say in say (len bytes; "" otherwise):
 * "PROG: ignored a PARAMS message no daemon sends (why)\n". The caller
 * writes it (wgrig through its writer: a stopped terminal stops no sweep). */
int bus_params_ignore(const wormgear_params_t *m, long *count, const char *prog, char *say,
                      size_t len);

#endif

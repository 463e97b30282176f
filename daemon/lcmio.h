/* lcmio.h - the LCM side of wormgeard: one lcm_t, the channel names, a
 * per-channel seq counter and one preallocated encode buffer.
 *
 * Publishing never allocates in our code: messages are encoded with the
 * generated _encode into io->buf and handed to lcm_publish. A failed encode
 * or publish counts as a dropped message (the seq still advances, so
 * receivers see the gap). */
#ifndef WGD_LCMIO_H
#define WGD_LCMIO_H

#include <lcm/lcm.h>
#include <stddef.h>
#include <stdint.h>

#include "lcmtypes/wormgear_ack_t.h"
#include "lcmtypes/wormgear_cmd_t.h"
#include "lcmtypes/wormgear_contact_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_scope_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "lcmtypes/wormgear_tick_t.h"

enum lcmio_channel { CH_CMD, CH_ACK, CH_PARAMS, CH_STATE, CH_POINCARE, CH_CONTACT, CH_STATUS,
                     CH_TICK, CH_SCOPE, CH_COUNT };
enum { LCMIO_SENT = 8,              /* the last messages of a channel lcmio_sent knows */
       LCMIO_BUF = 61440,          /* every message stays below 60 KB */
       LCMIO_RECV_BUF = 4194304 };  /* udpm receive buffer asked for (recv_buf_size) */

typedef struct lcmio {
    lcm_t *lcm;
    char ch[CH_COUNT][112];  /* prefix + name */
    int64_t seq[CH_COUNT];   /* next seq per outgoing channel */
    int64_t sent_utime[CH_COUNT][LCMIO_SENT]; /* utime of seq s at [s % LCMIO_SENT] */
    uint64_t published, dropped;
    int send_errno;           /* why the last message was dropped (EMSGSIZE: it did not encode) */
    const unsigned char *key; /* lcmio_sign_with: the caller's, or NULL */
    char url[400];            /* as given, for wg_mcast_guard */
    int guarded;              /* wg_mcast_guard done, at the first subscription */
    unsigned char buf[LCMIO_BUF];
} lcmio;

/* Suffixes of the channels: "CMD", "ACK", ... */
const char *lcmio_channel_suffix(int ch);

/* Create the LCM instance for url and build the channel names. WG_OK,
 * WG_EIO with why if the host has no route to a udpm:// URL's group
 * (wg_mcast_route), or WG_EINVAL if LCM refuses the URL (a misspelt one:
 * LCM's reason is on stderr). */
int lcmio_init(lcmio *io, const char *url, const char *prefix, char *why, size_t whylen);

/* Destroy the LCM instance (subscriptions go with it). */
void lcmio_fini(lcmio *io);

/* File descriptor to watch for incoming messages. */
int lcmio_fileno(const lcmio *io);

/* 1 when a message waits to be handled (one poll, no wait), else 0. */
int lcmio_waiting(const lcmio *io);

/* Subscribe fn (a raw handler, given user) to channel ch (CH_*), with room
 * for queue messages LCM may hold for it; the first subscription, which
 * opens LCM's receive socket, also filters it (wg_mcast_guard). WG_OK, or
 * WG_EIO (or wg_mcast_guard's code) with why. */
int lcmio_subscribe(lcmio *io, int ch, lcm_msg_handler_t fn, void *user, int queue, char *why,
                    size_t whylen);

/* 1 if this process published seq with utime on ch among its last
 * LCMIO_SENT messages there: a message on our own channel is our own
 * echo, else another sender's (a second daemon with our URL and prefix). */
int lcmio_sent(const lcmio *io, int ch, int64_t seq, int64_t utime);

/* Handle every message already waiting, at most max; returns the count. */
int lcmio_drain(lcmio *io, int max);

/* Datagrams the kernel dropped on this process's UDP sockets (LCM's), read
 * from /proc/net/udp's drops column; 0 where that cannot be read. */
uint64_t lcmio_rx_dropped(void);

/* Microseconds since the epoch (utime of outgoing messages). */
int64_t lcmio_now_us(void);

/* Sign every message published from now on with key (WG_KEY_BYTES, the
 * caller's: it must stay valid while set; NULL: unsigned). The daemon
 * calls it each time it takes a key or lets one go. */
void lcmio_sign_with(lcmio *io, const unsigned char *key);

/* Stamp utime and seq, encode, sign when a key is set, and publish. 0, or
 * -1 (counted as dropped). The MAC covers every byte before mac_len, as a
 * signed command's (PROTOCOL.md, "Signed answers" and "Signed streams"),
 * so a client with the key tells the daemon's messages from ones a sender
 * on the group made up. */
int lcmio_pub_ack(lcmio *io, wormgear_ack_t *m);
int lcmio_pub_params(lcmio *io, wormgear_params_t *m);
int lcmio_pub_state(lcmio *io, wormgear_state_t *m);
int lcmio_pub_poincare(lcmio *io, wormgear_poincare_t *m);
int lcmio_pub_contact(lcmio *io, wormgear_contact_t *m);
int lcmio_pub_status(lcmio *io, wormgear_status_t *m);
int lcmio_pub_scope(lcmio *io, wormgear_scope_t *m);

#endif

/* msg_check.h - an encoded wormgear message's bytes walked, with every
 * count and length checked, before LCM's generated decoder reads them.
 *
 * lcm-gen 1.3.1's C decoders trust the sender: an array count of 2^31 - 1
 * overflows their size check (int arithmetic) and they read past the
 * buffer; a string length is not checked at all, nor its NUL; a decode
 * that fails half-way leaks what it allocated. Anyone on the multicast
 * group can send, so the daemon (its CMD channel) and every client (what
 * the daemon publishes; wglog all of it) walk a message here first, field
 * by field as the .lcm files in this directory encode them, with 64-bit
 * arithmetic and no allocation. One table of layouts serves both sides;
 * clients.test_msg holds each layout to the generated encoder's bytes. */
#ifndef WG_MSG_CHECK_H
#define WG_MSG_CHECK_H

#include <stdint.h>

/* The message types, one layout each. */
enum {
    MSG_ACK, MSG_STATE, MSG_POINCARE, MSG_CONTACT, MSG_STATUS, MSG_PARAMS, MSG_CMD, MSG_TICK,
    MSG_SCOPE, MSG_NTYPE
};

/* The protocol's limits on a command (lcmtypes/PROTOCOL.md): what the
 * daemon takes, and what a message on CMD must keep to. */
enum {
    MSG_CMD_MAX_PARAMS = 64,   /* names[] / values[] (the parameter table has 29) */
    MSG_CMD_MAX_STRING = 4096, /* bytes of any string of a cmd_t, without its NUL */
    MSG_CMD_MAX_CLIENT = 256,  /* bytes of a client id (echoed in its ACK) */
    MSG_CMD_MAC_BYTES = 32,    /* a signed command's MAC (crypto_auth) */
    /* The bytes of any message, whatever its type (the daemon's largest are some
     * 60 kB). LCM 1.3.1 hands on a short datagram whose channel name has no NUL
     * (read on into the bytes its buffer held before) with a length of -1,
     * 4294967295 bytes: walked against that, a stale count or string length would
     * carry the walk past the real bytes. */
    MSG_MAX_BYTES = 1 << 24,
    /* POINCARE's nstate and nbearing, STATUS's nbearing: what any model has
     * (WG_NSTATE_MAX, WG_NBEARING; clients.test_msg holds them equal). With no
     * rows, a count of 2^31 - 1 needs no bytes, and wglog wrote a CSV header of
     * that many columns. */
    MSG_NSTATE_MAX = 16,
    MSG_NBEARING_MAX = 6
};

/* What a walk found. */
typedef struct msg_walk {
    long end;          /* the bytes the message occupies from buf, or -1 */
    int64_t count[3];  /* the counts read (cmd_t: [0] nparams, [1] mac_len; a MAC's length in a free slot) */
    const char *field; /* on a fault: the field at fault ... */
    int index;         /* ... its array index, or -1 ... */
    long at;           /* ... the byte the walk stood at ... */
    char what[160];    /* ... and what was wrong: "truncated", "a string of 5000 bytes,
                        * the limit is 4096", "string not NUL-terminated", ... */
} msg_walk;

/* Walk the message of type at the start of buf (len bytes, its 8-byte
 * fingerprint first, not compared here): the bytes it occupies, or -1
 * when len is over MSG_MAX_BYTES, a field runs past len, a count is negative or over its limit, a
 * string is longer than its limit or not one NUL-terminated C string
 * (w, if not NULL, says where and why). */
long msg_check(int type, const void *buf, long len, msg_walk *w);

/* 1 if the daemon answers the command op (with its at_section) only when
 * something has happened in the run (PROTOCOL.md): a step when its steps
 * are done, a set at_section at the next Poincare section. Its silence need
 * not mean that no daemon is there. */
int msg_cmd_late(const char *op, int at_section);

/* A big-endian integer of n bytes at p (n <= 8). */
uint64_t msg_be(const unsigned char *p, int n);

#endif

/* bus_msg.h - a daemon message decoded only after its bytes were walked
 * and checked (lcmtypes/msg_check.h: every array count and string length
 * against the bytes received; the generated decoder trusts them, and a
 * hostile count made it read past the buffer). */
#ifndef WG_BUS_MSG_H
#define WG_BUS_MSG_H

#include "msg_check.h"

#include <lcm/lcm.h>

/* The message types the clients decode (wglog all of them). */
enum {
    BUS_ACK = MSG_ACK, BUS_STATE = MSG_STATE, BUS_POINCARE = MSG_POINCARE,
    BUS_CONTACT = MSG_CONTACT, BUS_STATUS = MSG_STATUS, BUS_PARAMS = MSG_PARAMS,
    BUS_CMD = MSG_CMD, BUS_TICK = MSG_TICK, BUS_SCOPE = MSG_SCOPE, BUS_NTYPE = MSG_NTYPE
};

/* The bytes a message of type occupies at the start of buf (len bytes),
 * or -1 when a count, a length or a field runs past len, or a string is
 * not one NUL-terminated C string (msg_check). */
static inline long bus_msg_size(int type, const void *buf, long len)
{
    return msg_check(type, buf, len, NULL);
}

/* 1 if the generated decoder may be given buf: bus_msg_size >= 0. */
static inline int bus_msg_ok(int type, const void *buf, long len)
{
    return msg_check(type, buf, len, NULL) >= 0;
}

/* Decode an LCM message of type T (wormgear_X_t) from the receive buffer
 * rb into msg after the check: 0, or -1 (nothing to clean up). */
#define BUS_DECODE(T, TYPE, rb, msg)                                                        \
    (bus_msg_ok((TYPE), (rb)->data, (long)(rb)->data_size) &&                               \
             T##_decode((rb)->data, 0, (int)(rb)->data_size, (msg)) >= 0                    \
         ? 0                                                                                \
         : -1)

/* A raw LCM handler, name, that checks and decodes a message of type T
 * and passes it to typed, a handler of the generated kind: what
 * T_subscribe would have given it, but never an unchecked message. */
#define BUS_RAW_HANDLER(name, T, TYPE, typed)                                               \
    static void name(const lcm_recv_buf_t *rb, const char *ch, void *u)                     \
    {                                                                                       \
        T m_;                                                                               \
        if (BUS_DECODE(T, TYPE, rb, &m_))                                                   \
            return;                                                                         \
        typed(rb, ch, &m_, u);                                                              \
        T##_decode_cleanup(&m_);                                                            \
    }

#endif

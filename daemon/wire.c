/* wire.c - an encoded wormgear.cmd_t or tick_t checked before it is
 * decoded: the walk of lcmtypes/msg_check.c, and what the daemon adds to
 * it. */
#include "wire.h"

#include "lcmtypes/wormgear_cmd_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "lcmtypes/wormgear_tick_t.h"
#include "msg_check.h"
#include "wormgear/wg_status.h"

#include <stdio.h>
#include <string.h>

/* The walk of type (hash its fingerprint, name its type's name), and no
 * byte after the message. */
static int check(int type, int64_t hash, const char *name, const void *buf, size_t len,
                 int32_t *mac_len, char *why, size_t whylen)
{
    const unsigned char *b = buf;
    if (len >= 8 && (int64_t)msg_be(b, 8) != hash) {
        snprintf(why, whylen, "fingerprint mismatch: not a wormgear.%s, or another version "
                              "of it (%zu bytes)", name, len);
        return WG_EDECODE;
    }
    msg_walk w;
    long end = msg_check(type, buf, (long)len, &w);
    if (end < 0) {
        char idx[16] = "";
        if (w.index >= 0)
            snprintf(idx, sizeof idx, "[%d]", w.index);
        snprintf(why, whylen, "field %s%s: %s (at byte %ld of %zu)", w.field ? w.field : "?",
                 idx, w.what, w.at, len);
        return WG_EDECODE;
    }
    if ((size_t)end != len) {
        snprintf(why, whylen, "%zu bytes after the end of a complete %s (at byte %ld of %zu)",
                 len - (size_t)end, name, end, len);
        return WG_EDECODE;
    }
    if (mac_len)
        *mac_len = (int32_t)w.count[1]; /* 0 or WIRE_MAC_BYTES, said the walk */
    return WG_OK;
}

int wire_cmd_check(const void *buf, size_t len, int32_t *mac_len, char *why, size_t whylen)
{
    return check(MSG_CMD, __wormgear_cmd_t_get_hash(), "cmd_t", buf, len, mac_len, why, whylen);
}

int wire_tick_check(const void *buf, size_t len, int32_t *mac_len, char *why, size_t whylen)
{
    return check(MSG_TICK, __wormgear_tick_t_get_hash(), "tick_t", buf, len, mac_len, why,
                 whylen);
}

/* Every type begins with the fingerprint, utime and seq; the client id's
 * length is at byte at (cmd_t: right after seq; tick_t: after nsteps; 0:
 * none read). 1 when the fingerprint is hash's, else 0. */
static int header(const void *buf, size_t len, int64_t hash, size_t at, char *client,
                  size_t clen, int64_t *seq, int64_t *utime)
{
    const unsigned char *b = buf;
    client[0] = 0;
    *seq = -1;
    *utime = 0;
    if (len < 24 || (int64_t)msg_be(b, 8) != hash)
        return 0;
    *utime = (int64_t)msg_be(b + 8, 8);
    *seq = (int64_t)msg_be(b + 16, 8);
    if (len < at + 4 || clen == 0)
        return 1;
    int32_t n = (int32_t)(uint32_t)msg_be(b + at, 4);
    size_t have = len - at - 4, want = n > 1 ? (size_t)n - 1 : 0;
    size_t k = want < have ? want : have;
    k = k < clen - 1 ? k : clen - 1;
    memcpy(client, b + at + 4, k);
    client[k] = 0; /* and at the first NUL, as a C string */
    return 1;
}

void wire_cmd_header(const void *buf, size_t len, char *client, size_t clen, int64_t *seq,
                     int64_t *utime)
{
    header(buf, len, __wormgear_cmd_t_get_hash(), 24, client, clen, seq, utime);
}

void wire_tick_header(const void *buf, size_t len, char *client, size_t clen, int64_t *seq,
                      int64_t *utime)
{
    header(buf, len, __wormgear_tick_t_get_hash(), 32, client, clen, seq, utime);
}

int wire_status_header(const void *buf, size_t len, int64_t *seq, int64_t *utime)
{
    char none[1];
    return header(buf, len, __wormgear_status_t_get_hash(), 0, none, 0, seq, utime);
}

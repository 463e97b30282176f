/* bus_msg.c - the bytes of a daemon message walked before LCM's generated
 * decoder sees them (bus_msg.h). That decoder trusts the sender: an array
 * count of 2^31 - 1 overflows its size check (int arithmetic) and it reads
 * past the buffer; a string length is not checked at all, nor its NUL. One
 * such message on the group killed wgweb, wgmon, wgrig and wglog. Here
 * every count and length is checked against the bytes there are, with
 * 64-bit arithmetic, in the order the fields are encoded; clients.test_msg
 * holds each layout to the generated encoder's bytes. */
#include "bus_msg.h"

#include <stdint.h>
#include <string.h>

/* A field: what the walk reads there. */
enum {
    F_SKIP, /* a scalar: a bytes */
    F_N32,  /* an int32 count into slot a */
    F_N8,   /* an int8 count into slot a */
    F_STR,  /* a string */
    F_ARR,  /* a bytes x count[b] */
    F_ARR2, /* a bytes x count[b] x count[c] */
    F_STRS, /* count[b] strings */
    F_END
};
typedef struct fld {
    unsigned char kind, a, b, c;
} fld;

#define SKIP(n) {F_SKIP, n, 0, 0}
#define N32(s) {F_N32, s, 0, 0}
#define N8(s) {F_N8, s, 0, 0}
#define STR {F_STR, 0, 0, 0}
#define ARR(n, s) {F_ARR, n, s, 0}
#define ARR2(n, s, t) {F_ARR2, n, s, t}
#define STRS(s) {F_STRS, 0, s, 0}
#define END {F_END, 0, 0, 0}

/* The layouts of the .lcm files in lcmtypes/ after the 8-byte
 * fingerprint, field by field (slots: 0 n, 1 nstate, 2 nbearing). */
static const fld ACK[] = {SKIP(8), SKIP(8), STR, SKIP(8), STR, SKIP(1), SKIP(4), STR, STR,
                          SKIP(8), SKIP(8), SKIP(8), END};
static const fld STATE[] = {SKIP(8), SKIP(8), SKIP(8), SKIP(4), N32(0),
                            ARR(8, 0), ARR(8, 0), ARR(8, 0), ARR(8, 0), ARR(8, 0), ARR(8, 0),
                            ARR(8, 0), ARR(8, 0), ARR(8, 0), ARR(8, 0), ARR(8, 0), ARR(8, 0),
                            ARR(8, 0), ARR(8, 0), END};
static const fld POINCARE[] = {SKIP(8), SKIP(8), N32(1), N32(0),
                               ARR(8, 0), ARR(8, 0), ARR(8, 0), ARR(8, 0), ARR(8, 0),
                               ARR(8, 0), ARR(8, 0), ARR(8, 0), ARR(8, 0), ARR(1, 0),
                               ARR(4, 0), ARR2(8, 0, 1), N32(2), ARR2(4, 0, 2), ARR2(8, 0, 2),
                               END};
static const fld CONTACT[] = {SKIP(8), SKIP(8), SKIP(4), N32(0), ARR(8, 0), ARR(8, 0),
                              ARR(8, 0), ARR(8, 0), ARR(1, 0), ARR(1, 0), END};
static const fld STATUS[] = {SKIP(8), SKIP(8), STR, STR, SKIP(8), STR, STR, STR,
                             SKIP(8), SKIP(8), SKIP(8), SKIP(8), SKIP(8), SKIP(4),
                             SKIP(8), SKIP(8), SKIP(8), SKIP(8), SKIP(8), SKIP(8), SKIP(8),
                             SKIP(8), SKIP(8), SKIP(8), SKIP(8), SKIP(8), STR, SKIP(8),
                             N8(2), ARR(8, 2), ARR(8, 2), STR, SKIP(1), SKIP(8), END};
static const fld PARAMS[] = {SKIP(8), SKIP(8), STR, STR, SKIP(8), STR, STR, STR, SKIP(4),
                             SKIP(8), SKIP(8), SKIP(8), SKIP(8), N32(0), STRS(0), STRS(0),
                             ARR(8, 0), ARR(8, 0), ARR(8, 0), ARR(8, 0), ARR(1, 0), SKIP(1),
                             STR, SKIP(8), SKIP(8), SKIP(8), SKIP(8), END};

static const fld CMD[] = {SKIP(8), SKIP(8), STR, STR, N32(0), STRS(0), ARR(8, 0), SKIP(1),
                          SKIP(8), SKIP(8), STR, SKIP(8), STR, SKIP(8), SKIP(1), N32(1),
                          ARR(1, 1), END};
static const fld TICK[] = {SKIP(8), SKIP(8), SKIP(8), END};
static const fld SCOPE[] = {SKIP(8), SKIP(8), SKIP(8), SKIP(8), SKIP(8), SKIP(8), SKIP(8),
                            SKIP(8), END};

static const fld *const LAYOUT[BUS_NTYPE] = {ACK,    STATE, POINCARE, CONTACT, STATUS,
                                             PARAMS, CMD,   TICK,     SCOPE};

static int64_t be32(const unsigned char *p)
{
    return (int32_t)((uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3]);
}

/* A string at pos: its int32 length (the bytes with the NUL), the bytes,
 * the last a NUL. The new pos, or -1. */
static int64_t str_at(const unsigned char *b, int64_t len, int64_t pos)
{
    if (pos + 4 > len)
        return -1;
    int64_t n = be32(b + pos);
    pos += 4;
    if (n < 1 || n > len - pos || b[pos + n - 1] != 0)
        return -1;
    return pos + n;
}

long bus_msg_size(int type, const void *buf, long len)
{
    if (type < 0 || type >= BUS_NTYPE || !buf || len < 8)
        return -1;
    const unsigned char *b = buf;
    int64_t pos = 8, cnt[3] = {0, 0, 0}, n;
    for (const fld *f = LAYOUT[type]; f->kind != F_END && pos >= 0; f++) {
        switch (f->kind) {
        case F_SKIP: pos = pos + f->a <= len ? pos + f->a : -1; break;
        case F_N32:
        case F_N8:
            n = f->kind == F_N32 ? 4 : 1;
            if (pos + n > len)
                return -1;
            cnt[f->a] = n == 4 ? be32(b + pos) : (int64_t)(int8_t)b[pos];
            if (cnt[f->a] < 0 || cnt[f->a] > len) /* each element takes a byte at least */
                return -1;
            pos += n;
            break;
        case F_STR: pos = str_at(b, len, pos); break;
        case F_ARR:
        case F_ARR2:
            n = f->a; /* grown by each count while it fits in what is left */
            for (int k = 0; k < (f->kind == F_ARR2 ? 2 : 1) && pos >= 0; k++) {
                int64_t c = cnt[k ? f->c : f->b];
                if (c && n > (len - pos) / c)
                    pos = -1;
                n *= c;
            }
            pos = pos >= 0 && n <= len - pos ? pos + n : -1;
            break;
        case F_STRS:
            for (int64_t i = 0; i < cnt[f->b] && pos >= 0; i++)
                pos = str_at(b, len, pos);
            break;
        }
    }
    return (long)pos;
}

int bus_msg_ok(int type, const void *buf, long len) { return bus_msg_size(type, buf, len) >= 0; }

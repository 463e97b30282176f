/* wire.c - bounds-checked walk over an encoded wormgear.cmd_t. */
#include "wire.h"

#include "lcmtypes/wormgear_cmd_t.h"
#include "wormgear/wg_status.h"

#include <stdio.h>
#include <string.h>

typedef struct walk {
    const unsigned char *b;
    size_t len, pos;
    const char *field;   /* the field being read, for the message */
    int index;           /* its array index, or -1 */
    char err[160];       /* what was wrong ("" while all is well) */
} walk;

static uint64_t be(const unsigned char *p, int n)
{
    uint64_t v = 0;
    for (int i = 0; i < n; i++)
        v = v << 8 | p[i];
    return v;
}

/* The field read next (kept once something was wrong). */
static void at(walk *w, const char *field, int index)
{
    if (w->err[0])
        return;
    w->field = field;
    w->index = index;
}

static int skip(walk *w, size_t n)
{
    if (w->err[0])
        return -1;
    if (w->len - w->pos < n) {
        snprintf(w->err, sizeof w->err, "truncated");
        return -1;
    }
    w->pos += n;
    return 0;
}

static int32_t i32(walk *w)
{
    size_t p = w->pos;
    return skip(w, 4) ? 0 : (int32_t)(uint32_t)be(w->b + p, 4);
}

/* A string of at most max bytes (without its NUL). */
static void str(walk *w, int max)
{
    int32_t n = i32(w);
    if (w->err[0])
        return;
    if (n < 1 || n - 1 > max) {
        if (n < 1)
            snprintf(w->err, sizeof w->err, "string length %d (with its NUL, at least 1)", n);
        else
            snprintf(w->err, sizeof w->err, "a string of %d bytes, the limit is %d", n - 1,
                     max);
        return;
    }
    size_t p = w->pos;
    if (skip(w, (size_t)n))
        return;
    if (w->b[p + (size_t)n - 1] != 0)
        snprintf(w->err, sizeof w->err, "string not NUL-terminated");
    else if (memchr(w->b + p, 0, (size_t)n - 1))
        snprintf(w->err, sizeof w->err, "a NUL byte inside the string");
}

/* The fields of cmd_t, in order (lcmtypes/cmd_t.lcm). */
static void walk_fields(walk *w, wire_sig *sig)
{
    at(w, "fingerprint", -1), skip(w, 8);
    at(w, "utime", -1), skip(w, 8);
    at(w, "seq", -1), skip(w, 8);
    at(w, "client", -1), str(w, WIRE_MAX_CLIENT);
    at(w, "op", -1), str(w, WIRE_MAX_STRING);
    at(w, "nparams", -1);
    int32_t n = i32(w);
    if (!w->err[0] && (n < 0 || n > WIRE_MAX_PARAMS))
        snprintf(w->err, sizeof w->err, "%d, allowed 0 to %d", n, WIRE_MAX_PARAMS);
    for (int32_t i = 0; i < n && !w->err[0]; i++)
        at(w, "names", i), str(w, WIRE_MAX_STRING);
    at(w, "values", -1), skip(w, (size_t)(w->err[0] ? 0 : n) * 8);
    at(w, "has_from", -1), skip(w, 1);
    at(w, "from", -1), skip(w, 8);
    at(w, "duration", -1), skip(w, 8);
    at(w, "unit", -1), str(w, WIRE_MAX_STRING);
    at(w, "nsteps", -1), skip(w, 8);
    at(w, "name", -1), str(w, WIRE_MAX_STRING);
    at(w, "rate", -1), skip(w, 8);
    at(w, "at_section", -1), skip(w, 1);
    sig->signed_len = w->pos;
    at(w, "mac_len", -1);
    sig->mac_len = i32(w);
    if (!w->err[0] && sig->mac_len != 0 && sig->mac_len != WIRE_MAC_BYTES)
        snprintf(w->err, sizeof w->err, "%d, allowed 0 (unsigned) or %d", sig->mac_len,
                 WIRE_MAC_BYTES);
    sig->mac_at = w->pos;
    at(w, "mac", -1), skip(w, w->err[0] ? 0 : (size_t)sig->mac_len);
}

int wire_cmd_check(const void *buf, size_t len, wire_sig *sig, char *why, size_t whylen)
{
    walk w = {.b = buf, .len = len, .index = -1};
    wire_sig s = {0, 0, 0};
    if (len >= 8 && (int64_t)be(w.b, 8) != __wormgear_cmd_t_get_hash()) {
        snprintf(why, whylen, "fingerprint mismatch: not a wormgear.cmd_t, or another version "
                              "of it (%zu bytes)", len);
        return WG_EDECODE;
    }
    walk_fields(&w, &s);
    if (!w.err[0] && w.pos != len) {
        snprintf(why, whylen, "%zu bytes after the end of a complete cmd_t (at byte %zu of %zu)",
                 len - w.pos, w.pos, len);
        return WG_EDECODE;
    }
    if (!w.err[0]) {
        if (sig)
            *sig = s;
        return WG_OK;
    }
    char idx[16] = "";
    if (w.index >= 0)
        snprintf(idx, sizeof idx, "[%d]", w.index);
    snprintf(why, whylen, "field %s%s: %s (at byte %zu of %zu)", w.field, idx, w.err, w.pos,
             len);
    return WG_EDECODE;
}

void wire_cmd_header(const void *buf, size_t len, char *client, size_t clen, int64_t *seq)
{
    const unsigned char *b = buf;
    client[0] = 0;
    *seq = -1;
    if (len < 24 || (int64_t)be(b, 8) != __wormgear_cmd_t_get_hash())
        return;
    *seq = (int64_t)be(b + 16, 8);
    if (len < 28 || clen == 0)
        return;
    int32_t n = (int32_t)(uint32_t)be(b + 24, 4);
    size_t have = len - 28, want = n > 1 ? (size_t)n - 1 : 0;
    size_t k = want < have ? want : have;
    k = k < clen - 1 ? k : clen - 1;
    memcpy(client, b + 28, k);
    client[k] = 0; /* and at the first NUL, as a C string */
}

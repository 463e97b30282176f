/* wire.c - bounds-checked walk over an encoded wormgear.cmd_t. */
#include "wire.h"

#include "lcmtypes/wormgear_cmd_t.h"
#include "wormgear/wg_status.h"

#include <stdio.h>
#include <string.h>

typedef struct walk {
    const unsigned char *b;
    size_t len, pos;
    const char *err;
} walk;

static uint64_t be(const unsigned char *p, int n)
{
    uint64_t v = 0;
    for (int i = 0; i < n; i++)
        v = v << 8 | p[i];
    return v;
}

static int skip(walk *w, size_t n)
{
    if (w->err)
        return -1;
    if (w->len - w->pos < n) {
        w->err = "truncated";
        return -1;
    }
    w->pos += n;
    return 0;
}

static int32_t i32(walk *w)
{
    size_t at = w->pos;
    return skip(w, 4) ? 0 : (int32_t)(uint32_t)be(w->b + at, 4);
}

static void str(walk *w)
{
    int32_t n = i32(w);
    if (w->err)
        return;
    if (n < 1 || n > WIRE_MAX_STRING) {
        w->err = "string length out of range";
        return;
    }
    size_t at = w->pos;
    if (!skip(w, (size_t)n) && w->b[at + (size_t)n - 1] != 0)
        w->err = "string not NUL-terminated";
}

int wire_cmd_check(const void *buf, size_t len, char *why, size_t whylen)
{
    walk w = {buf, len, 0, NULL};
    if (len >= 8 && (int64_t)be(w.b, 8) != __wormgear_cmd_t_get_hash())
        w.err = "fingerprint mismatch (not a wormgear.cmd_t, or another version of it)";
    skip(&w, 8 + 8 + 8); /* fingerprint, utime, seq */
    str(&w);             /* client */
    str(&w);             /* op */
    int32_t n = i32(&w); /* nparams */
    if (!w.err && (n < 0 || n > WIRE_MAX_PARAMS))
        w.err = "nparams out of range [0, 64]";
    for (int32_t i = 0; i < n && !w.err; i++)
        str(&w);         /* names[nparams] */
    skip(&w, (size_t)(w.err ? 0 : n) * 8); /* values[nparams] */
    skip(&w, 1 + 8 + 8); /* has_from, from, duration */
    str(&w);             /* unit */
    skip(&w, 8);         /* nsteps */
    str(&w);             /* name */
    skip(&w, 8);         /* rate */
    skip(&w, 1);         /* at_section */
    if (!w.err)
        return WG_OK;
    snprintf(why, whylen, "%s at byte %zu of %zu", w.err, w.pos, len);
    return WG_EDECODE;
}

void wire_cmd_header(const void *buf, size_t len, char *client, size_t clen, int64_t *seq)
{
    walk w = {buf, len, 0, NULL};
    client[0] = 0;
    *seq = -1;
    if (len < 8 || (int64_t)be(w.b, 8) != __wormgear_cmd_t_get_hash())
        return;
    skip(&w, 16);
    size_t at = w.pos;
    skip(&w, 8);
    size_t s = w.pos + 4;
    str(&w);
    if (w.err || w.pos - s > clen)
        return;
    memcpy(client, w.b + s, w.pos - s);
    *seq = (int64_t)be(w.b + at, 8);
}

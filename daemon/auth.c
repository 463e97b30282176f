/* auth.c - signed commands: key, MAC, time window, per-client counters. */
#include "auth.h"

#include "wormgear/wg_status.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int auth_load(auth *a, const char *path, char *why, size_t whylen)
{
    unsigned char key[WG_KEY_BYTES];
    char full[600];
    const char *cred = getenv("CREDENTIALS_DIRECTORY");
    if (!path[0]) {
        auth_fini(a);
        return WG_OK;
    }
    if (path[0] != '/' && cred && *cred)
        snprintf(full, sizeof full, "%s/%s", cred, path);
    else
        snprintf(full, sizeof full, "%s", path);
    int rc = wg_key_load(full, key, why, whylen);
    if (rc)
        return rc;
    memcpy(a->key, key, sizeof key);
    memset(key, 0, sizeof key);
    snprintf(a->path, sizeof a->path, "%s", full);
    a->on = 1;
    return WG_OK;
}

void auth_fini(auth *a)
{
    volatile unsigned char *k = a->key; /* not optimised away */
    for (size_t i = 0; i < sizeof a->key; i++)
        k[i] = 0;
    a->on = 0;
    a->path[0] = 0;
}

/* The slot of client id: its own, a free one, or the one least recently
 * used (an id older than the window can no longer replay: its messages
 * are stale). NULL when every slot is in use within the window. */
static auth_client *slot_of(auth *a, const char *id, int64_t now_us)
{
    auth_client *old = NULL;
    for (int i = 0; i < AUTH_CLIENTS; i++) {
        auth_client *c = &a->seen[i];
        if (c->id[0] && !strcmp(c->id, id))
            return c;
        if (!old || c->last_us < old->last_us)
            old = c;
    }
    if (old->id[0] && (double)(now_us - old->last_us) * 1e-6 < AUTH_WINDOW_S)
        return NULL;
    *old = (auth_client){.last_seq = INT64_MIN};
    snprintf(old->id, sizeof old->id, "%s", id);
    return old;
}

int auth_check(auth *a, const void *buf, const wire_sig *sig, const char *client,
               int64_t seq, int64_t utime, int64_t now_us, char *why, size_t whylen)
{
    if (!a->on)
        return WG_OK;
    const unsigned char *b = buf;
    double skew = ((double)utime - (double)now_us) * 1e-6;
    auth_client *c;
    if (sig->mac_len != WG_MAC_BYTES)
        snprintf(why, whylen, "unsigned command: this daemon accepts signed commands only "
                              "(PROTOCOL.md, \"Signed commands\"; a client's --key-file)");
    else if (!wg_mac_ok(a->key, b, sig->signed_len, b + sig->mac_at))
        snprintf(why, whylen, "bad signature: not signed with this daemon's key");
    else if (!(fabs(skew) <= AUTH_WINDOW_S))
        snprintf(why, whylen, "stale command: its time is %.3g s from the daemon's clock (the "
                              "window is +-%g s)", skew, AUTH_WINDOW_S);
    else if (!(c = slot_of(a, client, now_us)))
        snprintf(why, whylen, "too many signing clients within %g s (limit %d)", AUTH_WINDOW_S,
                 AUTH_CLIENTS);
    else if (seq <= c->last_seq)
        snprintf(why, whylen, "replayed or reordered command: seq %" PRId64 " is not above %"
                 PRId64 ", the last accepted from this client", seq, c->last_seq);
    else {
        c->last_seq = seq, c->last_us = now_us;
        return WG_OK;
    }
    a->refused++;
    return WG_EAUTH;
}

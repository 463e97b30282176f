/* auth.c - signed commands: key, MAC, time window, per-client counters and
 * the floor for clients not tracked. */
#include "auth.h"

#include "wormgear/wg_status.h"

#include <inttypes.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define US 1e6 /* microseconds per second */

/* A new key: no id's counter holds for it, so nothing signed before now_us
 * plus AUTH_AHEAD_S is accepted from any id. That covers every command an
 * earlier run accepted (before this one started, and at most AUTH_AHEAD_S
 * ahead of its clock) and every command under another key. */
static void start_afresh(auth *a, int64_t now_us)
{
    memset(a->seen, 0, sizeof a->seen);
    a->since_us = now_us;
}

int auth_load(auth *a, const char *path, int64_t now_us, char *why, size_t whylen)
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
    if (!a->on || memcmp(a->key, key, sizeof key) != 0)
        start_afresh(a, now_us); /* the same key re-read (SIGHUP) keeps the counters */
    memcpy(a->key, key, sizeof key);
    memset(key, 0, sizeof key);
    snprintf(a->path, sizeof a->path, "%s", full);
    a->on = 1;
    return WG_OK;
}

int64_t auth_open_us(const auth *a) { return a->since_us + (int64_t)(AUTH_AHEAD_S * US); }

void auth_fini(auth *a)
{
    volatile unsigned char *k = a->key; /* not optimised away */
    for (size_t i = 0; i < sizeof a->key; i++)
        k[i] = 0;
    a->on = 0;
    a->path[0] = 0;
}

/* The slot tracking id, or NULL. */
static auth_client *find(auth *a, const char *id)
{
    for (int i = 0; i < AUTH_CLIENTS; i++)
        if (a->seen[i].id[0] && !strcmp(a->seen[i].id, id))
            return &a->seen[i];
    return NULL;
}

/* A slot for a new id: a free one, or the one least recently used (an id
 * older than the window can no longer replay: its messages are stale).
 * NULL when every slot is in use within the window. */
static auth_client *take(auth *a, const char *id, int64_t now_us)
{
    auth_client *old = NULL;
    for (int i = 0; i < AUTH_CLIENTS; i++)
        if (!old || a->seen[i].last_us < old->last_us)
            old = &a->seen[i];
    if (old->id[0] && (double)(now_us - old->last_us) / US < AUTH_WINDOW_S)
        return NULL;
    *old = (auth_client){.last_seq = INT64_MIN};
    snprintf(old->id, sizeof old->id, "%s", id);
    return old;
}

/* Why a command from an id not tracked, signed at utime before the daemon
 * opened, is refused, and when signing it again helps. */
static void say_too_early(const auth *a, int64_t utime, int64_t now_us, char *why, size_t len)
{
    int64_t open = auth_open_us(a);
    double wait = ((double)open - (double)now_us) / US;
    char again[48] = "sign it again";
    if (wait > 0)
        snprintf(again, sizeof again, "sign it again in %.3f s", wait);
    snprintf(why, len, "signed %.3f s before this daemon started taking signed commands "
             "(%g s after its start or key change), so it may be a replay of one an "
             "earlier run or another key accepted: %s (if this repeats, this host's clock "
             "lags the daemon's)", ((double)open - (double)utime) / US, AUTH_AHEAD_S, again);
}

/* The time checks: the window, then the counter or the floor. */
static int fresh_ok(auth *a, const char *client, int64_t seq, int64_t utime, int64_t now_us,
                    char *why, size_t whylen)
{
    double skew = ((double)utime - (double)now_us) / US;
    auth_client *c = NULL;
    if (!(skew >= -AUTH_WINDOW_S))
        snprintf(why, whylen, "stale command: signed %.3g s before the daemon's clock (it "
                 "accepts up to %g s before and %g s ahead)", -skew, AUTH_WINDOW_S,
                 AUTH_AHEAD_S);
    else if (!(skew <= AUTH_AHEAD_S))
        snprintf(why, whylen, "signed %.3g s ahead of the daemon's clock (it accepts up to %g s "
                 "ahead, as a command from further ahead could outlive a daemon restart, and "
                 "%g s before): check the clocks (NTP)", skew, AUTH_AHEAD_S, AUTH_WINDOW_S);
    else if (!(c = find(a, client)) && utime <= auth_open_us(a))
        say_too_early(a, utime, now_us, why, whylen);
    else if (!c && !(c = take(a, client, now_us)))
        snprintf(why, whylen, "too many signing clients within %g s (limit %d)", AUTH_WINDOW_S,
                 AUTH_CLIENTS);
    else if (seq <= c->last_seq)
        snprintf(why, whylen, "replayed or reordered command: seq %" PRId64 " is not above %"
                 PRId64 ", the last accepted from this client", seq, c->last_seq);
    else {
        c->last_seq = seq, c->last_us = now_us;
        return WG_OK;
    }
    return WG_EAUTH;
}

int auth_check(auth *a, const void *buf, const wire_sig *sig, const char *client,
               int64_t seq, int64_t utime, int64_t now_us, char *why, size_t whylen)
{
    if (!a->on)
        return WG_OK;
    const unsigned char *b = buf;
    if (sig->mac_len != WG_MAC_BYTES)
        snprintf(why, whylen, "unsigned command: this daemon accepts signed commands only "
                              "(PROTOCOL.md, \"Signed commands\"; a client's --key-file)");
    else if (!wg_mac_ok(a->key, b, sig->signed_len, b + sig->mac_at))
        snprintf(why, whylen, "bad signature: not signed with this daemon's key");
    else if (fresh_ok(a, client, seq, utime, now_us, why, whylen) == WG_OK)
        return WG_OK;
    a->refused++;
    return WG_EAUTH;
}

/* auth.c - signed commands: key, MAC, time window, per-client counters and
 * the floor that stands in for the counters of clients not tracked. */
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
    a->forgot_us = INT64_MIN;
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

const unsigned char *auth_key(const auth *a) { return a->on ? a->key : NULL; }

void auth_fini(auth *a)
{
    volatile unsigned char *k = a->key; /* not optimised away */
    for (size_t i = 0; i < sizeof a->key; i++)
        k[i] = 0;
    a->on = 0;
    a->path[0] = 0;
}

/* A command from an id not tracked must be signed after this (us): after
 * the key was taken, and after every command of every id let go. */
static int64_t floor_us(const auth *a)
{
    int64_t open = auth_open_us(a);
    return a->forgot_us > open ? a->forgot_us : open;
}

static uint64_t id_hash(int chan, const char *id) /* FNV-1a: a quick first test */
{
    uint64_t h = (14695981039346656037u ^ (unsigned)chan) * 1099511628211u;
    for (; *id; id++)
        h = (h ^ (unsigned char)*id) * 1099511628211u;
    return h;
}

/* Stop tracking c. Its commands, all signed no later than its max_utime,
 * stay refused through the floor. */
static void forget(auth *a, auth_client *c)
{
    if (c->max_utime > a->forgot_us)
        a->forgot_us = c->max_utime;
    *c = (auth_client){0};
}

/* The slot tracking id, or NULL. A slot whose commands are all stale by
 * now is let go: they are refused as stale anyway, and the id may be a new
 * process with a reused pid, counting from 1 again. */
static auth_client *find(auth *a, int chan, const char *id, uint64_t h, int64_t now_us)
{
    for (int i = 0; i < AUTH_CLIENTS; i++) {
        auth_client *c = &a->seen[i];
        if (!c->used || c->hash != h || c->chan != chan || strcmp(c->id, id) != 0)
            continue;
        if (((double)now_us - (double)c->max_utime) / US > AUTH_WINDOW_S) {
            forget(a, c);
            return NULL;
        }
        return c;
    }
    return NULL;
}

/* A slot for id: a free one, else the one whose latest command is oldest
 * (forgetting it raises the floor the least). Never refuses: a full table
 * costs only clients whose clocks lag, through the floor. */
static auth_client *take(auth *a, int chan, const char *id, uint64_t h)
{
    auth_client *old = &a->seen[0];
    for (int i = 0; i < AUTH_CLIENTS && old->used; i++)
        if (!a->seen[i].used || a->seen[i].max_utime < old->max_utime)
            old = &a->seen[i];
    if (old->used)
        forget(a, old);
    *old = (auth_client){.used = 1, .chan = (unsigned char)chan, .hash = h,
                         .last_seq = INT64_MIN, .max_utime = INT64_MIN};
    snprintf(old->id, sizeof old->id, "%s", id);
    return old;
}

/* Why a message from an id not tracked, signed at utime, is refused, and
 * when signing it again helps. */
static void say_too_early(const auth *a, int64_t utime, int64_t now_us, char *why, size_t len)
{
    int64_t open = auth_open_us(a);
    double wait = ((double)floor_us(a) - (double)now_us) / US;
    char again[48] = "sign it again";
    if (wait > 0)
        snprintf(again, sizeof again, "sign it again in %.3f s", wait);
    if (utime <= open)
        snprintf(why, len, "signed %.3f s before this daemon started taking signed commands "
                 "(%g s after its start or key change), so it may be a replay of one an "
                 "earlier run or another key accepted: %s (if this repeats, this host's clock "
                 "lags the daemon's)", ((double)open - (double)utime) / US, AUTH_AHEAD_S, again);
    else
        snprintf(why, len, "signed no later than a message of a client this daemon stopped "
                 "tracking to make room (it tracks %d signing clients; one it does not could "
                 "replay): %s (if this repeats, this host's clock lags the daemon's)",
                 AUTH_CLIENTS, again);
}

static const char *noun(int chan) { return chan == AUTH_TICK ? "tick" : "command"; }

/* The time checks: the window, then the counter or the floor. */
static int fresh_ok(auth *a, int chan, const char *client, int64_t seq, int64_t utime,
                    int64_t now_us, char *why, size_t whylen)
{
    double skew = ((double)utime - (double)now_us) / US;
    uint64_t h = id_hash(chan, client);
    auth_client *c = NULL;
    if (!(skew >= -AUTH_WINDOW_S))
        snprintf(why, whylen, "stale %s: signed %.3g s before the daemon's clock (it "
                 "accepts up to %g s before and %g s ahead)", noun(chan), -skew, AUTH_WINDOW_S,
                 AUTH_AHEAD_S);
    else if (!(skew <= AUTH_AHEAD_S))
        snprintf(why, whylen, "signed %.3g s ahead of the daemon's clock (it accepts up to %g s "
                 "ahead, as a command from further ahead could outlive a daemon restart, and "
                 "%g s before): check the clocks (NTP)", skew, AUTH_AHEAD_S, AUTH_WINDOW_S);
    else if (!(c = find(a, chan, client, h, now_us)) && utime <= floor_us(a))
        say_too_early(a, utime, now_us, why, whylen);
    else if (c && seq <= c->last_seq)
        snprintf(why, whylen, "replayed or reordered %s: seq %" PRId64 " is not above %" PRId64
                 ", the last accepted from this client", noun(chan), seq, c->last_seq);
    else {
        c = c ? c : take(a, chan, client, h);
        c->last_seq = seq;
        c->max_utime = utime > c->max_utime ? utime : c->max_utime;
        return WG_OK;
    }
    return WG_EAUTH;
}

int auth_check(auth *a, int chan, const void *msg, size_t len, int32_t mac_len,
               const char *client, int64_t seq, int64_t utime, int64_t now_us, char *why,
               size_t whylen)
{
    if (!a->on)
        return WG_OK;
    if (mac_len != WG_MAC_BYTES)
        snprintf(why, whylen, "unsigned %s: this daemon accepts signed %ss only (PROTOCOL.md, "
                 "\"Signed commands\"; a client's --key-file)", noun(chan), noun(chan));
    else if (!wg_mac_sealed(a->key, msg, len))
        snprintf(why, whylen, "bad signature: not signed with this daemon's key");
    else if (fresh_ok(a, chan, client, seq, utime, now_us, why, whylen) == WG_OK)
        return WG_OK;
    a->refused++;
    return WG_EAUTH;
}

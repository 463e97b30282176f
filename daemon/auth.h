/* auth.h - signed commands: with a key, every CMD and TICK must carry a MAC.
 *
 * LCM has no authentication: anything that reaches the multicast group can
 * send commands. With `command_key_file` set, a command is accepted only if
 * (1) it carries a MAC (cmd_t.mac_len = 32): libsodium's crypto_auth
 * (HMAC-SHA-512-256) with the shared 32-byte key over every byte of the
 * message before mac_len; (2) its utime is at most AUTH_WINDOW_S behind and
 * AUTH_AHEAD_S ahead of the daemon's clock; (3) its seq is above the last
 * one accepted from the same client id, or, for an id the daemon does not
 * track (new, or forgotten to make room), its utime is after the daemon
 * took the key plus AUTH_AHEAD_S and after the latest utime of every id it
 * forgot (an id's commands and its ticks are counted apart). (3) is what
 * makes a replay fail: every command or tick accepted before, by this run
 * or an earlier one (a restart, a crash), is either under its id's counter
 * or signed no later than that floor. Anything else gets EAUTH (a tick:
 * logged and dropped) and changes nothing. The key file holds the key as
 * 64 hexadecimal digits (wgctl keygen FILE writes one; wormgear/wg_key.h);
 * a relative name is looked up in $CREDENTIALS_DIRECTORY (systemd
 * LoadCredential=). Without a key, commands and ticks are accepted
 * unsigned (a MAC, if present, is ignored), as before. Lower module: no
 * calls up; time comes in as arguments. */
#ifndef WGD_AUTH_H
#define WGD_AUTH_H

#include <stddef.h>
#include <stdint.h>

#include "wire.h"
#include "wormgear/wg_key.h"

enum { AUTH_CLIENTS = 1024 };
#define AUTH_WINDOW_S 30.0 /* utime may be this far behind the daemon's clock, seconds */
#define AUTH_AHEAD_S 1.0   /* and this far ahead (the wait after taking a key) */

/* What a signed message is: each client id has a counter on each. */
enum { AUTH_CMD, AUTH_TICK };

typedef struct auth_client {
    int used;                  /* 0: a free slot ("" is an id like any other) */
    unsigned char chan;        /* AUTH_CMD or AUTH_TICK */
    char id[WIRE_MAX_CLIENT + 1];
    uint64_t hash;             /* of id: most slots are passed over on it */
    int64_t last_seq;          /* highest seq accepted from this id */
    int64_t max_utime;         /* latest utime accepted from this id */
} auth_client;

typedef struct auth {
    int on;                    /* a key is loaded */
    unsigned char key[WG_KEY_BYTES];
    char path[600];            /* where it was read from */
    int64_t since_us;          /* daemon clock when this key was taken */
    int64_t forgot_us;         /* latest utime of an id no longer tracked */
    auth_client seen[AUTH_CLIENTS];
    uint64_t refused;          /* commands refused with EAUTH */
} auth;

/* Read the key from path ("" = signing off; the format is wg_key_load's) at
 * daemon wall time now_us. A relative path is taken in
 * $CREDENTIALS_DIRECTORY when that is set. A key that differs from the one
 * in use (or the first) starts afresh: no id is tracked and nothing signed
 * before now_us + AUTH_AHEAD_S is accepted; the same key re-read changes
 * nothing. WG_OK, or WG_EIO / WG_EINVAL with why; on error the previous key
 * stays. */
int auth_load(auth *a, const char *path, int64_t now_us, char *why, size_t whylen);

/* The daemon wall time (us) from which a command signed at that time is
 * accepted from any id: the caller waits for it before taking commands. */
int64_t auth_open_us(const auth *a);

/* The key the daemon signs its ACK, PARAMS and STATUS with (lcmio), or
 * NULL when signing is off. */
const unsigned char *auth_key(const auth *a);

/* Forget the key (memory wiped). */
void auth_fini(auth *a);

/* Check the message msg of len bytes on chan (a command or a tick, already
 * through wire_cmd_check or wire_tick_check, which said mac_len) from
 * client with seq and utime, at wall time now_us: WG_OK (and the client's
 * counter on chan advanced), or WG_EAUTH with why. Always WG_OK when
 * signing is off. */
int auth_check(auth *a, int chan, const void *msg, size_t len, int32_t mac_len,
               const char *client, int64_t seq, int64_t utime, int64_t now_us, char *why,
               size_t whylen);

#endif

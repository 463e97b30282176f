/* wg_key.h - the shared key of signed commands, and the MAC.
 *
 * One rule in one place for the daemon and every client that sends
 * commands: a key file holds a 32-byte key as 64 hexadecimal digits (and
 * an optional newline), in a regular file that group and others cannot
 * read; a command's MAC is libsodium's crypto_auth (HMAC-SHA-512-256) of
 * the message bytes it covers (lcmtypes/PROTOCOL.md, "Signed commands"). */
#ifndef WG_KEY_H
#define WG_KEY_H

#include <stddef.h>

enum { WG_KEY_BYTES = 32, WG_MAC_BYTES = 32 };

/* Read a key file into key. WG_OK, or WG_EIO (cannot read, not a regular
 * file, readable by group or others) / WG_EINVAL (not 64 hex digits, or a
 * placeholder: every byte the same) with why naming the file. */
int wg_key_load(const char *path, unsigned char key[WG_KEY_BYTES], char *why, size_t whylen);

/* Write a new random key to path (created with mode 0600; an existing file
 * is never overwritten). WG_OK, or WG_EIO with why. */
int wg_key_create(const char *path, char *why, size_t whylen);

/* The MAC of len bytes of msg under key, into mac. */
void wg_mac(const unsigned char key[WG_KEY_BYTES], const void *msg, size_t len,
            unsigned char mac[WG_MAC_BYTES]);

/* 1 if mac is the MAC of msg under key (constant time), else 0. */
int wg_mac_ok(const unsigned char key[WG_KEY_BYTES], const void *msg, size_t len,
              const unsigned char mac[WG_MAC_BYTES]);

/* A signed message's tail (lcmtypes/PROTOCOL.md, "Signed commands" and
 * "Signed answers"): its last field is the MAC, an int32 mac_len (big-endian,
 * WG_MAC_BYTES) and then the MAC of every byte before mac_len. msg is the
 * whole encoded message, n bytes. */

/* Write the MAC into msg's last WG_MAC_BYTES (encoded with mac_len =
 * WG_MAC_BYTES); nothing when n is too short to hold the tail. */
void wg_mac_seal(const unsigned char key[WG_KEY_BYTES], unsigned char *msg, size_t n);

/* 1 if msg ends in such a tail (mac_len = WG_MAC_BYTES) and its MAC is
 * right under key (constant time), else 0. */
int wg_mac_sealed(const unsigned char key[WG_KEY_BYTES], const unsigned char *msg, size_t n);

/* Who may have sent an answer that a client with a key did not take, as
 * wgctl, wgrig and wgweb say when no signed one came. */
#define WG_KEY_UNSIGNED_WHO                                                                 \
    "a daemon without command_key_file or with another key (if it was the daemon's, it "     \
    "did what that says), or another sender on the bus"

#endif

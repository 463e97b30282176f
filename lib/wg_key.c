/* wg_key.c - key files and MACs of signed commands (libsodium). */
#include "wormgear/wg_key.h"
#include "wormgear/wg_file.h"

#include "wormgear/wg_status.h"

#include <errno.h>
#include <fcntl.h>
#include <sodium.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/* A key file is 64 hexadecimal digits and a line end; a larger file is
 * not one (read whole, it would only be refused later). */
enum { KEY_FILE_MAX = 1024 };

/* libsodium must be initialised once before use; sodium_init is safe to
 * call again and from several threads. */
static int sodium_ready(void) { return sodium_init() >= 0; }

int wg_key_load(const char *path, unsigned char key[WG_KEY_BYTES], char *why, size_t whylen)
{
    char text[KEY_FILE_MAX + 1];
    struct stat st;
    int fd = wg_file_open(path, "key file", WG_FILE_NOFOLLOW, KEY_FILE_MAX, &st, why, whylen);
    if (fd < 0)
        return WG_EIO;
    if (st.st_mode & 077) {
        close(fd);
        snprintf(why, whylen, "key file %s is readable by group or others (mode %03o): "
                              "chmod 600 it", path, (unsigned)(st.st_mode & 0777));
        return WG_EIO;
    }
    ssize_t n = read(fd, text, sizeof text - 1);
    close(fd);
    text[n > 0 ? n : 0] = 0;
    size_t len = strcspn(text, "\r\n"), got = 0;
    /* the digits, then at most one line end ("\n" or "\r\n"); nothing else */
    const char *end = text + len;
    size_t tail = n > 0 ? (size_t)n - len : 0;
    int ended = tail == 0 || (tail == 1 && end[0] == '\n') ||
                (tail == 2 && end[0] == '\r' && end[1] == '\n');
    if (len != 2 * WG_KEY_BYTES || !ended ||
        sodium_hex2bin(key, WG_KEY_BYTES, text, len, NULL, &got, NULL) != 0 ||
        got != WG_KEY_BYTES) {
        sodium_memzero(text, sizeof text);
        snprintf(why, whylen, "key file %s: not a key (64 hexadecimal digits; wgctl keygen "
                              "FILE writes one)", path);
        return WG_EINVAL;
    }
    sodium_memzero(text, sizeof text);
    /* a placeholder (every byte the same: 00...0, ff...f) is no secret */
    size_t same = 1;
    while (same < WG_KEY_BYTES && key[same] == key[0])
        same++;
    if (same == WG_KEY_BYTES) {
        sodium_memzero(key, WG_KEY_BYTES);
        snprintf(why, whylen, "key file %s: every byte of the key is the same, a placeholder "
                              "anyone can guess (wgctl keygen FILE writes a random key)", path);
        return WG_EINVAL;
    }
    return WG_OK;
}

int wg_key_create(const char *path, char *why, size_t whylen)
{
    unsigned char key[WG_KEY_BYTES];
    char hex[2 * WG_KEY_BYTES + 1];
    if (!sodium_ready()) {
        snprintf(why, whylen, "libsodium could not be initialised");
        return WG_EIO;
    }
    int fd = open(path, O_WRONLY | O_CREAT | O_EXCL | O_NOFOLLOW | O_CLOEXEC, 0600);
    if (fd < 0) {
        snprintf(why, whylen, "cannot create key file %s: %s", path, strerror(errno));
        return WG_EIO;
    }
    crypto_auth_keygen(key);
    sodium_bin2hex(hex, sizeof hex, key, sizeof key);
    hex[2 * WG_KEY_BYTES] = '\n';
    int bad = write(fd, hex, sizeof hex) != (ssize_t)sizeof hex || fsync(fd) != 0;
    bad |= close(fd) != 0;
    sodium_memzero(key, sizeof key);
    sodium_memzero(hex, sizeof hex);
    if (bad) {
        snprintf(why, whylen, "cannot write key file %s: %s", path, strerror(errno));
        unlink(path);
        return WG_EIO;
    }
    return WG_OK;
}

void wg_mac(const unsigned char key[WG_KEY_BYTES], const void *msg, size_t len,
            unsigned char mac[WG_MAC_BYTES])
{
    sodium_ready();
    crypto_auth(mac, msg, len, key);
}

int wg_mac_ok(const unsigned char key[WG_KEY_BYTES], const void *msg, size_t len,
              const unsigned char mac[WG_MAC_BYTES])
{
    sodium_ready();
    return crypto_auth_verify(mac, msg, len, key) == 0;
}

enum { TAIL = 4 + WG_MAC_BYTES }; /* mac_len, then the MAC */

void wg_mac_seal(const unsigned char key[WG_KEY_BYTES], unsigned char *msg, size_t n)
{
    if (n >= TAIL)
        wg_mac(key, msg, n - TAIL, msg + n - WG_MAC_BYTES);
}

int wg_mac_sealed(const unsigned char key[WG_KEY_BYTES], const unsigned char *msg, size_t n)
{
    if (n < TAIL)
        return 0;
    const unsigned char *len = msg + n - TAIL;
    uint32_t mac_len = (uint32_t)len[0] << 24 | (uint32_t)len[1] << 16 | (uint32_t)len[2] << 8 | len[3];
    return mac_len == WG_MAC_BYTES && wg_mac_ok(key, msg, n - TAIL, msg + n - WG_MAC_BYTES);
}

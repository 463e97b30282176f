/* lcmio.c - LCM instance, channel names, encode-and-publish helpers. */
#include "lcmio.h"

#include "wormgear/wg_key.h"
#include "wormgear/wg_mcast.h"
#include "wormgear/wg_status.h"

#include <dirent.h>
#include <errno.h>
#include <stdio.h>
#include <string.h>
#include <poll.h>
#include <sys/time.h>
#include <unistd.h>

static const char *const suffix[CH_COUNT] = {"CMD",     "ACK",    "PARAMS", "STATE", "POINCARE",
                                             "CONTACT", "STATUS", "TICK",   "SCOPE"};

const char *lcmio_channel_suffix(int ch) { return ch >= 0 && ch < CH_COUNT ? suffix[ch] : "?"; }

int lcmio_init(lcmio *io, const char *url, const char *prefix, char *why, size_t whylen)
{
    memset(io, 0, sizeof *io);
    for (int i = 0; i < CH_COUNT; i++)
        snprintf(io->ch[i], sizeof io->ch[i], "%s%s", prefix, suffix[i]);
    char full[400];
    /* a receive buffer for bursts of commands, unless the URL sets one (the
     * kernel caps it at net.core.rmem_max) */
    if (!strncmp(url, "udpm://", 7) && !strstr(url, "recv_buf_size"))
        snprintf(full, sizeof full, "%s%crecv_buf_size=%d", url, strchr(url, '?') ? '&' : '?',
                 LCMIO_RECV_BUF);
    else
        snprintf(full, sizeof full, "%s", url);
    int rc = wg_mcast_route(url, why, whylen); /* WG_EINVAL for port 0, else WG_EIO */
    if (rc)
        return rc;
    snprintf(io->url, sizeof io->url, "%s", url);
    io->lcm = lcm_create(full);
    if (!io->lcm) { /* LCM has said why on stderr */
        snprintf(why, whylen, "LCM could not open '%s' (LCM's reason is above); a URL is "
                 WG_LCM_URL_FORMS, url);
        return WG_EINVAL;
    }
    return WG_OK;
}

int lcmio_subscribe(lcmio *io, int ch, lcm_msg_handler_t fn, void *user, int queue, char *why,
                    size_t whylen)
{
    lcm_subscription_t *s = lcm_subscribe(io->lcm, io->ch[ch], fn, user);
    if (!s) {
        snprintf(why, whylen, "LCM: cannot subscribe %s", io->ch[ch]);
        return WG_EIO;
    }
    lcm_subscription_set_queue_capacity(s, queue);
    int rc = io->guarded ? WG_OK : wg_mcast_guard(io->url, WG_MCAST_WHOLE, why, whylen);
    if (rc != WG_OK)
        return rc;
    io->guarded = 1;
    return WG_OK;
}

int lcmio_sent(const lcmio *io, int ch, int64_t seq, int64_t utime)
{
    return seq >= 0 && seq < io->seq[ch] && io->seq[ch] - seq <= LCMIO_SENT &&
           io->sent_utime[ch][(uint64_t)seq % LCMIO_SENT] == utime;
}

void lcmio_fini(lcmio *io)
{
    if (io->lcm)
        lcm_destroy(io->lcm);
    io->lcm = NULL;
}

int lcmio_fileno(const lcmio *io) { return lcm_get_fileno(io->lcm); }

static int readable(int fd)
{
    struct pollfd p = {.fd = fd, .events = POLLIN};
    return poll(&p, 1, 0) > 0 && (p.revents & (POLLIN | POLLHUP | POLLERR)); /* as select */
}

int lcmio_waiting(const lcmio *io) { return readable(lcm_get_fileno(io->lcm)); }

int lcmio_drain(lcmio *io, int max)
{
    int n = 0, fd = lcm_get_fileno(io->lcm);
    while (n < max && readable(fd) && lcm_handle(io->lcm) == 0)
        n++;
    return n;
}

/* The socket inodes among this process's file descriptors (at most max). */
static int socket_inodes(unsigned long *ino, int max)
{
    DIR *dir = opendir("/proc/self/fd");
    struct dirent *e;
    int n = 0;
    while (dir && n < max && (e = readdir(dir))) {
        char path[300], link[64];
        snprintf(path, sizeof path, "/proc/self/fd/%s", e->d_name);
        ssize_t k = readlink(path, link, sizeof link - 1);
        if (k > 0 && (link[k] = 0, sscanf(link, "socket:[%lu]", &ino[n]) == 1))
            n++;
    }
    if (dir)
        closedir(dir);
    return n;
}

uint64_t lcmio_rx_dropped(void)
{
    unsigned long ino[64], line_ino;
    unsigned long long drops, total = 0;
    int n = socket_inodes(ino, 64);
    FILE *f = n ? fopen("/proc/net/udp", "r") : NULL;
    char line[512];
    while (f && fgets(line, sizeof line, f)) {
        /* sl local rem st tx:rx tr:when retrnsmt uid timeout inode ref pointer drops */
        if (sscanf(line, "%*s %*s %*s %*s %*s %*s %*s %*s %*s %lu %*s %*s %llu", &line_ino,
                   &drops) != 2)
            continue;
        for (int i = 0; i < n; i++)
            total += ino[i] == line_ino ? drops : 0;
    }
    if (f)
        fclose(f);
    return total;
}

int64_t lcmio_now_us(void)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    return (int64_t)tv.tv_sec * 1000000 + tv.tv_usec;
}

static int send(lcmio *io, int ch, int len)
{
    errno = 0;
    if (len < 0 || lcm_publish(io->lcm, io->ch[ch], io->buf, (unsigned)len) != 0) {
        io->dropped++; /* LCM's sendmsg left its errno (no route, the interface down) */
        io->send_errno = len < 0 ? EMSGSIZE : errno ? errno : EIO;
        return -1;
    }
    io->published++;
    return 0;
}

void lcmio_sign_with(lcmio *io, const unsigned char *key) { io->key = key; }

/* n bytes encoded in io->buf, sealed (wg_mac_seal) when a key is set. n,
 * or n < 0 as it came. */
static int sign(lcmio *io, int n)
{
    if (n > 0 && io->key)
        wg_mac_seal(io->key, io->buf, (size_t)n);
    return n;
}

#define PUB(T, CH)                                                                     \
    int lcmio_pub_##T(lcmio *io, wormgear_##T##_t *m)                                  \
    {                                                                                  \
        unsigned char mac[WG_MAC_BYTES] = {0};                                         \
        m->utime = lcmio_now_us();                                                     \
        m->seq = io->seq[CH]++;                                                        \
        io->sent_utime[CH][(uint64_t)m->seq % LCMIO_SENT] = m->utime;                  \
        m->mac_len = io->key ? WG_MAC_BYTES : 0, m->mac = mac;                         \
        int n = wormgear_##T##_t_encode(io->buf, 0, LCMIO_BUF, m);                     \
        m->mac_len = 0, m->mac = NULL;                                                 \
        return send(io, CH, sign(io, n));                                              \
    }
PUB(ack, CH_ACK)
PUB(params, CH_PARAMS)
PUB(status, CH_STATUS)
PUB(state, CH_STATE)
PUB(poincare, CH_POINCARE)
PUB(contact, CH_CONTACT)
PUB(scope, CH_SCOPE)
#undef PUB

/* lcmio.c - LCM instance, channel names, encode-and-publish helpers. */
#include "lcmio.h"

#include "wormgear/wg_status.h"

#include <stdio.h>
#include <string.h>
#include <sys/select.h>
#include <sys/time.h>

static const char *const suffix[CH_COUNT] = {"CMD",      "ACK",     "PARAMS", "STATE",
                                             "POINCARE", "CONTACT", "STATUS", "TICK"};

const char *lcmio_channel_suffix(int ch) { return ch >= 0 && ch < CH_COUNT ? suffix[ch] : "?"; }

int lcmio_init(lcmio *io, const char *url, const char *prefix, char *why, size_t whylen)
{
    memset(io, 0, sizeof *io);
    for (int i = 0; i < CH_COUNT; i++)
        snprintf(io->ch[i], sizeof io->ch[i], "%s%s", prefix, suffix[i]);
    io->lcm = lcm_create(url);
    if (!io->lcm) {
        snprintf(why, whylen, "LCM: cannot open '%s' (bad URL, or no route for multicast: "
                              "see docs/daemon.md)", url);
        return WG_EIO;
    }
    return WG_OK;
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
    fd_set set;
    struct timeval tv = {0, 0};
    FD_ZERO(&set);
    FD_SET(fd, &set);
    return select(fd + 1, &set, NULL, NULL, &tv) > 0;
}

int lcmio_drain(lcmio *io, int max)
{
    int n = 0, fd = lcm_get_fileno(io->lcm);
    while (n < max && readable(fd) && lcm_handle(io->lcm) == 0)
        n++;
    return n;
}

int64_t lcmio_now_us(void)
{
    struct timeval tv;
    gettimeofday(&tv, NULL);
    return (int64_t)tv.tv_sec * 1000000 + tv.tv_usec;
}

static int send(lcmio *io, int ch, int len)
{
    if (len < 0 || lcm_publish(io->lcm, io->ch[ch], io->buf, (unsigned)len) != 0) {
        io->dropped++;
        return -1;
    }
    io->published++;
    return 0;
}

#define PUB(T, CH)                                                                  \
    int lcmio_pub_##T(lcmio *io, wormgear_##T##_t *m)                               \
    {                                                                               \
        m->utime = lcmio_now_us();                                                  \
        m->seq = io->seq[CH]++;                                                     \
        return send(io, CH, wormgear_##T##_t_encode(io->buf, 0, LCMIO_BUF, m));     \
    }
PUB(ack, CH_ACK)
PUB(params, CH_PARAMS)
PUB(state, CH_STATE)
PUB(poincare, CH_POINCARE)
PUB(contact, CH_CONTACT)
PUB(status, CH_STATUS)
#undef PUB

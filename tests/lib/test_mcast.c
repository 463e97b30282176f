/* test_mcast.c - a udpm:// URL's multicast group as LCM 1.3.1 reads it
 * (lib/wg_mcast.c): no group is LCM's default one, the port and the options
 * do not matter, inet_aton's forms count; anything else (another provider,
 * a unicast or unreadable address, no address before the port) is left to
 * LCM, and wg_mcast_route then tries no socket. The route itself is
 * sys.wgctl's: in a network namespace with no route, and with one.
 *
 * wg_mcast_guard's filter, datagram by datagram: a UDP socket bound to
 * 127.0.0.1 stands for LCM's, and each datagram is followed by a marker,
 * so the first one read says whether the filter kept it. What LCM does
 * with what is kept is sys.fuzz_wire's. */
#include "test.h"
#include "wormgear/wg_mcast.h"
#include "wormgear/wg_status.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <poll.h>
#include <stdint.h>
#include <sys/socket.h>
#include <unistd.h>

static void test_groups(void)
{
    static const struct {
        const char *url, *group; /* NULL: not one of LCM's multicast groups */
    } c[] = {
        {"udpm://239.255.76.67:7667?ttl=0", "239.255.76.67"},
        {"udpm://", WG_LCM_DEFAULT_GROUP},
        {"udpm://?ttl=1", WG_LCM_DEFAULT_GROUP},
        {"udpm://239.1.2.3", "239.1.2.3"},
        {"udpm://239.1.2.3?ttl=0&recv_buf_size=2097152", "239.1.2.3"},
        {"udpm://239.1.2.3:0", "239.1.2.3"},
        {"udpm://239.1.2.3:99999", "239.1.2.3"}, /* LCM refuses the port, not the route */
        {"udpm://0xef010203:7667", "239.1.2.3"},  /* inet_aton's forms */
        {"udpm://224.0.0.1:1", "224.0.0.1"},
        {"udpm://10.0.0.1:7667?ttl=0", NULL},
        {"udpm://240.0.0.1:7667", NULL},
        {"udpm://:7667", NULL},
        {"udpm://bogus:1", NULL},
        {"udpm://239.1.2.3.4:7667", NULL},
        {"udpm://[ff02::1]:7667", NULL},
        {"udpm://2391111111111111111111111111111111111111111111111111111111111111111111:1", NULL},
        {"UDPM://239.1.2.3:7667", NULL},
        {"memq://", NULL},
        {"file:///tmp/x.lcmlog?mode=r", NULL},
        {"tcpq://127.0.0.1:7700", NULL},
        {"", NULL},
        {NULL, NULL},
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        char name[WG_MCAST_NAME] = "", why[300] = "";
        int got = wg_mcast_group(c[i].url, name);
        printf("%-75s -> %s\n", c[i].url ? c[i].url : "(null)", got ? name : "(LCM judges)");
        ASSERT_EQ_INT(got, c[i].group != NULL);
        if (c[i].group)
            ASSERT_STR(name, c[i].group);
        else /* no group: no socket, no refusal */
            ASSERT_EQ_INT(wg_mcast_route(c[i].url, why, sizeof why), WG_OK);
    }
}

enum { LC02 = 0x4c433032, LC03 = 0x4c433033 };

typedef struct dgram {
    unsigned char b[3000];
    size_t n;
} dgram;

static void put32(dgram *d, uint32_t v)
{
    uint32_t be = htonl(v);
    memcpy(d->b + d->n, &be, 4), d->n += 4;
}

static void put16(dgram *d, uint16_t v)
{
    uint16_t be = htons(v);
    memcpy(d->b + d->n, &be, 2), d->n += 2;
}

/* ch with its NUL unless cut, then len bytes of 'x' */
static void tail(dgram *d, const char *ch, int cut, size_t len)
{
    size_t k = strlen(ch) + !cut;
    memcpy(d->b + d->n, ch, k), d->n += k;
    memset(d->b + d->n, 'x', len), d->n += len;
}

static dgram shortmsg(const char *ch, int cut, size_t len)
{
    dgram d = {.n = 0};
    put32(&d, LC02), put32(&d, 7);
    tail(&d, ch, cut, len);
    return d;
}

/* A fragment: no of count, at off in a message of size bytes; the first
 * (no 0) carries the channel. */
static dgram fragment(uint32_t size, uint32_t off, uint16_t no, uint16_t count, const char *ch,
                      int cut, size_t len)
{
    dgram d = {.n = 0};
    put32(&d, LC03), put32(&d, 9), put32(&d, size), put32(&d, off);
    put16(&d, no), put16(&d, count);
    if (no == 0)
        tail(&d, ch, cut, len);
    else
        memset(d.b + d.n, 'y', len), d.n += len;
    return d;
}

/* Sends d, then a marker; 1 if d is the first to arrive, 0 if the marker
 * is, -1 if nothing came within a second. */
static int kept(int tx, int rx, const struct sockaddr_in *to, const dgram *d)
{
    static const char marker[] = "LC02\0\0\0\0MARK";
    unsigned char got[4096];
    sendto(tx, d->b, d->n, 0, (const struct sockaddr *)to, sizeof *to);
    sendto(tx, marker, sizeof marker, 0, (const struct sockaddr *)to, sizeof *to);
    struct pollfd p = {.fd = rx, .events = POLLIN};
    if (poll(&p, 1, 1000) != 1)
        return -1;
    ssize_t n = recv(rx, got, sizeof got, 0);
    int first = !(n == (ssize_t)sizeof marker && !memcmp(got, marker, sizeof marker));
    if (first && poll(&p, 1, 1000) == 1) /* the marker behind it */
        recv(rx, got, sizeof got, 0);
    return first;
}

static void test_guard(void)
{
    char chan63[64], why[300] = "";
    memset(chan63, 'c', 63), chan63[63] = 0;
    const struct {
        const char *what;
        dgram d;
        int keep;
    } c[] = {
        {"a short message", shortmsg("WG_CMD", 0, 100), 1},
        {"a short message, a 63-byte channel", shortmsg(chan63, 0, 10), 1},
        {"a short message, its channel at the end", shortmsg("WG_CMD", 0, 0), 1},
        {"a first fragment", fragment(3000, 0, 0, 3, "WG_CMD", 0, 1300), 1},
        /* msg_size counts the data, not the channel: a first fragment whose
         * message ends 1 byte later is whole, as is one of a single fragment */
        {"a first fragment, 1 byte of the message after it",
         fragment(1301, 0, 0, 2, "WORMGEAR_POINCARE", 0, 1300), 1},
        {"a message in one fragment", fragment(1300, 0, 0, 1, "WORMGEAR_POINCARE", 0, 1300), 1},
        {"a first fragment, 1 byte past its message",
         fragment(1299, 0, 0, 2, "WORMGEAR_POINCARE", 0, 1300), 0},
        {"a middle fragment", fragment(3000, 1393, 1, 3, "", 0, 1400), 1},
        {"a last fragment, ending at the message's end", fragment(3000, 2793, 2, 3, "", 0, 207),
         1},
        {"offset + size wraps 32 bits (LCM copies 4 GB)",
         fragment(3000, 0xffffff00u, 1, 2, "", 0, 512), 0},
        {"a first fragment at a wrapping offset", fragment(3000, 0xffffff00u, 0, 2, "WG_CMD", 0,
                                                           512), 0},
        {"a fragment one byte past its message", fragment(3000, 2793, 2, 3, "", 0, 208), 0},
        {"a fragment's offset past its message", fragment(3000, 3001, 1, 3, "", 0, 0), 0},
        {"a count of 0", fragment(3000, 100, 1, 0, "", 0, 100), 0},
        {"a number equal to the count", fragment(3000, 100, 3, 3, "", 0, 100), 0},
        {"a first fragment not at offset 0", fragment(3000, 10, 0, 3, "WG_CMD", 0, 100), 0},
        {"a first fragment, its channel cut", fragment(3000, 0, 0, 3, "WG_CMD", 1, 0), 0},
        {"a short message, its channel cut", shortmsg("WG_CMD", 1, 0), 0},
        {"a short message, a 64-byte channel", shortmsg(chan63, 1, 1), 0},
    };
    int rx = socket(AF_INET, SOCK_DGRAM, 0), tx = socket(AF_INET, SOCK_DGRAM, 0);
    struct sockaddr_in to = {.sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    socklen_t tl = sizeof to;
    ASSERT_TRUE(rx >= 0 && tx >= 0);
    ASSERT_EQ_INT(bind(rx, (struct sockaddr *)&to, sizeof to), 0);
    ASSERT_EQ_INT(getsockname(rx, (struct sockaddr *)&to, &tl), 0);
    char url[80];
    snprintf(url, sizeof url, "udpm://239.255.76.67:%d?ttl=0", ntohs(to.sin_port));
    /* with fragments (wglog record), then without (the daemon, the clients): the
     * second attach replaces the first filter; without, every fragment is dropped,
     * the message in one first fragment too */
    ASSERT_EQ_INT(wg_mcast_filtered(url), 0); /* bound to 127.0.0.1: no filter from bind */
    int len[2] = {0, 0};
    for (int frag = WG_MCAST_FRAGMENTS; frag >= WG_MCAST_WHOLE; frag--) {
        printf("-- %s\n", frag ? "WG_MCAST_FRAGMENTS" : "WG_MCAST_WHOLE");
        ASSERT_EQ_INT(wg_mcast_guard(url, frag, why, sizeof why), WG_OK);
        len[frag] = wg_mcast_filtered(url);
        printf("the filter on the port: %d instructions\n", len[frag]);
        ASSERT_TRUE(len[frag] > 0);
        for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
            int k = kept(tx, rx, &to, &c[i].d), whole = c[i].d.b[3] == '2';
            printf("%-50s %4zu bytes: %s\n", c[i].what, c[i].d.n, k ? "kept" : "dropped");
            ASSERT_EQ_INT(k, c[i].keep && (frag || whole));
        }
        /* cut headers and other magics */
        static const unsigned char cut[] = {'L', 'C', '0', '3', 0, 0, 0, 9, 0, 0, 0xb, 0xb8,
                                            0xff, 0xff, 0xff, 0, 0, 1, 0, 2};
        for (size_t n = 0; n < sizeof cut; n++) {
            dgram d = {.n = n};
            memcpy(d.b, cut, n);
            ASSERT_EQ_INT(kept(tx, rx, &to, &d), 0);
            d.b[3] = '2'; /* "LC02" with no room for its channel (from 9 bytes: an empty one) */
            ASSERT_EQ_INT(kept(tx, rx, &to, &d), n > 8);
        }
        dgram other = shortmsg("WG_CMD", 0, 10);
        other.b[3] = '4';
        ASSERT_EQ_INT(kept(tx, rx, &to, &other), 0);
    }
    ASSERT_TRUE(len[WG_MCAST_WHOLE] < len[WG_MCAST_FRAGMENTS]); /* the second replaced the first */
    close(rx), close(tx);
    ASSERT_EQ_INT(wg_mcast_filtered(url), -1); /* no socket on the port */
    ASSERT_EQ_INT(wg_mcast_filtered("memq://"), -1);
    /* not a udpm:// URL: nothing to do; no socket on the port: said */
    ASSERT_EQ_INT(wg_mcast_guard("memq://", WG_MCAST_WHOLE, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_mcast_guard("udpm://239.255.76.67:0?ttl=0", WG_MCAST_WHOLE, why, sizeof why),
                  WG_EINVAL);
    ASSERT_TRUE(strstr(why, "port 0") != NULL);
    /* and before LCM opens it (its self-test fails after 10 s there): the route check,
     * which every program runs first; 0x0 is LCM's strtol's zero too */
    why[0] = '\0';
    ASSERT_EQ_INT(wg_mcast_route("udpm://239.255.76.67:0?ttl=0", why, sizeof why), WG_EINVAL);
    ASSERT_TRUE(strstr(why, "port 0") != NULL);
    ASSERT_EQ_INT(wg_mcast_route("udpm://239.255.76.67:0x0", why, sizeof why), WG_EINVAL);
    ASSERT_EQ_INT(wg_mcast_route("memq://", why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_mcast_guard(url, WG_MCAST_FRAGMENTS, why, sizeof why), WG_EIO);
    printf("no socket: %s\n", why);
    ASSERT_TRUE(strstr(why, "no LCM receive socket on port") != NULL);
}

/* LCM's receive socket is filtered from its bind (wg_mcast.c's bind, which
 * liblcm's call reaches): an IPv4 UDP socket with SO_REUSEADDR bound to a
 * port on any address (LCM 1.3.1's) or on a multicast group's (later
 * LCM's) has the WG_MCAST_FRAGMENTS program before any datagram can reach
 * it; one without SO_REUSEADDR, one bound to 127.0.0.1, and a TCP socket
 * have none (wgfuzz checks LCM's own socket, bound to any address, in
 * sys.fuzz_*). SO_GET_FILTER with no buffer gives a socket's filter length,
 * in instructions. */
static socklen_t filter_len(int fd)
{
    socklen_t n = 0;
    if (getsockopt(fd, SOL_SOCKET, SO_GET_FILTER, NULL, &n))
        return 0;
    return n;
}

/* A UDP socket bound to addr:port (SO_REUSEADDR if reuse): its filter's length. */
static socklen_t bound_filter(const char *addr, uint16_t port, int reuse, int type)
{
    int fd = socket(AF_INET, type, 0), one = 1;
    ASSERT_TRUE(fd >= 0);
    if (reuse)
        setsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &one, sizeof one);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_port = htons(port)};
    inet_pton(AF_INET, addr, &a.sin_addr);
    ASSERT_EQ_INT(filter_len(fd), 0);
    ASSERT_EQ_INT(bind(fd, (struct sockaddr *)&a, sizeof a), 0);
    socklen_t n = filter_len(fd);
    printf("%-15s port %5u %-12s %s: %u filter instructions after bind\n", addr, port,
           reuse ? "SO_REUSEADDR" : "", type == SOCK_DGRAM ? "UDP" : "TCP", (unsigned)n);
    if (reuse && type == SOCK_DGRAM) { /* the kernel's own errors still come back */
        errno = 0;
        ASSERT_EQ_INT(bind(fd, (struct sockaddr *)&a, sizeof a), -1);
        ASSERT_EQ_INT(errno, EINVAL);
    }
    close(fd);
    return n;
}

static void test_bind_filtered(void)
{
    /* a free port: the kernel's pick for a socket closed at once */
    int p = socket(AF_INET, SOCK_DGRAM, 0);
    struct sockaddr_in a = {.sin_family = AF_INET, .sin_addr.s_addr = htonl(INADDR_LOOPBACK)};
    socklen_t al = sizeof a;
    ASSERT_EQ_INT(bind(p, (struct sockaddr *)&a, sizeof a), 0);
    ASSERT_EQ_INT(getsockname(p, (struct sockaddr *)&a, &al), 0);
    uint16_t port = ntohs(a.sin_port);
    close(p);
    /* no socket here is bound to any address (LCM 1.3.1's form), which would listen
     * beyond this host: sys.fuzz_* check LCM's own socket, in a network namespace */
    ASSERT_TRUE(bound_filter("239.255.76.67", port, 1, SOCK_DGRAM) > 100); /* later LCM */
    ASSERT_EQ_INT(bound_filter("239.255.76.67", port, 0, SOCK_DGRAM), 0);
    ASSERT_EQ_INT(bound_filter("127.0.0.1", port, 1, SOCK_DGRAM), 0);
    ASSERT_EQ_INT(bound_filter("127.0.0.1", port, 1, SOCK_STREAM), 0);
}

TEST_MAIN(TEST(test_groups), TEST(test_guard), TEST(test_bind_filtered))

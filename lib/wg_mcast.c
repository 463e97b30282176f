/* wg_mcast.c - a udpm:// URL's multicast route, and the filter on LCM's
 * receive socket (wg_mcast.h). */
#include "wormgear/wg_mcast.h"
#include "wormgear/wg_status.h"

#include <arpa/inet.h>
#include <dirent.h>
#include <errno.h>
#include <linux/filter.h>
#include <netinet/in.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/syscall.h>
#include <unistd.h>

/* The group of udpm://NETWORK[?options] as LCM 1.3.1 reads NETWORK: empty
 * for its default group, else GROUP[:PORT] with GROUP as inet_aton takes
 * it (the port does not change the route). */
static int group_of(const char *url, struct in_addr *group)
{
    static const char scheme[] = "udpm://";
    if (!url || strncmp(url, scheme, sizeof scheme - 1) != 0)
        return 0;
    const char *net = url + sizeof scheme - 1;
    size_t n = strcspn(net, ":?");
    char addr[64];
    if (n == 0 && (net[0] == '\0' || net[0] == '?'))
        snprintf(addr, sizeof addr, "%s", WG_LCM_DEFAULT_GROUP);
    else if (n < sizeof addr)
        memcpy(addr, net, n), addr[n] = '\0';
    else
        return 0;
    return inet_aton(addr, group) != 0 && IN_MULTICAST(ntohl(group->s_addr));
}

int wg_mcast_group(const char *url, char name[WG_MCAST_NAME])
{
    struct in_addr g;
    return group_of(url, &g) && inet_ntop(AF_INET, &g, name, WG_MCAST_NAME) != NULL;
}

/* The port of a udpm://GROUP[:PORT][?options] URL as LCM 1.3.1 reads it
 * (strtol, base 0, after the ':'; 7667 without one), or -1 if url is not a
 * udpm:// one or its port is not one LCM takes. */
static int port_of(const char *url)
{
    static const char scheme[] = "udpm://";
    if (!url || strncmp(url, scheme, sizeof scheme - 1) != 0)
        return -1;
    const char *net = url + sizeof scheme - 1, *colon = strchr(net, ':'), *q = strchr(net, '?');
    if (!colon || (q && colon > q))
        return 7667;
    char *end;
    long port = strtol(colon + 1, &end, 0);
    return end == colon + 1 || port < 0 || port > 65535 ? -1 : (int)port;
}

/* The refusal of a udpm:// URL with port 0 (LCM would listen on a port the
 * kernel picks, which no sender knows; its self-test then fails after 10 s). */
static int port_zero(char *why, size_t whylen)
{
    snprintf(why, whylen, "a udpm:// URL with port 0: give the bus's port, e.g. "
             "udpm://239.255.76.67:7667?ttl=0");
    return WG_EINVAL;
}

int wg_mcast_route(const char *url, char *why, size_t whylen)
{
    struct in_addr g;
    char name[WG_MCAST_NAME];
    if (port_of(url) == 0)
        return port_zero(why, whylen);
    if (!group_of(url, &g) || !inet_ntop(AF_INET, &g, name, sizeof name))
        return WG_OK;
    struct sockaddr_in sa = {.sin_family = AF_INET, .sin_port = htons(7667), .sin_addr = g};
    int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0), err = errno;
    if (fd < 0) {
        snprintf(why, whylen, "cannot open a UDP socket for the multicast group %s: %s", name,
                 strerror(err));
        return WG_EIO;
    }
    int rc = connect(fd, (const struct sockaddr *)&sa, sizeof sa);
    err = errno;
    close(fd);
    if (rc == 0)
        return WG_OK;
    if (err == ENETUNREACH || err == EHOSTUNREACH)
        snprintf(why, whylen, "no route to the multicast group %s (%s): add one, e.g. `ip route "
                 "add 239.0.0.0/8 dev lo` for this host only (docs/daemon.md)", name,
                 strerror(err));
    else
        snprintf(why, whylen, "cannot send to the multicast group %s: %s (docs/daemon.md)", name,
                 strerror(err));
    return WG_EIO;
}

/* A socket filter sees a UDP datagram from its UDP header on: LCM's
 * header starts after it. The offsets below are LCM 1.3.1's udpm format
 * (lcm_udpm.c): "LC02" seqno channel NUL data, or "LC03" seqno msg_size
 * fragment_offset fragment_no fragments_in_msg [channel NUL] data, every
 * field big-endian. */
enum {
    UDPH = 8,
    LC_SHORT = 0x4c433032, /* "LC02" */
    LC_LONG = 0x4c433033,  /* "LC03" */
    LONG_HDR = 20,
    CHAN_MAX = 63, /* LCM_MAX_CHANNEL_NAME_LENGTH */
    KEEP = 0x7fffffff,
    NUL_LEN = 2 * (CHAN_MAX + 1) + 2, /* nul_within's instructions */
    PROG_MAX = 2 * NUL_LEN + 2 * (CHAN_MAX + 1) + 60
};

typedef struct prog {
    struct sock_filter f[PROG_MAX];
    int n, over;
} prog;

static void op(prog *p, unsigned short code, unsigned k, unsigned char jt, unsigned char jf)
{
    if (p->n == PROG_MAX)
        p->over = 1;
    else
        p->f[p->n++] = (struct sock_filter){code, jt, jf, k};
}

/* Go on if A (compared with k, or with X for BPF_X) meets the jump's
 * test, else drop the datagram. */
static void need(prog *p, unsigned short jump, unsigned k)
{
    op(p, BPF_JMP | jump, k, 1, 0);
    op(p, BPF_RET | BPF_K, 0, 0, 0);
}

/* Keep the datagram if a NUL is among the CHAN_MAX + 1 bytes from off,
 * inside it (a load past its end drops it), else drop it. */
static void nul_within(prog *p, unsigned off)
{
    for (unsigned i = 0; i <= CHAN_MAX; i++) {
        op(p, BPF_LD | BPF_B | BPF_ABS, off + i, 0, 0);
        op(p, BPF_JMP | BPF_JEQ | BPF_K, 0, (unsigned char)(2 * (CHAN_MAX - i) + 1), 0);
    }
    op(p, BPF_RET | BPF_K, 0, 0, 0);
    op(p, BPF_RET | BPF_K, KEEP, 0, 0);
}

/* A later fragment (no > 0): inside its message, offset + size <=
 * msg_size computed without LCM's 32-bit wrap. */
static void later_fragment(prog *p)
{
    op(p, BPF_LD | BPF_W | BPF_LEN, 0, 0, 0);
    op(p, BPF_ALU | BPF_SUB | BPF_K, UDPH + LONG_HDR, 0, 0);
    op(p, BPF_ST, 0, 0, 0); /* M[0]: the fragment's bytes */
    op(p, BPF_LD | BPF_W | BPF_ABS, UDPH + 12, 0, 0);
    op(p, BPF_MISC | BPF_TAX, 0, 0, 0); /* X: its offset */
    op(p, BPF_LD | BPF_W | BPF_ABS, UDPH + 8, 0, 0);
    need(p, BPF_JGE | BPF_X, 0); /* msg_size >= offset */
    op(p, BPF_ALU | BPF_SUB | BPF_X, 0, 0, 0);
    op(p, BPF_ST, 1, 0, 0); /* M[1]: the room from the offset on */
    op(p, BPF_LDX | BPF_W | BPF_MEM, 0, 0, 0);
    op(p, BPF_LD | BPF_W | BPF_MEM, 1, 0, 0);
    need(p, BPF_JGE | BPF_X, 0); /* the room >= the fragment's bytes */
    op(p, BPF_RET | BPF_K, KEEP, 0, 0);
}

/* The first fragment (no 0): at offset 0, its channel ending inside it
 * within CHAN_MAX + 1 bytes, and its data after the channel (msg_size
 * counts only data) no more than msg_size. */
static void first_fragment(prog *p)
{
    const unsigned off = UDPH + LONG_HDR;
    op(p, BPF_LD | BPF_W | BPF_ABS, UDPH + 12, 0, 0);
    need(p, BPF_JEQ | BPF_K, 0);
    for (unsigned i = 0; i <= CHAN_MAX; i++) { /* A: the channel's bytes with its NUL */
        op(p, BPF_LD | BPF_B | BPF_ABS, off + i, 0, 0);
        op(p, BPF_JMP | BPF_JEQ | BPF_K, 0, 0, 2);
        op(p, BPF_LD | BPF_IMM, i + 1, 0, 0);
        op(p, BPF_JMP | BPF_JA, 4 * (CHAN_MAX - i) + 1, 0, 0);
    }
    op(p, BPF_RET | BPF_K, 0, 0, 0);
    op(p, BPF_MISC | BPF_TAX, 0, 0, 0);
    op(p, BPF_LD | BPF_W | BPF_LEN, 0, 0, 0);
    op(p, BPF_ALU | BPF_SUB | BPF_K, off, 0, 0);
    op(p, BPF_ALU | BPF_SUB | BPF_X, 0, 0, 0); /* the data's bytes: the NUL is inside */
    op(p, BPF_MISC | BPF_TAX, 0, 0, 0);
    op(p, BPF_LD | BPF_W | BPF_ABS, UDPH + 8, 0, 0);
    need(p, BPF_JGE | BPF_X, 0); /* msg_size >= the data's bytes */
    op(p, BPF_RET | BPF_K, KEEP, 0, 0);
}

/* The filter: a short message's channel ends inside the datagram; with
 * fragments, a fragment has its whole header, is numbered below its count
 * and lies inside its message (later_fragment, first_fragment); without,
 * none is kept. Everything else, LCM would drop or mishandle: dropped. */
static void build(prog *p, int fragments)
{
    p->n = p->over = 0;
    op(p, BPF_LD | BPF_W | BPF_ABS, UDPH, 0, 0);
    op(p, BPF_JMP | BPF_JEQ | BPF_K, LC_SHORT, 0, NUL_LEN);
    nul_within(p, UDPH + 8);
    if (!fragments) {
        op(p, BPF_RET | BPF_K, 0, 0, 0);
        return;
    }
    need(p, BPF_JEQ | BPF_K, LC_LONG);
    op(p, BPF_LD | BPF_W | BPF_LEN, 0, 0, 0);
    need(p, BPF_JGE | BPF_K, UDPH + LONG_HDR);
    op(p, BPF_LD | BPF_H | BPF_ABS, UDPH + 18, 0, 0);
    op(p, BPF_MISC | BPF_TAX, 0, 0, 0); /* X: fragments_in_msg */
    op(p, BPF_LD | BPF_H | BPF_ABS, UDPH + 16, 0, 0);
    op(p, BPF_JMP | BPF_JGE | BPF_X, 0, 0, 1); /* fragment_no >= count: drop */
    op(p, BPF_RET | BPF_K, 0, 0, 0);
    int at = p->n;
    op(p, BPF_JMP | BPF_JEQ | BPF_K, 0, 0, 0); /* no 0: past later_fragment */
    later_fragment(p);
    if (!p->over)
        p->f[at].jt = (unsigned char)(p->n - at - 1);
    first_fragment(p);
}

/* The filter for a socket: build's program in p, fp pointing at it; 0, or
 * -1 if it has more than PROG_MAX instructions (then nothing to attach). */
static int program(prog *p, int fragments, struct sock_fprog *fp)
{
    build(p, fragments);
    fp->len = (unsigned short)p->n, fp->filter = p->f;
    return p->over ? -1 : 0;
}

/* 1 if fd is an IPv4 UDP socket bound to port. */
static int bound_udp(int fd, int port)
{
    int type = 0;
    socklen_t tl = sizeof type;
    struct sockaddr_in sa;
    socklen_t sl = sizeof sa;
    return getsockopt(fd, SOL_SOCKET, SO_TYPE, &type, &tl) == 0 && type == SOCK_DGRAM &&
           getsockname(fd, (struct sockaddr *)&sa, &sl) == 0 && sl >= sizeof sa &&
           sa.sin_family == AF_INET && ntohs(sa.sin_port) == port;
}

/* 1 if fd, about to be bound to addr, looks like LCM's receive socket: an
 * IPv4 UDP socket with SO_REUSEADDR, bound to a port (not 0) on any
 * address (LCM 1.3.1) or on a multicast group's (later LCM). */
static int lcm_recv_like(int fd, const struct sockaddr *addr, socklen_t len)
{
    const struct sockaddr_in *in = (const struct sockaddr_in *)(const void *)addr;
    if (!addr || len < sizeof *in || addr->sa_family != AF_INET || !in->sin_port)
        return 0;
    uint32_t a = ntohl(in->sin_addr.s_addr);
    int type = 0, reuse = 0;
    socklen_t tl = sizeof type, rl = sizeof reuse;
    return (a == INADDR_ANY || IN_MULTICAST(a)) &&
           getsockopt(fd, SOL_SOCKET, SO_TYPE, &type, &tl) == 0 && type == SOCK_DGRAM &&
           getsockopt(fd, SOL_SOCKET, SO_REUSEADDR, &reuse, &rl) == 0 && reuse;
}

/* bind(2) for every caller in the process, LCM among them: a socket that
 * looks like LCM's receive socket (lcm_recv_like) gets the
 * WG_MCAST_FRAGMENTS filter (WG_MCAST_WHOLE with $WG_MCAST_BIND=whole: the
 * preloaded library under lcm-spy, whose Java LCM no later guard reaches)
 * before it is bound, so no datagram reaches it
 * unfiltered (wg_mcast_guard, after the first subscription, comes too late
 * for what arrives before it: a datagram queued in the meantime is not
 * filtered). The executable's definition comes first in the dynamic
 * linker's order, so liblcm's call lands here; the kernel's bind is then
 * called directly. wg_mcast_guard may then replace the filter
 * (WG_MCAST_WHOLE). A filter that cannot be attached here is left to
 * wg_mcast_guard to report. */
__attribute__((visibility("default"))) int bind(int fd, const struct sockaddr *addr,
                                               socklen_t len)
{
    if (lcm_recv_like(fd, addr, len)) {
        const char *m = getenv("WG_MCAST_BIND");
        prog p;
        struct sock_fprog fp;
        if (!program(&p, m && !strcmp(m, "whole") ? WG_MCAST_WHOLE : WG_MCAST_FRAGMENTS, &fp))
            setsockopt(fd, SOL_SOCKET, SO_ATTACH_FILTER, &fp, sizeof fp);
    }
    return (int)syscall(SYS_bind, fd, addr, len);
}

/* Calls fn(fd, ctx) for every IPv4 UDP socket of this process bound to
 * port; the sockets seen, or -1 with errno when the process's files cannot
 * be listed. */
static int each_bound(int port, void (*fn)(int fd, void *ctx), void *ctx)
{
    DIR *dir = opendir("/proc/self/fd");
    if (!dir)
        return -1;
    int seen = 0;
    struct dirent *e;
    while ((e = readdir(dir))) {
        char *end;
        long fd = strtol(e->d_name, &end, 10);
        if (end == e->d_name || *end || fd == dirfd(dir) || !bound_udp((int)fd, port))
            continue;
        fn((int)fd, ctx);
        seen++;
    }
    closedir(dir);
    return seen;
}

typedef struct attach {
    const struct sock_fprog *fp;
    int failed, err;
} attach;

static void attach_one(int fd, void *ctx)
{
    attach *a = ctx;
    if (setsockopt(fd, SOL_SOCKET, SO_ATTACH_FILTER, a->fp, sizeof *a->fp))
        a->failed++, a->err = errno;
}

int wg_mcast_guard(const char *url, int fragments, char *why, size_t whylen)
{
    int port = port_of(url);
    if (port < 0)
        return WG_OK;
    if (port == 0)
        return port_zero(why, whylen);
    prog p;
    struct sock_fprog fp;
    if (program(&p, fragments, &fp)) {
        snprintf(why, whylen, "LCM's socket filter has more than %d instructions", PROG_MAX);
        return WG_EIO;
    }
    attach a = {&fp, 0, 0};
    int seen = each_bound(port, attach_one, &a);
    if (seen < 0)
        snprintf(why, whylen, "cannot list this process's files to filter LCM's socket: %s",
                 strerror(errno));
    else if (a.failed)
        snprintf(why, whylen, "cannot filter LCM's receive socket on port %d: %s", port,
                 strerror(a.err));
    else if (!seen)
        snprintf(why, whylen, "no LCM receive socket on port %d to filter (subscribe first)",
                 port);
    return seen <= 0 || a.failed ? WG_EIO : WG_OK;
}

/* The least of the filter lengths seen so far (-1: none seen yet). */
static void filter_len(int fd, void *ctx)
{
    int *least = ctx;
    socklen_t n = 0;
    int got = getsockopt(fd, SOL_SOCKET, SO_GET_FILTER, NULL, &n) == 0 ? (int)n : 0;
    if (*least < 0 || got < *least)
        *least = got;
}

int wg_mcast_filtered(const char *url)
{
    int port = port_of(url), least = -1;
    if (port > 0)
        each_bound(port, filter_len, &least);
    return least;
}

/* wg_mcast.c - a udpm:// URL's multicast route (wg_mcast.h). */
#include "wormgear/wg_mcast.h"
#include "wormgear/wg_status.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

/* The group and port of udpm://A.B.C.D:PORT[?options]; 0 if url is not of
 * that form. */
static int udpm_group(const char *url, struct sockaddr_in *sa, char *group, size_t glen)
{
    static const char scheme[] = "udpm://";
    if (strncmp(url, scheme, sizeof scheme - 1) != 0)
        return 0;
    const char *net = url + sizeof scheme - 1, *colon = strchr(net, ':');
    size_t n = colon ? (size_t)(colon - net) : 0;
    if (!colon || n == 0 || n >= glen)
        return 0;
    memcpy(group, net, n);
    group[n] = '\0';
    char *end;
    errno = 0;
    long port = strtol(colon + 1, &end, 10);
    if (errno || end == colon + 1 || (*end != '\0' && *end != '?') || port < 1 || port > 65535)
        return 0;
    memset(sa, 0, sizeof *sa);
    sa->sin_family = AF_INET;
    sa->sin_port = htons((unsigned short)port);
    return inet_pton(AF_INET, group, &sa->sin_addr) == 1 &&
           IN_MULTICAST(ntohl(sa->sin_addr.s_addr));
}

int wg_mcast_route(const char *url, char *why, size_t whylen)
{
    struct sockaddr_in sa;
    char group[INET_ADDRSTRLEN];
    if (!url || !udpm_group(url, &sa, group, sizeof group))
        return WG_OK;
    int fd = socket(AF_INET, SOCK_DGRAM | SOCK_CLOEXEC, 0);
    if (fd < 0)
        return WG_OK; /* LCM will fail to open it too, and say why */
    int rc = connect(fd, (const struct sockaddr *)&sa, sizeof sa), err = errno;
    close(fd);
    if (rc == 0 || (err != ENETUNREACH && err != EHOSTUNREACH))
        return WG_OK;
    snprintf(why, whylen, "no route to the multicast group %s of %s (%s): add one, "
             "`ip route add 239.0.0.0/8 dev lo` for this host only (ttl=0), or with the LAN's "
             "interface in place of lo for ttl=1 (docs/daemon.md)", group, url, strerror(err));
    return WG_EIO;
}

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

int wg_mcast_route(const char *url, char *why, size_t whylen)
{
    struct in_addr g;
    char name[WG_MCAST_NAME];
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

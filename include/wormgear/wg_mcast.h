/* wg_mcast.h - can this host send to a udpm:// URL's multicast group?
 *
 * LCM 1.3.1 tests the route when it opens a udpm:// URL. Without one it
 * prints a page of advice that names an address which is not the group's
 * and tools Debian 12 does not install (ifconfig, route), and lcm_create
 * then fails as it does for a misspelt URL. The daemon and the clients ask
 * here first, so that a missing route is one line naming the group and the
 * fix, and a URL LCM refuses is a configuration error of its own. */
#ifndef WG_MCAST_H
#define WG_MCAST_H

#include <stddef.h>

/* WG_OK if url is not of the form udpm://A.B.C.D:PORT[?...] with a
 * multicast group (LCM judges it), or a UDP socket connects to the group
 * (what LCM's own test does); WG_EIO with why (one sentence naming the
 * group and the command that adds a route) when the host has no route to
 * it. */
int wg_mcast_route(const char *url, char *why, size_t whylen);

/* The forms of an LCM URL, for the message when LCM refuses one. */
#define WG_LCM_URL_FORMS                                                                     \
    "udpm://GROUP:PORT?ttl=0 (this host) or ?ttl=1 (the LAN), memq://, file://PATH or "     \
    "tcpq://HOST:PORT"

#endif

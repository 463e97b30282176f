/* wg_mcast.h - can this host send to a udpm:// URL's multicast group, and
 * a filter that keeps datagrams LCM mishandles away from its socket?
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

enum { WG_MCAST_NAME = 16 }; /* "255.255.255.255" and its NUL */

/* LCM's group when a udpm:// URL names none (udpm:// or udpm://?ttl=0). */
#define WG_LCM_DEFAULT_GROUP "239.255.76.67"

/* The multicast group of a udpm:// URL, read as LCM 1.3.1 reads it (no
 * group: WG_LCM_DEFAULT_GROUP; GROUP[:PORT], GROUP as inet_aton takes it):
 * 1 and the group in dotted form in name, or 0 if url is not a udpm:// one
 * or names no multicast group that way (LCM judges it). */
int wg_mcast_group(const char *url, char name[WG_MCAST_NAME]);

/* WG_OK if wg_mcast_group finds no group in url, or a UDP socket connects
 * to the group (what LCM's own test does); else WG_EIO with why, one
 * sentence naming the group: "no route to the multicast group G (...):
 * add one, e.g. `ip route add 239.0.0.0/8 dev lo` ..." when the host has
 * no route to it, the error otherwise. WG_EINVAL for a udpm:// URL with
 * port 0, before LCM opens it (its self-test would fail after 10 s). */
int wg_mcast_route(const char *url, char *why, size_t whylen);

/* Filters LCM's receive socket for a udpm:// URL, so that datagrams LCM
 * 1.3.1 would read out of bounds never reach it. Its fragment check adds
 * offset and size in 32 bits, so a fragment whose sum wraps is copied ~4
 * GB past its buffer: one datagram on the group kills any process that
 * listens. Kept: a short message whose channel ends inside it; with
 * WG_MCAST_FRAGMENTS, also a fragment with its whole header, inside its
 * message, numbered below its count, the first at offset 0 with its
 * channel ending inside it. With WG_MCAST_WHOLE no fragment is kept: LCM
 * sends a message in one datagram when its channel, NUL and data fit
 * 65,499 bytes (WG_MCAST_WHOLE_MAX), as every message wormgeard sends or
 * takes does, so a process that needs no other gives LCM's reassembly
 * nothing to work on (a message counted whole from a repeated fragment,
 * its missing part left as heap; first fragments of 4 GB messages). Call
 * it right after the first lcm_subscribe on the URL (which opens the
 * socket). Before that, from its bind, the socket has the
 * WG_MCAST_FRAGMENTS filter: this library defines bind(2), which LCM's
 * call reaches, and filters an IPv4 UDP socket with SO_REUSEADDR bound to
 * a port on any address or on a multicast group's before binding it
 * (every other bind goes straight to the kernel). WG_OK if url is
 * not a udpm:// one or every UDP socket of this process bound to its port
 * now has the filter; WG_EINVAL for port 0 (no sender could reach it);
 * else WG_EIO; with why. */
enum { WG_MCAST_WHOLE = 0, WG_MCAST_FRAGMENTS = 1 };
enum { WG_MCAST_WHOLE_MAX = 65499 }; /* channel, NUL and data of an unfragmented message */
int wg_mcast_guard(const char *url, int fragments, char *why, size_t whylen);

/* The instructions of the filter on this process's UDP sockets bound to
 * url's port (the shortest, if there are several; 0 for a socket with
 * none), or -1 if url is not a udpm:// one with a port or no socket is
 * bound to it. What wg_mcast_guard or the bind left there: a test's check
 * that LCM's socket was never unfiltered. */
int wg_mcast_filtered(const char *url);

/* The forms of an LCM URL, for the message when LCM refuses one. */
#define WG_LCM_URL_FORMS                                                                     \
    "udpm://GROUP:PORT?ttl=0 (this host) or ?ttl=1 (the LAN), memq://, file://PATH or "     \
    "tcpq://HOST:PORT"

#endif

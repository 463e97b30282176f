/* web_opt.h - wgweb's command line: every option with its default and
 * range, parsed with getopt_long; numbers with strtod, an end pointer,
 * isfinite and the range. */
#ifndef WEB_OPT_H
#define WEB_OPT_H

#include <stddef.h>

typedef struct web_opt {
    const char *url, *prefix; /* NULL: $WORMGEAR_URL / $WORMGEAR_PREFIX or defaults */
    const char *listen;       /* an IPv4 or IPv6 address: "127.0.0.1" */
    int port;                 /* 8765 */
    const char *web_root;     /* NULL: $WGWEB_ROOT or <exe>/../share/wormgear/web */
    int allow_commands;
    const char *key_file;     /* sign commands (NULL: $WORMGEAR_KEY_FILE, or unsigned) */
    const char *origins[8];   /* --allow-origin: web pages allowed besides this bridge's own */
    int norigins;
    double scope_hz, poincare_hz, contact_hz;
    int contacts_all;         /* --contacts all: bearings too */
    int queue_len;            /* data messages per client */
    int max_clients;
    int max_frame;            /* bytes */
    double heartbeat_s;       /* no STATUS for this long: "no heartbeat" */
    double ack_timeout_s;
    int verbose;
} web_opt;

/* Parse argv into o. 0 to run, 1 after --help (printed to stdout), 2 on a
 * usage error (the message, naming the option and its allowed values, on
 * stderr). */
int web_opt_parse(web_opt *o, int argc, char **argv);

/* Whether addr is a loopback address (127.0.0.0/8, ::1, ::ffff:127.0.0.0/104);
 * anything that is not an IP address is not. */
int web_opt_is_loopback(const char *addr);

#endif

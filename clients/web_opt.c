/* web_opt.c - wgweb's options. */
#include "web_opt.h"

#include "cli.h"

#include <arpa/inet.h>
#include <getopt.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* One numeric option: name, where it goes, range, whether integer. */
typedef struct num_opt {
    const char *name;
    size_t off;
    int is_int;
    double min, max;
    const char *unit;
} num_opt;

#define OFF(f) offsetof(web_opt, f)
static const num_opt nums[] = {
    {"port", OFF(port), 1, 0, 65535, "TCP port (0: any free one, printed)"},
    {"scope-hz", OFF(scope_hz), 0, 1, 20000, "/scope samples per wall second"},
    {"poincare-hz", OFF(poincare_hz), 0, 0, 50000, "/poincare sections per wall second, at most"},
    {"contact-hz", OFF(contact_hz), 0, 0, 50000, "/contact events per wall second, at most"},
    {"queue", OFF(queue_len), 1, 16, 1000000, "messages queued per client before the oldest drop"},
    {"max-clients", OFF(max_clients), 1, 1, 64, "WebSocket clients at once"},
    {"max-frame", OFF(max_frame), 1, 1024, 16777216, "largest frame accepted from a client, bytes"},
    {"heartbeat", OFF(heartbeat_s), 0, 0.5, 60, "seconds without STATUS before 'no heartbeat'"},
    {"ack-timeout", OFF(ack_timeout_s), 0, 0.1, 60, "seconds to wait for the daemon's ACK"},
};

static void defaults(web_opt *o)
{
    memset(o, 0, sizeof *o);
    o->listen = "127.0.0.1";
    o->port = 8765;
    o->scope_hz = 300;
    o->poincare_hz = 500;
    o->contact_hz = 200;
    o->queue_len = 4096;
    o->max_clients = 16;
    o->max_frame = 65536;
    o->heartbeat_s = 3;
    o->ack_timeout_s = 3;
}

static void usage(const web_opt *d)
{
    printf("usage: wgweb [options]\n"
           "Bridge a wormgeard's LCM channels to the Foxglove WebSocket protocol\n"
           "(foxglove.websocket.v1) and serve the dashboard, on one HTTP port.\n\n"
           "  --url URL           LCM URL (default $WORMGEAR_URL or udpm://239.255.76.67:7667?ttl=0)\n"
           "  --prefix P          channel prefix (default $WORMGEAR_PREFIX or WORMGEAR_)\n"
           "  --listen ADDR       IP address to listen on (default %s, or ::1, localhost;\n"
           "                      others warn)\n"
           "  --web-root DIR      dashboard files (default $WGWEB_ROOT or\n"
           "                      <exe>/../share/wormgear/web)\n"
           "  --allow-commands    accept setParameters and clientPublish (/cmd)\n"
           "  --key-file FILE     sign commands with this key (default $WORMGEAR_KEY_FILE):\n"
           "                      needed when the daemon has command_key_file\n"
           "  --allow-origin O    a web page origin allowed to connect besides this\n"
           "                      bridge's own (e.g. https://app.foxglove.dev); repeatable.\n"
           "                      A browser WebSocket from any other origin is refused\n"
           "  --contacts mesh|all contact events on /contact (default mesh)\n"
           "  --verbose           log connections and commands\n",
           d->listen);
    for (size_t i = 0; i < sizeof nums / sizeof nums[0]; i++) {
        const char *p = (const char *)d + nums[i].off;
        double v = nums[i].is_int ? *(const int *)p : *(const double *)p;
        char opt[40];
        snprintf(opt, sizeof opt, "%s N", nums[i].name);
        printf("  --%-17s %s (default %g; [%g, %g])\n", opt, nums[i].unit, v, nums[i].min,
               nums[i].max);
    }
    printf("  -h, --help         this text\n\n"
           "Exit status: 0 stopped by SIGTERM or SIGINT, 1 could not start (the port, the\n"
           "web root, no route to LCM's group), 2 usage error (a URL LCM refuses too).\n");
}

static int set_num(web_opt *o, const num_opt *n, const char *text)
{
    char *end;
    double v = strtod(text, &end);
    if (end == text || *end || !isfinite(v) || v < n->min || v > n->max ||
        (n->is_int && v != floor(v))) {
        fprintf(stderr, "wgweb: --%s '%s': %s%s in [%g, %g]\n", n->name, text,
                n->is_int ? "an integer " : "a number ", n->unit, n->min, n->max);
        return 2;
    }
    char *p = (char *)o + n->off;
    if (n->is_int)
        *(int *)p = (int)v;
    else
        *(double *)p = v;
    return 0;
}

enum { O_URL = 256, O_PREFIX, O_LISTEN, O_ROOT, O_ALLOW, O_CONTACTS, O_VERBOSE, O_HELP, O_KEY,
       O_ORIGIN, O_NUM };

/* --listen: an IPv4 or IPv6 address (localhost: 127.0.0.1). lws also took
 * interface and host names, and one it could not find ("localhost",
 * "127.1", a typo) it kept waiting for: wgweb ran on, listening nowhere,
 * and printed http://localhost:0/. */
static int set_listen(web_opt *o, const char *arg)
{
    unsigned char a[16];
    if (!strcmp(arg, "localhost"))
        arg = "127.0.0.1";
    if (inet_pton(AF_INET, arg, a) != 1 && inet_pton(AF_INET6, arg, a) != 1) {
        fprintf(stderr, "wgweb: --listen '%s': not an IP address; an IPv4 or IPv6 address of "
                        "this host (127.0.0.1 the default, ::1, or localhost; 0.0.0.0 or :: for "
                        "every interface, with a warning)\n", arg);
        return 2;
    }
    o->listen = arg;
    return 0;
}

static int parse_one(web_opt *o, int c, const char *arg)
{
    switch (c) {
    case O_URL: o->url = arg; return 0;
    case O_PREFIX: o->prefix = arg; return 0;
    case O_LISTEN: return set_listen(o, arg);
    case O_ROOT: o->web_root = arg; return 0;
    case O_ALLOW: o->allow_commands = 1; return 0;
    case O_KEY: o->key_file = arg; return 0;
    case O_ORIGIN:
        if (o->norigins == (int)(sizeof o->origins / sizeof o->origins[0])) {
            fprintf(stderr, "wgweb: --allow-origin: at most %zu\n",
                    sizeof o->origins / sizeof o->origins[0]);
            return 2;
        }
        o->origins[o->norigins++] = arg;
        return 0;
    case O_VERBOSE: o->verbose = 1; return 0;
    case O_CONTACTS:
        if (strcmp(arg, "mesh") && strcmp(arg, "all")) {
            fprintf(stderr, "wgweb: --contacts '%s': mesh or all\n", arg);
            return 2;
        }
        o->contacts_all = !strcmp(arg, "all");
        return 0;
    default:
        if (c >= O_NUM && c < O_NUM + (int)(sizeof nums / sizeof nums[0]))
            return set_num(o, &nums[c - O_NUM], arg);
        return 2;
    }
}

int web_opt_parse(web_opt *o, int argc, char **argv)
{
    struct option lo[32] = {
        {"url", 1, 0, O_URL},         {"prefix", 1, 0, O_PREFIX},
        {"listen", 1, 0, O_LISTEN},   {"web-root", 1, 0, O_ROOT},
        {"allow-commands", 0, 0, O_ALLOW}, {"contacts", 1, 0, O_CONTACTS},
        {"verbose", 0, 0, O_VERBOSE}, {"help", 0, 0, O_HELP},
        {"key-file", 1, 0, O_KEY},    {"allow-origin", 1, 0, O_ORIGIN}};
    int n = 10, c, rc;
    for (size_t i = 0; i < sizeof nums / sizeof nums[0]; i++)
        lo[n++] = (struct option){nums[i].name, 1, 0, O_NUM + (int)i};
    lo[n] = (struct option){0, 0, 0, 0};
    defaults(o);
    opterr = 0;
    optind = 1;
    while ((c = getopt_long(argc, argv, "h", lo, NULL)) != -1) {
        if (c == O_HELP || c == 'h') { /* -h as every other client takes it */
            web_opt d;
            defaults(&d);
            usage(&d);
            return 1;
        }
        if (c == '?' || c == ':')
            return cli_getopt_error("wgweb", argv, "h", lo);
        if ((rc = parse_one(o, c, optarg)) != 0)
            return rc;
    }
    if (optind < argc) {
        fprintf(stderr, "wgweb: unexpected argument '%s' (see --help)\n", argv[optind]);
        return 2;
    }
    return 0;
}

int web_opt_is_loopback(const char *addr)
{
    static const unsigned char one[16] = {[15] = 1};
    static const unsigned char v4mapped[12] = {[10] = 0xff, [11] = 0xff}; /* ::ffff:a.b.c.d */
    unsigned char a[16];
    if (inet_pton(AF_INET, addr, a) == 1)
        return a[0] == 127;
    if (inet_pton(AF_INET6, addr, a) != 1)
        return 0;
    return !memcmp(a, one, 16) || (!memcmp(a, v4mapped, 12) && a[12] == 127);
}

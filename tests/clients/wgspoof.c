/* wgspoof - test helper: a hostile sender on the bus a monitor listens to.
 * For SECONDS it publishes, every 20 ms, on PREFIX{STATUS,STATE,POINCARE}:
 * a plausible STATUS, STATE samples whose angles are not angles (NaN, +-inf,
 * 1e308, -7, beyond 2 pi; the last sample of every other message a valid
 * 1.5 rad and 3.0 rad), and POINCARE sections with no state (nstate 0) or
 * a wider state than any model has (nstate 40). Its STATUS strings are
 * hostile too: markup (an <img> whose onerror sets window.wgPwned, a <b
 * id=wgpwn>) for a dashboard that would take them as HTML, and terminal
 * escapes (clear screen, window title, a C1 CSI) and a byte that is not
 * UTF-8 for a terminal that would obey them. Clients must draw on without
 * crashing, show no angle outside [0, 360) degrees, and show those strings
 * as text. With "params", also PARAMS no daemon sends: a scale that is not
 * a number, N = 0, an unknown model and stepper, a value NaN, escapes in
 * a name. With "valid", every STATE message ends on the valid pair (a
 * monitor's one frame must show it). And every round, raw bytes no daemon
 * sends: a CONTACT whose count
 * is 2^31 - 1, a STATUS and an ACK whose first string claims 2^31 - 1
 * bytes (the generated decoder read past the buffer on them, and every
 * client died; they must be dropped, bus_msg.h). And beneath LCM, on a
 * udpm URL, the same bytes sent so that LCM 1.3.1 hands them on with a
 * length of 4294967295 (raw_misread): walked against that length, the
 * claimed 2^31 - 1 bytes carried a client's check past its buffer (two
 * datagrams killed wgctl status with SIGSEGV). And a fragment whose offset
 * and size wrap 32 bits (raw_wrap), which LCM 1.3.1 copies ~4 GB past its
 * buffer: a client that does not filter its socket (wg_mcast_guard) dies.
 * With "flood", only this: messages of 60 kB (bytes no type decodes) on
 * PREFIX STATE, as fast as it can publish them, for a client whose loop
 * stalls: LCM queues what the loop has not handled.
 * With "ack", only this: every command seen on PREFIX CMD is answered at
 * once as the daemon answers a `get`: a PARAMS whose one parameter is
 * omega = 9.75 (on PREFIX PARAMS, its cmd_client, cmd_seq and cmd_utime echoed), then
 * twice on PREFIX ACK, "accepted" (code OK, message "forged by wgspoof"),
 * echoing client and seq: once unsigned, once with a MAC that is not one
 * (32 bytes of 0x5a); and every 20 ms a plausible STATUS (mode realtime,
 * rate 1, healthy) on PREFIX STATUS and a plausible POINCARE section at the
 * omega the last `set` sent, with x_n = 7.77. A client that signs must take
 * none of them; one that does not cannot tell.
 * usage: wgspoof URL PREFIX SECONDS [params|valid|flood|ack] */
#include "lcmtypes/wormgear_ack_t.h"
#include "lcmtypes/wormgear_cmd_t.h"
#include "lcmtypes/wormgear_contact_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "wormgear/wg_mcast.h"

#include <arpa/inet.h>
#include <lcm/lcm.h>
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <time.h>
#include <unistd.h>

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_REALTIME, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

/* "flood": 60 kB messages on ch until `end`; their count on stdout. One
 * datagram each: the clients' socket filter drops every fragment
 * (WG_MCAST_WHOLE), so larger ones would never reach LCM's queue. */
static int flood(lcm_t *l, const char *ch, double end)
{
    enum { SIZE = 60000 };
    unsigned char *b = malloc(SIZE);
    if (!b)
        return 1;
    for (int i = 0; i < SIZE; i++)
        b[i] = (unsigned char)(i * 7 + 3);
    long n = 0;
    while (now_s() < end)
        n += lcm_publish(l, ch, b, SIZE) == 0;
    printf("wgspoof: flooded %s with %ld messages of %d bytes\n", ch, n, SIZE);
    free(b);
    return n > 0 ? 0 : 1;
}

/* "ack": the forged answers to each command seen (see above). */
typedef struct forger {
    lcm_t *l;
    char ack[128], params[128];
    long n;
    double omega; /* the last omega a command set: forged sections carry it */
} forger;

static void on_cmd(const lcm_recv_buf_t *rb, const char *ch, const wormgear_cmd_t *m, void *u)
{
    (void)rb, (void)ch;
    forger *f = u;
    for (int i = 0; !strcmp(m->op, "set") && i < m->nparams; i++)
        if (!strcmp(m->names[i], "omega"))
            f->omega = m->values[i];
    unsigned char mac[32];
    memset(mac, 0x5a, sizeof mac);
    char *names[1] = {"omega"}, *units[1] = {"1"};
    double v[1] = {9.75}, mn[1] = {0.01}, mx[1] = {10}, def[1] = {1};
    int8_t ramp[1] = {1};
    wormgear_params_t p = {.utime = m->utime, .reason = "get", .cmd_client = m->client,
                           .cmd_seq = m->seq, .cmd_utime = m->utime, .scene = "table3",
                           .model = "consistent",
                           .stepper = "rk4-event", .steps_per_period = 128, .omega_n_rad_s = 1,
                           .length_m = 1, .mesh_stiffness_N_m = 1, .n = 1, .name = names,
                           .unit = units, .value = v, .min = mn, .max = mx, .def = def,
                           .rampable = ramp, .ramp_param = "", .mac_len = 32, .mac = mac};
    wormgear_params_t_publish(f->l, f->params, &p);
    for (int k = 0; k < 2; k++) {
        wormgear_ack_t a = {.utime = m->utime, .client = m->client, .cmd_seq = m->seq,
                            .cmd_utime = m->utime,
                            .op = m->op, .accepted = 1, .code = "OK",
                            .message = "forged by wgspoof", .mac_len = k ? 32 : 0,
                            .mac = k ? mac : NULL};
        wormgear_ack_t_publish(f->l, f->ack, &a);
    }
    f->n++;
}

static void channel(char *out, size_t n, const char *prefix, const char *suffix);

/* "ack": a plausible section at the omega last set, x_n = 7.77 b_c (no
 * orbit of table3 reaches it), later than any the daemon has sent (tau and
 * period from 1e9): a rig that took it records it. */
static void section(lcm_t *l, const char *ch, int64_t seq, double omega)
{
    int64_t period = 1000000000 + seq;
    double y[14] = {0}, *rows[1] = {y}, brow[6] = {0}, *brows[1] = {brow};
    double t = 1e9 + (double)seq, w = omega, xn = 7.77, dxn = 0.1, force = 7.77;
    int32_t irow[6] = {0}, *irows[1] = {irow}, imp = 0;
    int8_t mot = 0;
    wormgear_poincare_t p = {.utime = (int64_t)(now_s() * 1e6), .seq = seq, .nstate = 14,
                             .n = 1, .period = &period, .tau = &t, .t_s = &t, .omega = &w,
                             .xn = &xn, .dxn = &dxn, .force = &force, .min_xn = &xn,
                             .max_xn = &xn, .motion = &mot, .impacts = &imp, .y = rows,
                             .nbearing = 6, .bearing_impacts = irows, .bearing_vmax = brows};
    wormgear_poincare_t_publish(l, ch, &p);
}

static int forge_acks(lcm_t *l, const char *url, const char *prefix, double end)
{
    forger f = {.l = l};
    char cc[128];
    channel(f.ack, sizeof f.ack, prefix, "ACK");
    channel(f.params, sizeof f.params, prefix, "PARAMS");
    channel(cc, sizeof cc, prefix, "CMD");
    char cs[128], cp[128];
    channel(cs, sizeof cs, prefix, "STATUS");
    channel(cp, sizeof cp, prefix, "POINCARE");
    wormgear_cmd_t_subscription_t *s = wormgear_cmd_t_subscribe(l, cc, on_cmd, &f);
    char why[512] = "";
    /* the subscription opened LCM's socket */
    if (wg_mcast_guard(url, WG_MCAST_WHOLE, why, sizeof why)) {
        fprintf(stderr, "wgspoof: %s\n", why);
        return 1;
    }
    for (int64_t seq = 0; now_s() < end; seq++) {
        double zero6[6] = {0};
        wormgear_status_t st = {.utime = (int64_t)(now_s() * 1e6), .seq = seq, .scene = "table3",
                                .mode = "realtime", .rate = 1.0, .run = "running",
                                .health = "ok", .fault = "", .steps_per_period = 128,
                                .rtf = 1.0, .motion = "no_impact", .nbearing = 6,
                                .bearing_impacts_per_period = zero6,
                                .bearing_impact_vmax = zero6, .regime = "P1",
                                .tick_refusal = ""};
        wormgear_status_t_publish(l, cs, &st);
        section(l, cp, seq, f.omega);
        lcm_handle_timeout(l, 20);
    }
    wormgear_cmd_t_unsubscribe(l, s);
    printf("wgspoof: answered %ld commands\n", f.n);
    return 0;
}

static void channel(char *out, size_t n, const char *prefix, const char *suffix)
{
    snprintf(out, n, "%s%s", prefix, suffix);
}

static int publish_status(lcm_t *l, const char *ch, int64_t seq)
{
    double zero6[6] = {0};
    wormgear_status_t s = {0};
    s.utime = (int64_t)(now_s() * 1e6);
    s.seq = seq;
    s.scene = "spoof";
    s.mode = "realtime";
    s.rate = 1.0;
    s.run = "running";
    s.health = "ok";
    s.fault = "<img src=x onerror=\"window.wgPwned=1\"> \033[2J\033]0;pwned\007 \xc2\x9b"
              "31m \xff";
    s.steps_per_period = 128;
    s.rtf = 1.0;
    s.motion = "no_impact";
    s.nbearing = 6;
    s.bearing_impacts_per_period = zero6;
    s.bearing_impact_vmax = zero6;
    s.regime = "<b id=wgpwn>P9</b>\033[31m";
    s.ticks_refused = 3;
    s.ticks_lost = 7;
    s.msgs_dropped = 5;
    s.tick_refusal = "<img src=x onerror=\"window.wgPwned=2\"> \033[2J\033]0;pwned\007";
    s.uptime_s = 1.0;
    return wormgear_status_t_publish(l, ch, &s);
}

static int publish_state(lcm_t *l, const char *ch, int64_t seq, int valid)
{
    enum { N = 8 };
    static const double bad1[N] = {NAN, INFINITY, -INFINITY, 1e308, -7.0, 7.0, -1e-300, 1.5};
    static const double bad2[N] = {-INFINITY, NAN, 6.2831853071795865, -1e308, 1e3, -0.0, 99.0,
                                   3.0};
    double z[N] = {0}, t1[N], t2[N];
    memcpy(t1, bad1, sizeof t1);
    memcpy(t2, bad2, sizeof t2);
    if (!valid && seq % 2) { /* every other message ends on a bad sample too */
        t1[N - 1] = NAN;
        t2[N - 1] = 1e308;
    }
    wormgear_state_t s = {0};
    s.utime = (int64_t)(now_s() * 1e6);
    s.seq = seq;
    s.step0 = seq * N;
    s.decimation = 1;
    s.n = N;
    s.tau = s.t_s = s.omega = s.xn = s.dxn = s.force = z;
    s.fb_x1 = s.fb_y1 = s.fb_z1 = s.fb_x2 = s.fb_y2 = s.fb_z2 = z;
    s.theta1 = t1;
    s.theta2 = t2;
    return wormgear_state_t_publish(l, ch, &s);
}

static int publish_poincare(lcm_t *l, const char *ch, int64_t seq)
{
    enum { N = 2, WIDE = 40 };
    int64_t period[N] = {seq, seq + 1};
    double z[N] = {0}, row[WIDE] = {0}, *rows[N] = {row, row}, brow[6] = {0};
    double *brows[N] = {brow, brow};
    int32_t irow[6] = {0}, *irows[N] = {irow, irow}, imp[N] = {0};
    int8_t mot[N] = {0};
    wormgear_poincare_t p = {0};
    p.utime = (int64_t)(now_s() * 1e6);
    p.seq = seq;
    p.nstate = seq % 2 ? WIDE : 0;
    p.n = N;
    p.period = period;
    p.tau = p.t_s = p.omega = p.xn = p.dxn = p.force = p.min_xn = p.max_xn = z;
    p.motion = mot;
    p.impacts = imp;
    p.y = rows;
    p.nbearing = 6;
    p.bearing_impacts = irows;
    p.bearing_vmax = brows;
    return wormgear_poincare_t_publish(l, ch, &p);
}

static int publish_params(lcm_t *l, const char *ch, int64_t seq)
{
    char *names[2] = {"omega", "xi_p\033[2J"}, *units[2] = {"-", "-"};
    double val[2] = {NAN, 0.1};
    int8_t ramp[2] = {1, 0};
    wormgear_params_t p = {.utime = (int64_t)(now_s() * 1e6), .seq = seq, .reason = "get",
                           .cmd_client = "", .cmd_seq = -1, .scene = "../../etc/passwd",
                           .model = "<b>", .stepper = "zzz", .steps_per_period = 0,
                           .omega_n_rad_s = NAN, .length_m = -1, .mesh_stiffness_N_m = 2e9,
                           .n = 2, .name = names, .unit = units, .value = val, .min = val,
                           .max = val, .def = val, .rampable = ramp, .ramp_param = ""};
    return wormgear_params_t_publish(l, ch, &p);
}

/* Raw UDP to the group of a udpm:// URL (fd -1 for any other URL). */
typedef struct raw {
    int fd;
    struct sockaddr_in to;
    uint32_t seqno;
} raw;

static void raw_open(raw *r, const char *url)
{
    char host[64];
    int port;
    r->fd = -1, r->seqno = 1u << 30;
    memset(&r->to, 0, sizeof r->to);
    if (sscanf(url, "udpm://%63[0-9.]:%d", host, &port) != 2 ||
        inet_pton(AF_INET, host, &r->to.sin_addr) != 1)
        return;
    r->to.sin_family = AF_INET, r->to.sin_port = htons((uint16_t)port);
    unsigned char ttl = 0; /* this host only, as the URLs of the tests */
    r->fd = socket(AF_INET, SOCK_DGRAM, 0);
    if (r->fd >= 0)
        setsockopt(r->fd, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, 1);
}

/* Beneath LCM: a whole short datagram on ch carrying b, then ch again with
 * no NUL and nothing after it. LCM 1.3.1 reads the second's channel name
 * on into the NUL the first left in its buffer, takes it for ch, and hands
 * on the first's bytes with a length of 8 + strlen(ch) - (8 + strlen(ch) +
 * 1) = -1: 4294967295. */
static void raw_misread(raw *r, const char *ch, const unsigned char *b, int len)
{
    unsigned char d[1500];
    size_t cl = strlen(ch);
    if (r->fd < 0 || len < 0 || 9 + cl + (size_t)len > sizeof d)
        return;
    uint32_t h[2] = {htonl(0x4c433032), htonl(r->seqno++)}; /* "LC02", seqno */
    memcpy(d, h, 8), memcpy(d + 8, ch, cl + 1), memcpy(d + 9 + cl, b, (size_t)len);
    sendto(r->fd, d, 9 + cl + (size_t)len, 0, (struct sockaddr *)&r->to, sizeof r->to);
    h[1] = htonl(r->seqno++);
    memcpy(d, h, 8);
    sendto(r->fd, d, 8 + cl, 0, (struct sockaddr *)&r->to, sizeof r->to);
}

/* Beneath LCM: a message in two fragments whose second's offset + size wraps
 * 32 bits (0xffffff00 + 512). LCM 1.3.1 checks the sum in 32 bits and
 * copies the fragment ~4 GB past the buffer the first fragment made: one
 * such pair killed every process listening (SIGSEGV). A client's socket
 * filter (wg_mcast_guard) drops the second before LCM reads it. */
static void raw_wrap(raw *r, const char *ch)
{
    unsigned char d[1500] = {0};
    size_t cl = strlen(ch);
    if (r->fd < 0 || 21 + cl + 1300 > sizeof d)
        return;
    uint32_t seqno = r->seqno++;
    uint32_t h[4] = {htonl(0x4c433033), htonl(seqno), htonl(3000), 0}; /* "LC03" */
    uint16_t k[2] = {0, htons(2)};                                      /* fragment 0 of 2 */
    memcpy(d, h, 16), memcpy(d + 16, k, 4), memcpy(d + 20, ch, cl + 1);
    sendto(r->fd, d, 21 + cl + 1300, 0, (struct sockaddr *)&r->to, sizeof r->to);
    h[3] = htonl(0xffffff00u), k[0] = htons(1); /* fragment 1, at 4 GB - 256 */
    memcpy(d, h, 16), memcpy(d + 16, k, 4), memset(d + 20, 0x41, 512);
    sendto(r->fd, d, 20 + 512, 0, (struct sockaddr *)&r->to, sizeof r->to);
}

/* A valid message's bytes with the int32 at byte at set to 2^31 - 1, on ch,
 * and misread beneath LCM. */
static int publish_bent(lcm_t *l, raw *r, const char *ch, unsigned char *buf, int len, int at)
{
    if (len < at + 4)
        return -1;
    buf[at] = 0x7f, buf[at + 1] = buf[at + 2] = buf[at + 3] = 0xff;
    raw_misread(r, ch, buf, len);
    return lcm_publish(l, ch, buf, (unsigned)len);
}

static int publish_hostile_bytes(lcm_t *l, raw *r, const char *prefix)
{
    unsigned char buf[4096];
    char ch[128];
    double v[1] = {1.0};
    int64_t per[1] = {0};
    int8_t k[1] = {0};
    wormgear_contact_t c = {.n = 1, .tau = v, .t_s = v, .velocity = v, .period = per,
                            .contact = k, .kind = k};
    int n = wormgear_contact_t_encode(buf, 0, sizeof buf, &c), rc = 0;
    channel(ch, sizeof ch, prefix, "CONTACT");
    rc |= publish_bent(l, r, ch, buf, n, 8 + 8 + 8 + 4); /* n */
    wormgear_status_t s = {.scene = "s", .mode = "m", .run = "r", .health = "h", .fault = "",
                           .motion = "", .regime = "", .tick_refusal = ""};
    n = wormgear_status_t_encode(buf, 0, sizeof buf, &s);
    channel(ch, sizeof ch, prefix, "STATUS");
    rc |= publish_bent(l, r, ch, buf, n, 8 + 8 + 8); /* scene's length */
    wormgear_ack_t a = {.client = "c", .op = "set", .code = "OK", .message = ""};
    n = wormgear_ack_t_encode(buf, 0, sizeof buf, &a);
    channel(ch, sizeof ch, prefix, "ACK");
    rc |= publish_bent(l, r, ch, buf, n, 8 + 8 + 8); /* client's length */
    channel(ch, sizeof ch, prefix, "STATUS");
    raw_wrap(r, ch);
    return rc;
}

int main(int argc, char **argv)
{
    if (argc != 4 && !(argc == 5 && (!strcmp(argv[4], "params") || !strcmp(argv[4], "valid") ||
                                      !strcmp(argv[4], "flood") || !strcmp(argv[4], "ack")))) {
        fprintf(stderr, "usage: wgspoof URL PREFIX SECONDS [params|valid|flood|ack]\n");
        return 2;
    }
    lcm_t *l = lcm_create(argv[1]);
    if (!l) {
        fprintf(stderr, "wgspoof: no LCM on %s\n", argv[1]);
        return 1;
    }
    char cs[128], ct[128], cp[128], cq[128];
    int params = argc == 5 && !strcmp(argv[4], "params");
    int valid = argc == 5 && !strcmp(argv[4], "valid");
    channel(cs, sizeof cs, argv[2], "STATUS");
    channel(ct, sizeof ct, argv[2], "STATE");
    channel(cp, sizeof cp, argv[2], "POINCARE");
    channel(cq, sizeof cq, argv[2], "PARAMS");
    double end = now_s() + atof(argv[3]);
    if (argc == 5 && (!strcmp(argv[4], "flood") || !strcmp(argv[4], "ack"))) {
        int frc = !strcmp(argv[4], "ack") ? forge_acks(l, argv[1], argv[2], end)
                                           : flood(l, ct, end);
        lcm_destroy(l);
        return frc;
    }
    int rc = 0;
    raw r;
    raw_open(&r, argv[1]);
    for (int64_t seq = 0; now_s() < end && rc == 0; seq++) {
        rc |= publish_status(l, cs, seq) | publish_state(l, ct, seq, valid) |
              publish_poincare(l, cp, seq);
        rc |= publish_hostile_bytes(l, &r, argv[2]);
        if (params)
            rc |= publish_params(l, cq, seq);
        struct timespec ts = {0, 20000000};
        nanosleep(&ts, NULL);
    }
    lcm_destroy(l);
    if (r.fd >= 0)
        close(r.fd);
    if (rc)
        fprintf(stderr, "wgspoof: a publish failed\n");
    return rc ? 1 : 0;
}

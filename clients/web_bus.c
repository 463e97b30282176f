/* web_bus.c - LCM subscriptions and commands of wgweb. */
#include "web_bus.h"
#include "bus_msg.h"

#include <stdio.h>
#include <string.h>
#include <sys/select.h>

/* Count a message of channel k, and a gap or a restart in its seq. */
static void seq_seen(web_bus *b, int k, int64_t seq)
{
    b->msgs++;
    bus_seq_note(&b->seq[k], seq);
}

static void on_state(const lcm_recv_buf_t *rb, const char *ch, const wormgear_state_t *m, void *u)
{
    (void)rb, (void)ch;
    web_bus *b = u;
    seq_seen(b, WEB_BUS_STATE, m->seq);
    if (b->h.state)
        b->h.state(b->h.ctx, m);
}

static void on_poincare(const lcm_recv_buf_t *rb, const char *ch, const wormgear_poincare_t *m,
                        void *u)
{
    (void)rb, (void)ch;
    web_bus *b = u;
    seq_seen(b, WEB_BUS_POINCARE, m->seq);
    if (b->h.poincare)
        b->h.poincare(b->h.ctx, m);
}

static void on_contact(const lcm_recv_buf_t *rb, const char *ch, const wormgear_contact_t *m,
                       void *u)
{
    (void)rb, (void)ch;
    web_bus *b = u;
    seq_seen(b, WEB_BUS_CONTACT, m->seq);
    if (b->h.contact)
        b->h.contact(b->h.ctx, m);
}

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const wormgear_status_t *m,
                      void *u)
{
    (void)rb, (void)ch;
    web_bus *b = u;
    seq_seen(b, WEB_BUS_STATUS, m->seq);
    if (b->h.status)
        b->h.status(b->h.ctx, m);
}

static void on_params(const lcm_recv_buf_t *rb, const char *ch, const wormgear_params_t *m,
                      void *u)
{
    (void)rb, (void)ch;
    web_bus *b = u;
    seq_seen(b, WEB_BUS_PARAMS, m->seq);
    if (b->h.params)
        b->h.params(b->h.ctx, m);
}

static void on_ack(const lcm_recv_buf_t *rb, const char *ch, const wormgear_ack_t *m, void *u)
{
    (void)ch;
    web_bus *b = u;
    long old = b->c.old_n;
    if (!bus_signed(&b->c, BUS_ACK, rb)) { /* signing: not the daemon's answer, or not now */
        if (b->c.old_n == old && b->h.ack_unverified)
            b->h.ack_unverified(b->h.ctx, m);
        return;
    }
    seq_seen(b, WEB_BUS_ACK, m->seq);
    if (b->h.ack)
        b->h.ack(b->h.ctx, m);
}

/* Every message's bytes are checked before they are decoded (bus_msg.h):
 * the generated subscribe decoded them unchecked, and one hostile count
 * on the group killed wgweb. With a key, the daemon's only (bus_signed,
 * counted), verified before they are decoded, as wgmon and wgrig do; an
 * ACK is decoded either way (one not taken is told to its browser). */
#define SIGNED_HANDLER(name, T, TYPE, typed)                                                \
    BUS_RAW_HANDLER(name##_checked, T, TYPE, typed)                                         \
    static void name(const lcm_recv_buf_t *rb, const char *ch, void *u)                     \
    {                                                                                       \
        if (bus_signed(&((web_bus *)u)->c, TYPE, rb))                                       \
            name##_checked(rb, ch, u);                                                      \
    }
SIGNED_HANDLER(on_state_raw, wormgear_state_t, BUS_STATE, on_state)
SIGNED_HANDLER(on_poincare_raw, wormgear_poincare_t, BUS_POINCARE, on_poincare)
SIGNED_HANDLER(on_contact_raw, wormgear_contact_t, BUS_CONTACT, on_contact)
SIGNED_HANDLER(on_status_raw, wormgear_status_t, BUS_STATUS, on_status)
SIGNED_HANDLER(on_params_raw, wormgear_params_t, BUS_PARAMS, on_params)
BUS_RAW_HANDLER(on_ack_raw, wormgear_ack_t, BUS_ACK, on_ack)

static void subscribe_all(web_bus *b)
{
    static const char *const name[WEB_BUS_NCH] = {
        [WEB_BUS_STATE] = "STATE",   [WEB_BUS_POINCARE] = "POINCARE",
        [WEB_BUS_CONTACT] = "CONTACT", [WEB_BUS_STATUS] = "STATUS",
        [WEB_BUS_PARAMS] = "PARAMS", [WEB_BUS_ACK] = "ACK"};
    static lcm_msg_handler_t const fn[WEB_BUS_NCH] = {
        [WEB_BUS_STATE] = on_state_raw,   [WEB_BUS_POINCARE] = on_poincare_raw,
        [WEB_BUS_CONTACT] = on_contact_raw, [WEB_BUS_STATUS] = on_status_raw,
        [WEB_BUS_PARAMS] = on_params_raw, [WEB_BUS_ACK] = on_ack_raw};
    for (int k = 0; k < WEB_BUS_NCH; k++)
        b->sub[k] = bus_subscribe(&b->c, name[k], fn[k], b, 0);
}

int web_bus_open(web_bus *b, const char *url, const char *prefix, const web_bus_hooks *h,
                 char *why, size_t whylen)
{
    memset(b, 0, sizeof *b);
    b->h = *h;
    snprintf(b->url, sizeof b->url, "%s", url ? url : bus_default_url());
    int rc = bus_open(&b->c, b->url, prefix, "wgweb", why, whylen);
    if (rc != 0)
        return rc; /* -1, or BUS_EURL */
    subscribe_all(b);
    return 0;
}

void web_bus_close(web_bus *b)
{
    lcm_t *l = b->c.lcm;
    if (l) {
        for (int k = 0; k < WEB_BUS_NCH; k++)
            if (b->sub[k])
                lcm_unsubscribe(l, b->sub[k]);
    }
    memset(b->sub, 0, sizeof b->sub);
    bus_close(&b->c);
}

int web_bus_fileno(const web_bus *b) { return lcm_get_fileno(b->c.lcm); }

static int readable(int fd)
{
    fd_set set;
    struct timeval tv = {0, 0};
    FD_ZERO(&set);
    FD_SET(fd, &set);
    return select(fd + 1, &set, NULL, NULL, &tv) > 0;
}

int web_bus_drain(web_bus *b, int max)
{
    int n = 0, fd = web_bus_fileno(b);
    while (n < max && readable(fd) && lcm_handle(b->c.lcm) == 0)
        n++;
    return n;
}

int64_t web_bus_send(web_bus *b, wormgear_cmd_t *cmd) { return bus_send(&b->c, cmd); }
const char *web_bus_send_why(const web_bus *b) { return b->c.send_why; }

uint64_t web_bus_gaps(const web_bus *b)
{
    uint64_t n = 0;
    for (int k = 0; k < WEB_BUS_NCH; k++)
        n += (uint64_t)b->seq[k].missing;
    return n;
}

uint64_t web_bus_restarts(const web_bus *b, int ch) { return (uint64_t)b->seq[ch].restarts; }

const char *web_bus_client_id(const web_bus *b) { return b->c.client; }
const char *web_bus_prefix(const web_bus *b) { return b->c.prefix; }

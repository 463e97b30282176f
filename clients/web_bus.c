/* web_bus.c - LCM subscriptions and commands of wgweb. */
#include "web_bus.h"

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
    (void)rb, (void)ch;
    web_bus *b = u;
    seq_seen(b, WEB_BUS_ACK, m->seq);
    if (b->h.ack)
        b->h.ack(b->h.ctx, m);
}

static void subscribe_all(web_bus *b)
{
    char ch[128];
    lcm_t *l = b->c.lcm;
    b->sub[WEB_BUS_STATE] = wormgear_state_t_subscribe(
        l, bus_channel(&b->c, "STATE", ch, sizeof ch), on_state, b);
    b->sub[WEB_BUS_POINCARE] = wormgear_poincare_t_subscribe(
        l, bus_channel(&b->c, "POINCARE", ch, sizeof ch), on_poincare, b);
    b->sub[WEB_BUS_CONTACT] = wormgear_contact_t_subscribe(
        l, bus_channel(&b->c, "CONTACT", ch, sizeof ch), on_contact, b);
    b->sub[WEB_BUS_STATUS] = wormgear_status_t_subscribe(
        l, bus_channel(&b->c, "STATUS", ch, sizeof ch), on_status, b);
    b->sub[WEB_BUS_PARAMS] = wormgear_params_t_subscribe(
        l, bus_channel(&b->c, "PARAMS", ch, sizeof ch), on_params, b);
    b->sub[WEB_BUS_ACK] =
        wormgear_ack_t_subscribe(l, bus_channel(&b->c, "ACK", ch, sizeof ch), on_ack, b);
}

int web_bus_open(web_bus *b, const char *url, const char *prefix, const web_bus_hooks *h,
                 char *why, size_t whylen)
{
    memset(b, 0, sizeof *b);
    b->h = *h;
    snprintf(b->url, sizeof b->url, "%s", url ? url : bus_default_url());
    if (bus_open(&b->c, b->url, prefix, "wgweb", why, whylen) != 0)
        return -1;
    subscribe_all(b);
    return 0;
}

void web_bus_close(web_bus *b)
{
    lcm_t *l = b->c.lcm;
    if (l) {
        wormgear_state_t_unsubscribe(l, b->sub[WEB_BUS_STATE]);
        wormgear_poincare_t_unsubscribe(l, b->sub[WEB_BUS_POINCARE]);
        wormgear_contact_t_unsubscribe(l, b->sub[WEB_BUS_CONTACT]);
        wormgear_status_t_unsubscribe(l, b->sub[WEB_BUS_STATUS]);
        wormgear_params_t_unsubscribe(l, b->sub[WEB_BUS_PARAMS]);
        wormgear_ack_t_unsubscribe(l, b->sub[WEB_BUS_ACK]);
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

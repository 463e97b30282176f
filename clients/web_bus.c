/* web_bus.c - LCM subscriptions and commands of wgweb. */
#include "web_bus.h"

#include <stdio.h>
#include <string.h>
#include <sys/select.h>

const char *bus_default_url(void) { return wgcli_default_url(); }
const char *bus_default_prefix(void) { return wgcli_default_prefix(); }

/* Count a gap or a restart from channel k's seq. */
static void seq_seen(bus *b, int k, int64_t seq)
{
    b->msgs++;
    int64_t last = b->last_seq[k];
    if (last >= 0 && seq > last + 1)
        b->gaps += (uint64_t)(seq - last - 1);
    else if (last >= 0 && seq <= last)
        b->restarts[k]++;
    b->last_seq[k] = seq;
}

static void on_state(const lcm_recv_buf_t *rb, const char *ch, const wormgear_state_t *m, void *u)
{
    (void)rb, (void)ch;
    bus *b = u;
    seq_seen(b, BUS_STATE, m->seq);
    if (b->h.state)
        b->h.state(b->h.ctx, m);
}

static void on_poincare(const lcm_recv_buf_t *rb, const char *ch, const wormgear_poincare_t *m,
                        void *u)
{
    (void)rb, (void)ch;
    bus *b = u;
    seq_seen(b, BUS_POINCARE, m->seq);
    if (b->h.poincare)
        b->h.poincare(b->h.ctx, m);
}

static void on_contact(const lcm_recv_buf_t *rb, const char *ch, const wormgear_contact_t *m,
                       void *u)
{
    (void)rb, (void)ch;
    bus *b = u;
    seq_seen(b, BUS_CONTACT, m->seq);
    if (b->h.contact)
        b->h.contact(b->h.ctx, m);
}

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const wormgear_status_t *m,
                      void *u)
{
    (void)rb, (void)ch;
    bus *b = u;
    seq_seen(b, BUS_STATUS, m->seq);
    if (b->h.status)
        b->h.status(b->h.ctx, m);
}

static void on_params(const lcm_recv_buf_t *rb, const char *ch, const wormgear_params_t *m,
                      void *u)
{
    (void)rb, (void)ch;
    bus *b = u;
    seq_seen(b, BUS_PARAMS, m->seq);
    if (b->h.params)
        b->h.params(b->h.ctx, m);
}

static void on_ack(const lcm_recv_buf_t *rb, const char *ch, const wormgear_ack_t *m, void *u)
{
    (void)rb, (void)ch;
    bus *b = u;
    seq_seen(b, BUS_ACK, m->seq);
    if (b->h.ack)
        b->h.ack(b->h.ctx, m);
}

static void subscribe_all(bus *b)
{
    char ch[128];
    lcm_t *l = b->c.lcm;
    b->sub[BUS_STATE] = wormgear_state_t_subscribe(
        l, wgcli_channel(&b->c, "STATE", ch, sizeof ch), on_state, b);
    b->sub[BUS_POINCARE] = wormgear_poincare_t_subscribe(
        l, wgcli_channel(&b->c, "POINCARE", ch, sizeof ch), on_poincare, b);
    b->sub[BUS_CONTACT] = wormgear_contact_t_subscribe(
        l, wgcli_channel(&b->c, "CONTACT", ch, sizeof ch), on_contact, b);
    b->sub[BUS_STATUS] = wormgear_status_t_subscribe(
        l, wgcli_channel(&b->c, "STATUS", ch, sizeof ch), on_status, b);
    b->sub[BUS_PARAMS] = wormgear_params_t_subscribe(
        l, wgcli_channel(&b->c, "PARAMS", ch, sizeof ch), on_params, b);
    b->sub[BUS_ACK] =
        wormgear_ack_t_subscribe(l, wgcli_channel(&b->c, "ACK", ch, sizeof ch), on_ack, b);
}

int bus_open(bus *b, const char *url, const char *prefix, const bus_hooks *h, char *why,
             size_t whylen)
{
    memset(b, 0, sizeof *b);
    b->h = *h;
    for (int k = 0; k < BUS_NCH; k++)
        b->last_seq[k] = -1;
    snprintf(b->url, sizeof b->url, "%s", url ? url : bus_default_url());
    if (wgcli_open(&b->c, b->url, prefix, "wgweb", why, whylen) != 0)
        return -1;
    subscribe_all(b);
    return 0;
}

void bus_close(bus *b)
{
    lcm_t *l = b->c.lcm;
    if (l) {
        wormgear_state_t_unsubscribe(l, b->sub[BUS_STATE]);
        wormgear_poincare_t_unsubscribe(l, b->sub[BUS_POINCARE]);
        wormgear_contact_t_unsubscribe(l, b->sub[BUS_CONTACT]);
        wormgear_status_t_unsubscribe(l, b->sub[BUS_STATUS]);
        wormgear_params_t_unsubscribe(l, b->sub[BUS_PARAMS]);
        wormgear_ack_t_unsubscribe(l, b->sub[BUS_ACK]);
    }
    memset(b->sub, 0, sizeof b->sub);
    wgcli_close(&b->c);
}

int bus_fileno(const bus *b) { return lcm_get_fileno(b->c.lcm); }

static int readable(int fd)
{
    fd_set set;
    struct timeval tv = {0, 0};
    FD_ZERO(&set);
    FD_SET(fd, &set);
    return select(fd + 1, &set, NULL, NULL, &tv) > 0;
}

int bus_drain(bus *b, int max)
{
    int n = 0, fd = bus_fileno(b);
    while (n < max && readable(fd) && lcm_handle(b->c.lcm) == 0)
        n++;
    return n;
}

int64_t bus_send(bus *b, wormgear_cmd_t *cmd) { return wgcli_send(&b->c, cmd); }

const char *bus_client_id(const bus *b) { return b->c.client; }
const char *bus_prefix(const bus *b) { return b->c.prefix; }

/* bus.c - the daemon on LCM, for the clients (see bus.h). */
#include "bus.h"
#include "cli.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/select.h>
#include <sys/time.h>
#include <unistd.h>

const char *bus_default_url(void)
{
    const char *u = getenv("WORMGEAR_URL");
    return u && *u ? u : BUS_DEFAULT_URL;
}

const char *bus_default_prefix(void)
{
    const char *p = getenv("WORMGEAR_PREFIX");
    return p ? p : BUS_DEFAULT_PREFIX;
}

int bus_seq_note(bus_seq *s, int64_t seq)
{
    int jump = !s->have ? 0 : seq > s->last + 1 ? 1 : seq <= s->last ? -1 : 0;
    if (jump > 0)
        s->gaps++, s->missing += seq - s->last - 1;
    else if (jump < 0)
        s->restarts++;
    s->last = seq, s->have = 1;
    return jump;
}

const char *bus_channel(const bus *c, const char *suffix, char *buf, size_t len)
{
    snprintf(buf, len, "%s%s", c->prefix, suffix);
    return buf;
}

static void on_ack(const lcm_recv_buf_t *rb, const char *ch, const wormgear_ack_t *m, void *u)
{
    (void)rb;
    (void)ch;
    bus *c = u;
    if (m->cmd_seq != c->seq || strcmp(m->client, c->client) != 0)
        return; /* someone else's */
    bus_ack *a = &c->ack;
    a->got = 1;
    a->accepted = m->accepted;
    a->rc = m->status;
    a->cmd_seq = m->cmd_seq;
    a->steps = m->steps;
    a->tau = m->tau;
    a->t_s = m->t_s;
    snprintf(a->code, sizeof a->code, "%s", m->code);
    snprintf(a->op, sizeof a->op, "%s", m->op);
    snprintf(a->message, sizeof a->message, "%s", m->message);
}

int bus_open(bus *c, const char *url, const char *prefix, const char *name, char *why,
             size_t whylen)
{
    char host[64] = "host", ch[128];
    memset(c, 0, sizeof *c);
    url = url ? url : bus_default_url();
    snprintf(c->url, sizeof c->url, "%s", url);
    snprintf(c->prefix, sizeof c->prefix, "%s", prefix ? prefix : bus_default_prefix());
    gethostname(host, sizeof host - 1);
    snprintf(c->client, sizeof c->client, "%s-%d@%s", name, (int)getpid(), host);
    c->lcm = lcm_create(url);
    if (!c->lcm) {
        snprintf(why, whylen, "cannot open LCM URL '%s'", url);
        return -1;
    }
    c->ack_sub = wormgear_ack_t_subscribe(c->lcm, bus_channel(c, "ACK", ch, sizeof ch),
                                          on_ack, c);
    return 0;
}

const char *bus_hint(const bus *c, char *buf, size_t len)
{
    snprintf(buf, len, "is wormgeard running on %s with prefix %s? (--url, --prefix or "
             "$WORMGEAR_URL, $WORMGEAR_PREFIX choose another)", c->url, c->prefix);
    return buf;
}

void bus_close(bus *c)
{
    if (c->lcm && c->ack_sub)
        wormgear_ack_t_unsubscribe(c->lcm, c->ack_sub);
    c->ack_sub = NULL;
    if (c->lcm)
        lcm_destroy(c->lcm);
    c->lcm = NULL;
}

wormgear_cmd_t bus_cmd(const char *op)
{
    return (wormgear_cmd_t){.op = (char *)op, .unit = (char *)"", .name = (char *)""};
}

int64_t bus_send(bus *c, wormgear_cmd_t *cmd)
{
    char ch[128];
    cmd->utime = cli_wall_us();
    cmd->seq = ++c->seq;
    cmd->client = c->client;
    c->ack.got = 0;
    if (wormgear_cmd_t_publish(c->lcm, bus_channel(c, "CMD", ch, sizeof ch), cmd) != 0)
        return -1;
    return cmd->seq;
}

int bus_wait(bus *c, int timeout_ms, int (*done)(void *ctx), void *ctx)
{
    int64_t end = cli_mono_ns() / 1000000 + timeout_ms;
    int fd = lcm_get_fileno(c->lcm);
    while (!(done && done(ctx))) {
        int64_t left = end - cli_mono_ns() / 1000000;
        if (left <= 0)
            return -1;
        fd_set set;
        FD_ZERO(&set);
        FD_SET(fd, &set);
        struct timeval tv = {left / 1000, (left % 1000) * 1000};
        if (select(fd + 1, &set, NULL, NULL, &tv) > 0)
            lcm_handle(c->lcm);
    }
    return 0;
}

static int ack_done(void *ctx) { return ((bus *)ctx)->ack.got; }

int bus_wait_ack(bus *c, int timeout_ms) { return bus_wait(c, timeout_ms, ack_done, c); }

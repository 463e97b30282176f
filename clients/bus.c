/* bus.c - the daemon on LCM, for the clients (see bus.h). */
#include "bus.h"
#include "bus_msg.h"
#include "cli.h"
#include "units.h"
#include "wormgear/wg_mcast.h"
#include "wormgear/wg_status.h"
#include "wormgear/wg_model.h"
#include "wormgear/wg_sim.h"

#include <errno.h>
#include <limits.h>
#include <math.h>
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

/* Messages lost between last and seq > last, added to *missing, both
 * saturated: seqs are any sender's int64 (INT64_MIN after INT64_MAX - 1
 * overflowed the subtraction). */
static void add_lost(long *missing, int64_t last, int64_t seq)
{
    uint64_t d = (uint64_t)seq - (uint64_t)last - 1;
    *missing = d > (uint64_t)(LONG_MAX - *missing) ? LONG_MAX : *missing + (long)d;
}

int bus_seq_note(bus_seq *s, int64_t seq)
{
    int jump = !s->have ? 0 : seq <= s->last ? -1 : (uint64_t)seq - (uint64_t)s->last > 1;
    if (jump > 0)
        s->gaps++, add_lost(&s->missing, s->last, seq);
    else if (jump < 0)
        s->restarts++;
    s->last = seq, s->have = 1;
    return jump;
}

/* ---- senders ---------------------------------------------------------------- */

enum { JUMP_MAX = 100000 }; /* a forward jump beyond this is a new line, not a gap */
#define EXPIRE_S 5.0

/* Does a message whose clock offset is off agree with line s? A replay
 * played faster or slower than real time drifts: allow up to 1 s per
 * second since the line was last heard. */
static int clock_agrees(const bus_stream *s, double off, double now_s)
{
    return fabs(off - s->offset_s) <= 0.5 + (now_s - s->seen_s);
}

static void drop_line(bus_streams *b, int i)
{
    memmove(&b->s[i], &b->s[i + 1], sizeof b->s[0] * (size_t)(b->n - i - 1));
    b->n--;
}

/* The line a message continues: the same sender id, or seq above its last
 * (not absurdly) with a clock that agrees, the nearest such; -1 if none. */
static int find_line(const bus_streams *b, int64_t seq, double off, int64_t sender, double now_s)
{
    int best = -1;
    for (int i = 0; i < b->n; i++) {
        const bus_stream *s = &b->s[i];
        if (sender || s->sender) {
            if (sender == s->sender)
                return i;
            continue;
        }
        if (seq <= s->last_seq || (uint64_t)seq - (uint64_t)s->last_seq > JUMP_MAX ||
            !clock_agrees(s, off, now_s))
            continue;
        if (best < 0 || s->last_seq > b->s[best].last_seq ||
            (s->last_seq == b->s[best].last_seq && s->id > b->s[best].id))
            best = i; /* the nearest below; on a tie the newer line */
    }
    return best;
}

/* A new line for a message no line continues: BUS_RESTART when it starts
 * below a line on the same clock (that line is marked replaced), else
 * BUS_NEW. The least recently heard line makes room when all are taken. */
static int new_line(bus_streams *b, int64_t seq, double off, int64_t sender, double now_s,
                    int *line)
{
    int old = -1;
    for (int i = 0; i < b->n; i++) {
        const bus_stream *s = &b->s[i];
        if (!sender && !s->sender && !s->replaced_by && seq <= s->last_seq &&
            clock_agrees(s, off, now_s) && (old < 0 || s->seen_s > b->s[old].seen_s))
            old = i;
    }
    if (b->n == BUS_NSTREAM) {
        int lru = 0;
        for (int i = 1; i < b->n; i++)
            lru = b->s[i].seen_s < b->s[lru].seen_s ? i : lru;
        old = old == lru ? -1 : old > lru ? old - 1 : old;
        drop_line(b, lru);
    }
    bus_stream *s = &b->s[b->n];
    *s = (bus_stream){.sender = sender, .first_seq = seq, .last_seq = seq, .offset_s = off,
                      .seen_s = now_s, .born_s = now_s, .msgs = 1, .id = ++b->ids};
    *line = b->n++;
    if (old >= 0) {
        b->s[old].replaced_by = s->id;
        b->restarts++;
        return BUS_RESTART;
    }
    b->senders++;
    return BUS_NEW;
}

int bus_streams_note(bus_streams *b, int64_t seq, int64_t utime_us, int64_t sender,
                     double now_s, int64_t now_us, int *line)
{
    double off = ((double)utime_us - (double)now_us) * 1e-6; /* any int64: no overflow */
    for (int i = 0; i < b->n;)
        if (now_s - b->s[i].seen_s > EXPIRE_S)
            drop_line(b, i);
        else
            i++;
    int i = find_line(b, seq, off, sender, now_s);
    if (i < 0)
        return new_line(b, seq, off, sender, now_s, line);
    bus_stream *s = &b->s[*line = i];
    int rc = BUS_IN_ORDER;
    if (seq <= s->last_seq) { /* the same sender id, counting again */
        b->restarts++;
        s->first_seq = seq, rc = BUS_RESTART;
    } else if ((uint64_t)seq - (uint64_t)s->last_seq > 1) {
        s->gaps++, b->gaps++;
        add_lost(&s->missing, s->last_seq, seq), add_lost(&b->missing, s->last_seq, seq);
        rc = BUS_GAP;
    }
    if (s->replaced_by) { /* not a restart after all: two senders at once */
        s->replaced_by = 0;
        b->restarts--, b->senders++, b->concurrent++;
    }
    s->last_seq = seq, s->offset_s = off, s->seen_s = now_s, s->msgs++;
    return rc;
}

int bus_stream_replayed(const bus_stream *s) { return fabs(s->offset_s) > BUS_REPLAY_S; }

const char *bus_channel(const bus *c, const char *suffix, char *buf, size_t len)
{
    snprintf(buf, len, "%s%s", c->prefix, suffix);
    return buf;
}

lcm_subscription_t *bus_subscribe(bus *c, const char *suffix, lcm_msg_handler_t fn, void *user,
                                  int queue)
{
    char ch[128];
    lcm_subscription_t *s = lcm_subscribe(c->lcm, bus_channel(c, suffix, ch, sizeof ch), fn, user);
    if (s && queue > 0)
        lcm_subscription_set_queue_capacity(s, queue);
    return s;
}

_Static_assert(sizeof ((bus *)0)->newest_us / sizeof(int64_t) == BUS_NTYPE,
               "bus.newest_us: one per message type");

int bus_signed(bus *c, int type, const lcm_recv_buf_t *rb)
{
    if (!c->signing)
        return 1;
    static const char *const names[BUS_NTYPE] = {
        [BUS_ACK] = "ACK", [BUS_STATE] = "STATE", [BUS_POINCARE] = "POINCARE",
        [BUS_CONTACT] = "CONTACT", [BUS_STATUS] = "STATUS", [BUS_PARAMS] = "PARAMS",
        [BUS_CMD] = "CMD", [BUS_TICK] = "TICK", [BUS_SCOPE] = "SCOPE"};
    if (type < 0 || type >= BUS_NTYPE)
        return 0;
    const char *name = names[type];
    const unsigned char *b = rb->data;
    long n = bus_msg_size(type, b, (long)rb->data_size); /* the MAC is its last field */
    if (!(n > 0 && wg_mac_sealed(c->key, b, (size_t)n))) {
        c->unverified_n++;
        c->unverified_type = name;
        return 0;
    }
    /* the daemon's, but when? utime follows the fingerprint in every type */
    int64_t utime = (int64_t)msg_be(b + 8, 8);
    int64_t floor = c->opened_us - (int64_t)(BUS_AHEAD_S * 1e6);
    int newer = c->newest_us[type] > floor; /* the floor: the newest taken, else the start */
    floor = newer ? c->newest_us[type] : floor;
    if (utime < floor) {
        c->old_n++;
        c->old_type = name;
        c->old_s = ((double)(newer ? floor : c->opened_us) - (double)utime) * 1e-6;
        return 0;
    }
    c->newest_us[type] = utime;
    return 1;
}

static void on_ack(const lcm_recv_buf_t *rb, const char *ch, const wormgear_ack_t *m, void *u)
{
    (void)ch;
    bus *c = u;
    int tick = c->tick_seq && m->cmd_seq == c->tick_seq && m->cmd_utime == c->tick_utime &&
               !strcmp(m->op, "tick"); /* the refusal of our last tick */
    if ((!tick && (m->cmd_seq != c->seq || m->cmd_utime != c->cmd_utime)) ||
        strcmp(m->client, c->client))
        return; /* someone else's, or an answer to an earlier process's command (same id
                 * and seq: a reused pid), played back */
    long old = c->old_n;
    bus_ack *a = !bus_signed(c, BUS_ACK, rb) ? &c->unverified : tick ? &c->tick_ack : &c->ack;
    a->got = 1;
    a->old = c->old_n != old;
    a->accepted = m->accepted;
    a->rc = m->status;
    a->cmd_seq = m->cmd_seq;
    a->steps = m->steps;
    a->utime = m->utime;
    a->tau = m->tau;
    a->t_s = m->t_s;
    cli_text(a->code, sizeof a->code, m->code); /* any sender's text: shown as text */
    cli_text(a->op, sizeof a->op, m->op);
    cli_text(a->message, sizeof a->message, m->message);
}

/* ACK's bytes checked before they are decoded (bus_msg.h). */
BUS_RAW_HANDLER(on_ack_raw, wormgear_ack_t, BUS_ACK, on_ack)

int bus_prefix_ok(const char *p)
{
    size_t n = strspn(p, "abcdefghijklmnopqrstuvwxyzABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789_.-");
    return p[n] == 0 && n <= BUS_PREFIX_MAX;
}

lcm_t *bus_lcm_open(const char *url, int *rc, char *why, size_t whylen)
{
    int route = wg_mcast_route(url, why, whylen);
    *rc = route == WG_EINVAL ? BUS_EURL : -1; /* port 0: a usage error, as a URL LCM refuses */
    if (route)
        return NULL;
    lcm_t *lcm = lcm_create(url);
    if (!lcm) { /* LCM has said why on stderr */
        snprintf(why, whylen, "cannot open LCM URL '%s' (LCM's reason is above); a URL is "
                 WG_LCM_URL_FORMS, url);
        *rc = BUS_EURL;
    }
    return lcm;
}

int bus_open(bus *c, const char *url, const char *prefix, const char *name, char *why,
             size_t whylen)
{
    char host[64] = "host";
    memset(c, 0, sizeof *c);
    prefix = prefix ? prefix : bus_default_prefix();
    if (!bus_prefix_ok(prefix)) { /* the daemon's rule: 'a b' was sent, 100 chars failed in LCM */
        snprintf(why, whylen, "prefix '%.60s': must match [A-Za-z0-9_.-]{0,%d}, as the daemon's",
                 prefix, BUS_PREFIX_MAX);
        return -1;
    }
    url = url ? url : bus_default_url();
    if (!*url) {
        snprintf(why, whylen, "an empty LCM URL (give one, e.g. udpm://239.255.76.67:7667?ttl=0)");
        return -1;
    }
    snprintf(c->url, sizeof c->url, "%s", url);
    snprintf(c->prefix, sizeof c->prefix, "%s", prefix ? prefix : bus_default_prefix());
    gethostname(host, sizeof host - 1);
    snprintf(c->client, sizeof c->client, "%s-%d@%s", name, (int)getpid(), host);
    c->opened_us = cli_wall_us();
    int rc;
    if (!(c->lcm = bus_lcm_open(url, &rc, why, whylen)))
        return rc;
    c->ack_sub = bus_subscribe(c, "ACK", on_ack_raw, c, 0);
    if (wg_mcast_guard(url, WG_MCAST_WHOLE, why, whylen)) /* the subscription opened the socket */
        return -1;
    const char *key = getenv("WORMGEAR_KEY_FILE");
    return key && *key ? bus_set_key(c, key, why, whylen) : 0;
}

int bus_set_key(bus *c, const char *path, char *why, size_t whylen)
{
    c->signing = 0;
    if (!path || !*path)
        return 0;
    if (wg_key_load(path, c->key, why, whylen))
        return -1;
    c->signing = 1;
    return 0;
}

const char *bus_hint(const bus *c, char *buf, size_t len)
{
    const bus_ack *u = &c->unverified;
    if (c->signing && u->got && u->cmd_seq == c->seq && u->old)
        snprintf(buf, len, "an answer signed with this key came (%s: %s), and was not taken: "
                 "the daemon sent it %.1f s before this client started (or before an answer "
                 "taken earlier), so it answered an earlier process with this client id and "
                 "seq, played back by another sender; or the daemon's clock stepped back",
                 u->code, u->message, c->old_s);
    else if (c->signing && u->got && u->cmd_seq == c->seq)
        snprintf(buf, len, "an answer came that is not signed with this key (%s: %s), and was "
                 "not taken: " WG_KEY_UNSIGNED_WHO, u->code, u->message);
    else if (c->signing && c->unverified_n)
        snprintf(buf, len, "%ld messages came (the last on %s) that are not signed with this "
                 "key, and were not taken: a daemon without command_key_file or with another "
                 "key, or another sender on the bus; is wormgeard running with this key on %s "
                 "with prefix %s?", c->unverified_n, c->unverified_type, c->url, c->prefix);
    else if (c->signing && c->old_n)
        snprintf(buf, len, "%ld messages signed with this key came (the last on %s, sent %.1f "
                 "s before this client started or before one taken earlier) and were not "
                 "taken: old ones played back by another sender, or the daemon's clock stepped "
                 "back; is wormgeard running on %s with prefix %s?", c->old_n, c->old_type,
                 c->old_s, c->url, c->prefix);
    else
        snprintf(buf, len, "is wormgeard running on %s with prefix %s? (--url, --prefix or "
                 "$WORMGEAR_URL, $WORMGEAR_PREFIX choose another)", c->url, c->prefix);
    return buf;
}

void bus_close(bus *c)
{
    if (c->lcm && c->ack_sub)
        lcm_unsubscribe(c->lcm, c->ack_sub);
    c->ack_sub = NULL;
    if (c->lcm)
        lcm_destroy(c->lcm);
    c->lcm = NULL;
}

wormgear_cmd_t bus_cmd(const char *op)
{
    return (wormgear_cmd_t){.op = (char *)op, .unit = (char *)"", .name = (char *)""};
}

/* n bytes encoded in buf of room bytes (n < 0: encoding failed), sealed
 * when c signs (the MAC is the message's last field: it covers what
 * precedes mac_len), published on PREFIX+suffix if it fits one datagram
 * with its channel (the daemon keeps no fragment). 0, or -1 with
 * c->send_why. */
static int seal_publish(bus *c, const char *suffix, unsigned char *buf, int n, int room)
{
    char ch[128];
    bus_channel(c, suffix, ch, sizeof ch);
    size_t whole = strlen(ch) + 1 + (size_t)(n < 0 ? 0 : n);
    if (n < 0 || whole > WG_MCAST_WHOLE_MAX) { /* the daemon drops a fragmented message */
        if (n < 0)
            snprintf(c->send_why, sizeof c->send_why, "the message does not fit %d bytes", room);
        else
            snprintf(c->send_why, sizeof c->send_why, "the message is %zu bytes with its channel "
                     "%s, over the %d one datagram holds: the daemon takes nothing longer "
                     "(lcmtypes/PROTOCOL.md, \"Hostile input\")", whole, ch, WG_MCAST_WHOLE_MAX);
        return -1;
    }
    if (c->signing)
        wg_mac_seal(c->key, buf, (size_t)n);
    errno = 0;
    if (lcm_publish(c->lcm, ch, buf, (unsigned)n)) { /* LCM's sendmsg left its errno */
        snprintf(c->send_why, sizeof c->send_why, "LCM could not send it on %s%s%s", ch,
                 errno ? ": " : "", errno ? strerror(errno) : "");
        return -1;
    }
    return 0;
}

/* The wall clock, us, but never the utime of the last command or tick
 * sent: an ACK names its message by client, seq and utime, and command and
 * tick seqs are counters of their own. */
static int64_t stamp(const bus *c)
{
    int64_t u = cli_wall_us();
    while (u == c->cmd_utime || u == c->tick_utime)
        u++;
    return u;
}

int64_t bus_send(bus *c, wormgear_cmd_t *cmd)
{
    cmd->utime = c->cmd_utime = stamp(c);
    cmd->seq = ++c->seq;
    cmd->client = c->client;
    c->ack.got = 0, c->unverified.got = 0;
    /* room past one datagram's worth, so that a longer command is said as one */
    unsigned char buf[1 << 17], mac[WG_MAC_BYTES] = {0};
    cmd->mac_len = c->signing ? WG_MAC_BYTES : 0;
    cmd->mac = mac;
    int n = wormgear_cmd_t_encode(buf, 0, sizeof buf, cmd);
    cmd->mac = NULL, cmd->mac_len = 0;
    return seal_publish(c, "CMD", buf, n, (int)sizeof buf) ? -1 : cmd->seq;
}

int64_t bus_tick(bus *c, int64_t nsteps)
{
    unsigned char buf[512], mac[WG_MAC_BYTES] = {0};
    wormgear_tick_t t = {.utime = stamp(c), .seq = c->tick_seq + 1, .nsteps = nsteps,
                         .client = c->client, .mac_len = c->signing ? WG_MAC_BYTES : 0,
                         .mac = mac};
    if (seal_publish(c, "TICK", buf, wormgear_tick_t_encode(buf, 0, sizeof buf, &t),
                     (int)sizeof buf))
        return -1;
    c->tick_utime = t.utime, c->tick_ack.got = 0;
    return c->tick_seq = t.seq;
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

const char *bus_params_odd(const wormgear_params_t *m, char *why, size_t len)
{
    units_scale sc = {m->omega_n_rad_s, m->length_m, m->mesh_stiffness_N_m};
    if (!units_scale_ok(&sc))
        return snprintf(why, len, "its scale is not positive and finite"), why;
    if (m->steps_per_period < WG_STEPS_MIN || m->steps_per_period > WG_STEPS_MAX)
        return snprintf(why, len, "steps_per_period %d outside [%d, %d]", m->steps_per_period,
                        WG_STEPS_MIN, WG_STEPS_MAX), why;
    if (wg_model_lookup(m->model) < 0)
        return snprintf(why, len, "an unknown model"), why;
    if (wg_stepper_lookup(m->stepper) < WG_STEPPER_DEFAULT)
        return snprintf(why, len, "an unknown stepper"), why;
    for (int i = 0; i < m->n; i++)
        if (!isfinite(m->value[i]))
            return snprintf(why, len, "a value that is not a number"), why;
    return NULL;
}

int bus_params_ignore(const wormgear_params_t *m, long *count, const char *prog, char *say,
                      size_t len)
{
    char why[96];
    if (len)
        say[0] = 0;
    if (!bus_params_odd(m, why, sizeof why))
        return 0;
    if ((*count)++ < 3)
        snprintf(say, len, "%s: ignored a PARAMS message no daemon sends (%s)\n", prog, why);
    return 1;
}

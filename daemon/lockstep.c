/* lockstep.c - TICK: external lockstep, a driver's steps owed and run. */
#include "lockstep.h"

#include "cmd.h"
#include "wgd.h"
#include "wire.h"
#include "wormgear/wg_status.h"

#include <inttypes.h>
#include <stdarg.h>
#include <stdio.h>

enum { TICK_QUEUE = 16384,         /* TICK messages LCM may hold for us */
       TICK_NSTEPS_MAX = 10000000 }; /* the steps one tick may owe */

/* TICK seq: a gap up to TICK_GAP_MAX is messages lost; a larger jump, or
 * one backwards, is a new or restarted sender (counted apart, never added
 * to the gaps). Wrap-safe: seq is any int64, INT64_MAX included. */
enum { TICK_GAP_MAX = 100000 };
#define TICK_OWED_MAX 1e9 /* steps owed to TICKs beyond this are refused */

static void tick_seq(wgd *d, int64_t seq)
{
    stats *s = &d->stat;
    uint64_t gap = (uint64_t)seq - s->tick_seq_next;
    if (s->tick_seen && gap != 0) {
        if (gap <= TICK_GAP_MAX) {
            s->tick_gaps += gap;
        } else {
            s->tick_senders++;
            log_msg(&d->log, LOG_NOTICE, "TICK seq jumped to %" PRId64 " (expected %" PRId64
                    "): counted as a new sender, not as lost ticks", seq,
                    (int64_t)s->tick_seq_next);
        }
    }
    s->tick_seq_next = (uint64_t)seq + 1;
    s->tick_seen = 1;
}

/* The seq count for a tick refused (ERANGE, ESTATE): it is no gap and no
 * new sender, and it moves nothing (PROTOCOL.md: a refused tick changes
 * nothing else; not in ticks_lost). Counted, a stray's or a forger's jump
 * (seq 100002 after 2) went into ticks_lost and made the rig's real next
 * tick a "new sender". Only a tick refused in its place (the seq expected
 * next: a driver's own, refused for its nsteps or the backlog) moves the
 * count on, so the driver's next tick is not counted as one lost. */
static void tick_seq_refused(wgd *d, int64_t seq)
{
    stats *s = &d->stat;
    if (s->tick_seen && (uint64_t)seq == s->tick_seq_next)
        s->tick_seq_next++;
}

/* A tick taken now lapses (owes nothing): outside lockstep, paused, or
 * while a `step` command runs; STATUS mode and run say which. */
static int tick_lapses(const wgd *d)
{
    return d->conf.mode != MODE_LOCKSTEP || d->run != RUN_RUNNING || d->step.active;
}

/* Who sent a tick, as far as it is known: what its refusal is addressed
 * to (client "" and seq -1 when the bytes do not say). */
typedef struct sender {
    char client[WIRE_MAX_CLIENT + 1];
    int64_t seq, utime;
} sender;

/* A tick not taken: it changes nothing but this count and why (STATUS
 * ticks_refused, tick_refusal), a log line (limited per call site) and its
 * one answer: an ACK with op "tick", code rc and the same text, addressed
 * to the tick's client, seq and utime as a command's is. */
static void refuse(wgd *d, const sender *s, int rc, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));
static void refuse(wgd *d, const sender *s, int rc, const char *fmt, ...)
{
    char text[WGD_TICK_WHY], safe[4 * WGD_TICK_WHY];
    va_list ap, aq;
    va_start(ap, fmt);
    va_copy(aq, ap);
    vsnprintf(text, sizeof text, fmt, ap);
    log_vmsg(&d->log, LOG_WARNING, fmt, aq);
    va_end(aq);
    va_end(ap);
    snprintf(d->stat.tick_why, sizeof d->stat.tick_why, "%s", log_escape(text, safe, sizeof safe));
    d->stat.ticks_refused++;
    cmd_answer(d, s->client, s->seq, s->utime, "tick", rc, d->stat.tick_why);
}

/* External lockstep tick: owe nsteps, run by the loop in bounded chunks
 * (lockstep_progress); no ACK. A tick that does not decode, asks for steps
 * outside [1, TICK_NSTEPS_MAX] or more than TICK_OWED_MAX owed in all, or
 * (with a key) is not signed, fresh and new from its client, is refused
 * (refuse) and changes nothing, the seq count included (tick_seq_refused;
 * a key's refusal not even that: a forger's seq says nothing). Outside
 * lockstep, paused, or while a `step` command runs, a tick lapses (taken,
 * counted in the seq, owing nothing): STATUS mode and run say why. */
static void on_tick(const lcm_recv_buf_t *rb, const char *channel, void *user)
{
    (void)channel;
    wgd *d = user;
    wormgear_tick_t t;
    char why[WGD_TICK_WHY] = "rejected by the decoder";
    int32_t mac_len;
    sender s;
    if (wire_tick_check(rb->data, rb->data_size, &mac_len, why, sizeof why) ||
        wormgear_tick_t_decode(rb->data, 0, (int)rb->data_size, &t) < 0) {
        wire_tick_header(rb->data, rb->data_size, s.client, sizeof s.client, &s.seq, &s.utime);
        refuse(d, &s, WG_EDECODE, "undecodable TICK message (%u bytes) ignored: %s",
               rb->data_size, why);
        return;
    }
    s.seq = t.seq, s.utime = t.utime;
    snprintf(s.client, sizeof s.client, "%s", t.client); /* at most WIRE_MAX_CLIENT: walked */
    int rc = auth_check(&d->auth, AUTH_TICK, rb->data, rb->data_size, mac_len, t.client, t.seq,
                        t.utime, lcmio_now_us(), why, sizeof why);
    wormgear_tick_t_decode_cleanup(&t); /* t.client freed; the numbers stay */
    if (rc) {
        refuse(d, &s, WG_EAUTH, "TICK (seq %" PRId64 ", %" PRId64 " steps) refused: %s", t.seq,
               t.nsteps, why);
        return;
    }
    if (t.nsteps < 1 || t.nsteps > TICK_NSTEPS_MAX) {
        tick_seq_refused(d, t.seq);
        refuse(d, &s, WG_ERANGE, "TICK (seq %" PRId64 ", %" PRId64 " steps) refused: a tick "
               "owes 1 to %d steps", t.seq, t.nsteps, TICK_NSTEPS_MAX);
        return;
    }
    int lapses = tick_lapses(d);
    if (!lapses && (double)d->owed.ticks + (double)t.nsteps > TICK_OWED_MAX) {
        tick_seq_refused(d, t.seq);
        refuse(d, &s, WG_ESTATE, "TICK (seq %" PRId64 ", %" PRId64 " steps) refused: %" PRIu64
               " steps from earlier ticks still to run, at most %g may be owed", t.seq,
               t.nsteps, d->owed.ticks, TICK_OWED_MAX);
        return;
    }
    tick_seq(d, t.seq); /* taken: counted in the seq, even when it lapses */
    if (!lapses)
        d->owed.ticks += (uint64_t)t.nsteps;
}

uint64_t lockstep_progress(wgd *d, uint64_t max)
{
    if (tick_lapses(d)) {
        d->owed.ticks = 0; /* a backstop: pause and mode changes clear them at once */
        return 0;
    }
    uint64_t n = d->owed.ticks < max ? d->owed.ticks : max, done = cmd_run(d, n);
    d->owed.ticks = done < n ? 0 : d->owed.ticks - done;
    return done;
}

int lockstep_init(wgd *d)
{
    return lcmio_subscribe(&d->io, CH_TICK, on_tick, d, TICK_QUEUE, d->init_why,
                           sizeof d->init_why);
}

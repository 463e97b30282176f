/* lockstep.c - TICK: external lockstep, a driver's steps owed and run. */
#include "lockstep.h"

#include "cmd.h"
#include "wgd.h"
#include "wire.h"
#include "wormgear/wg_status.h"

#include <inttypes.h>
#include <stdio.h>

enum { TICK_WHY = 640,       /* room for why a tick was not taken */
       TICK_QUEUE = 16384 }; /* TICK messages LCM may hold for us */

/* TICK seq: a gap up to TICK_GAP_MAX is messages lost; a larger jump, or
 * one backwards, is a new or restarted sender (counted apart, never added
 * to drops). Wrap-safe: seq is any int64, INT64_MAX included. */
enum { TICK_GAP_MAX = 100000 };
#define TICK_OWED_MAX 1e9 /* steps owed to TICKs beyond this are refused */

static void tick_seq(wgd *d, int64_t seq)
{
    stats *s = &d->stat;
    uint64_t gap = (uint64_t)seq - s->tick_seq_next;
    if (s->tick_seen && gap != 0) {
        if (gap <= TICK_GAP_MAX) {
            s->drops += gap;
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

/* External lockstep tick: owe nsteps, run by the loop in bounded chunks
 * (lockstep_progress); no ACK. With a key, a tick that is not signed, fresh
 * and new from its client is logged, counted as dropped and changes
 * nothing (not even the seq count: a forger's seq says nothing). */
static void on_tick(const lcm_recv_buf_t *rb, const char *channel, void *user)
{
    (void)channel;
    wgd *d = user;
    wormgear_tick_t t;
    char why[TICK_WHY] = "rejected by the decoder";
    int32_t mac_len;
    if (wire_tick_check(rb->data, rb->data_size, &mac_len, why, sizeof why) ||
        wormgear_tick_t_decode(rb->data, 0, (int)rb->data_size, &t) < 0) {
        d->stat.drops++;
        log_msg(&d->log, LOG_WARNING, "undecodable TICK message (%u bytes) ignored: %s",
                rb->data_size, why);
        return;
    }
    int rc = auth_check(&d->auth, AUTH_TICK, rb->data, rb->data_size, mac_len, t.client, t.seq,
                        t.utime, lcmio_now_us(), why, sizeof why);
    wormgear_tick_t_decode_cleanup(&t);
    if (rc) {
        d->stat.drops++;
        log_msg(&d->log, LOG_WARNING, "TICK (seq %" PRId64 ", %" PRId64 " steps) refused: %s",
                t.seq, t.nsteps, why);
        return;
    }
    tick_seq(d, t.seq);
    if (d->conf.mode != MODE_LOCKSTEP || d->run != RUN_RUNNING || d->step.active)
        return;
    if (t.nsteps < 1 || t.nsteps > 10000000) {
        log_msg(&d->log, LOG_WARNING, "TICK nsteps = %" PRId64 " outside [1, 1e7]: ignored",
                t.nsteps);
        return;
    }
    if ((double)d->owed.ticks + (double)t.nsteps > TICK_OWED_MAX) {
        d->stat.drops++;
        log_msg(&d->log, LOG_WARNING, "TICK of %" PRId64 " steps ignored: %" PRIu64 " steps "
                "from earlier ticks still to run (limit %g)", t.nsteps, d->owed.ticks,
                TICK_OWED_MAX);
        return;
    }
    d->owed.ticks += (uint64_t)t.nsteps;
}

uint64_t lockstep_progress(wgd *d, uint64_t max)
{
    if (d->conf.mode != MODE_LOCKSTEP || d->run != RUN_RUNNING || d->step.active) {
        d->owed.ticks = 0; /* a backstop: pause and mode changes clear them at once */
        return 0;
    }
    uint64_t n = d->owed.ticks < max ? d->owed.ticks : max, done = cmd_run(d, n);
    d->owed.ticks = done < n ? 0 : d->owed.ticks - done;
    return done;
}

int lockstep_init(wgd *d)
{
    lcm_subscription_t *s = lcm_subscribe(d->io.lcm, d->io.ch[CH_TICK], on_tick, d);
    if (!s) {
        snprintf(d->init_why, sizeof d->init_why, "LCM: cannot subscribe %s", d->io.ch[CH_TICK]);
        return WG_EIO;
    }
    lcm_subscription_set_queue_capacity(s, TICK_QUEUE);
    return WG_OK;
}

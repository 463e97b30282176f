/* ctl_tick.c - wgctl's tick: send, and with --wait watch what came of it:
 * its refusal on ACK, or its steps on STATUS (ctl_tick.h). */
#include "ctl_tick.h"

#include "bus_msg.h"
#include "cli.h"

#include "lcmtypes/wormgear_status_t.h"

#include <inttypes.h>
#include <stdio.h>
#include <string.h>

enum { RAN = 1, REFUSED, LAPSED };

/* What the STATUS messages taken so far said (the last one); the tick's
 * refusal, if one came, is the bus's (c->tick_ack). */
typedef struct watch {
    bus *c;
    int n;                       /* STATUS messages taken */
    int64_t steps;               /* steps of the last */
    char mode[16], run[16];
    int n0;                      /* n when the tick was sent */
    int64_t steps0, want;
} watch;

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const wormgear_status_t *m,
                      void *u)
{
    (void)ch;
    watch *w = u;
    if (!bus_signed(w->c, BUS_STATUS, rb)) /* with a key: the daemon's only */
        return;
    w->n++;
    w->steps = m->steps;
    cli_text(w->mode, sizeof w->mode, m->mode);
    cli_text(w->run, sizeof w->run, m->run);
}

BUS_RAW_HANDLER(on_status_raw, wormgear_status_t, BUS_STATUS, on_status)

static int have_status(void *u) { return ((watch *)u)->n > 0; }

/* What came of the tick: refused (its ACK, naming it by client, seq and
 * utime: a flood of others' refusals hides nothing); lapsed (not lockstep, or
 * paused: said by the second STATUS since, as the first may have left
 * before the tick arrived; realtime's steps are the pace's, not the
 * tick's); ran (in lockstep, the step count grew by nsteps); or 0: not
 * yet. */
static int outcome(const watch *w)
{
    if (w->c->tick_ack.got)
        return REFUSED;
    if (w->n == w->n0)
        return 0;
    if (strcmp(w->mode, "lockstep") || !strcmp(w->run, "paused"))
        return w->n >= w->n0 + 2 ? LAPSED : 0;
    return w->steps >= w->steps0 + w->want ? RAN : 0;
}

static int decided(void *u) { return outcome(u) != 0; }

int ctl_tick(bus *c, int64_t nsteps, int wait, double timeout_s, int json)
{
    watch w = {.c = c, .want = nsteps};
    lcm_subscription_t *sub = NULL;
    char hint[512];
    int ms = (int)(timeout_s * 1000);
    if (wait) {
        sub = bus_subscribe(c, "STATUS", on_status_raw, &w, 0);
        bus_wait(c, ms, have_status, &w);
        if (!w.n) {
            lcm_unsubscribe(c->lcm, sub);
            fprintf(stderr, "wgctl: tick: not sent: no STATUS on %sSTATUS within %g s to "
                    "measure it against: %s\n", c->prefix, timeout_s,
                    bus_hint(c, hint, sizeof hint));
            return 1;
        }
        w.n0 = w.n, w.steps0 = w.steps;
    }
    int64_t seq = bus_tick(c, nsteps);
    if (seq < 0) {
        if (sub)
            lcm_unsubscribe(c->lcm, sub);
        fprintf(stderr, "wgctl: tick not sent: %s\n", c->send_why);
        return 1;
    }
    const char *sg = c->signing ? "signed" : "unsigned";
    if (!wait) {
        if (json)
            printf("{\"sent\":true,\"op\":\"tick\",\"seq\":%" PRId64 ",\"nsteps\":%" PRId64
                   ",\"signed\":%s}\n", seq, nsteps, c->signing ? "true" : "false");
        else
            printf("sent TICK seq %" PRId64 ": %" PRId64 " steps, %s (a tick taken has no "
                   "answer: in lockstep mode the daemon runs its steps; a refused one is "
                   "answered on ACK; --wait waits for either, and 'wgctl status' shows the "
                   "steps and the ticks refused with why)\n", seq, nsteps, sg);
        return 0;
    }
    bus_wait(c, ms, decided, &w);
    lcm_unsubscribe(c->lcm, sub);
    int out = outcome(&w);
    const bus_ack *a = &c->tick_ack;
    static const char *const name[] = {"unknown", "ran", "refused", "lapsed"};
    if (json) {
        printf("{\"sent\":true,\"op\":\"tick\",\"seq\":%" PRId64 ",\"nsteps\":%" PRId64
               ",\"signed\":%s,\"result\":\"%s\",\"steps\":%" PRId64 ",\"code\":",
               seq, nsteps, c->signing ? "true" : "false", name[out], w.steps);
        cli_json_str(stdout, out == REFUSED ? a->code : "");
        printf(",\"message\":");
        cli_json_str(stdout, out == REFUSED ? a->message : "");
        printf("}\n");
    } else if (out == RAN) {
        printf("TICK seq %" PRId64 " (%s): %" PRId64 " steps run (the daemon's step %" PRId64
               " -> %" PRId64 ")\n", seq, sg, nsteps, w.steps0, w.steps);
    } else if (out == REFUSED) {
        fprintf(stderr, "wgctl: tick: %s: %s\n", a->code, a->message);
    } else if (out == LAPSED) {
        fprintf(stderr, "wgctl: tick: TICK seq %" PRId64 " did not run: the daemon is %s in "
                "%s mode, where a tick lapses (ticks run in lockstep mode while running: "
                "wgctl mode lockstep, wgctl resume)\n", seq, w.run, w.mode);
    } else {
        fprintf(stderr, "wgctl: tick: within %g s no STATUS showed TICK seq %" PRId64 "'s %"
                PRId64 " steps run (the daemon's step %" PRId64 " -> %" PRId64 ") nor an "
                "ACK refusing it%s%s\n", timeout_s, seq, nsteps, w.steps0, w.steps,
                w.n == w.n0 ? ": no STATUS came after it; " : "",
                w.n == w.n0 ? bus_hint(c, hint, sizeof hint) : "");
    }
    return out == RAN ? 0 : 1;
}

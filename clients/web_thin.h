/* web_thin.h - how wgweb cuts the daemon's streams down to rates a browser
 * and Foxglove's Plot panel take. Pure: the caller passes wall time.
 *
 * Scope: STATE samples are kept on a fixed stride of RK4 steps, chosen each
 * wall second from the measured input rate so that at most `target_hz`
 * samples per wall second pass: uniform in simulated time, so the plot's
 * time axis stays true. Sections and contact events: a rate cap that keeps
 * each one with probability cap / input rate (a random choice, never a
 * stride, which would alias a period-n orbit onto fewer points), and a
 * token bucket as a hard limit. */
#ifndef WEB_THIN_H
#define WEB_THIN_H

#include <stdint.h>

typedef struct thin_scope {
    double target_hz;     /* samples per wall second out, > 0 */
    double in_hz;         /* samples per wall second in, last second */
    uint64_t in_count;    /* samples in since the last thin_scope_second */
    int64_t stride_steps; /* keep samples at least this many steps apart */
    int64_t last_step;    /* step of the last kept sample, -1 none */
    int decimation;       /* the daemon's steps per sample, last seen */
} thin_scope;

/* A decimator passing at most target_hz samples per wall second. */
void thin_scope_init(thin_scope *t, double target_hz);

/* Whether the sample at RK4 step `step` (the daemon's decimation
 * `decimation` steps per sample) is kept. A step going backwards (daemon
 * reset or restart) starts over. */
int thin_scope_keep(thin_scope *t, int64_t step, int decimation);

/* Once per wall interval of dt_s seconds: measure the input rate and
 * choose the stride. */
void thin_scope_second(thin_scope *t, double dt_s);

typedef struct thin_rate {
    double cap_hz;   /* at most this many per wall second out (0: none pass) */
    double in_hz;    /* input rate, last interval */
    uint64_t in_count;
    double tokens;   /* token bucket, refilled at cap_hz, at most cap_hz / 4 */
    double last_s;   /* wall time of the last refill */
    uint64_t rng;    /* xorshift64 state */
    uint64_t kept, thinned;
} thin_rate;

/* A rate cap of cap_hz per wall second; seed for the random choice. */
void thin_rate_init(thin_rate *t, double cap_hz, uint64_t seed);

/* Whether one more item, arriving at wall time now_s, is kept. */
int thin_rate_keep(thin_rate *t, double now_s);

/* Once per wall interval of dt_s seconds: measure the input rate. */
void thin_rate_second(thin_rate *t, double dt_s);

#endif

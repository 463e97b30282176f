/* web_thin.c - scope decimation and rate caps. */
#include "web_thin.h"

#include <math.h>
#include <string.h>

void thin_scope_init(thin_scope *t, double target_hz)
{
    memset(t, 0, sizeof *t);
    t->target_hz = target_hz > 0 ? target_hz : 1;
    t->stride_steps = 1;
    t->last_step = -1;
    t->decimation = 1;
}

int thin_scope_keep(thin_scope *t, int64_t step, int decimation)
{
    t->in_count++;
    if (decimation > 0)
        t->decimation = decimation;
    if (t->last_step >= 0 && step >= t->last_step && step - t->last_step < t->stride_steps)
        return 0;
    t->last_step = step;
    return 1;
}

void thin_scope_second(thin_scope *t, double dt_s)
{
    if (dt_s <= 0)
        return;
    t->in_hz = (double)t->in_count / dt_s;
    t->in_count = 0;
    double k = ceil(t->in_hz / t->target_hz);
    if (!(k >= 1))
        k = 1;
    if (k > 1e9)
        k = 1e9;
    t->stride_steps = (int64_t)k * t->decimation;
}

void thin_rate_init(thin_rate *t, double cap_hz, uint64_t seed)
{
    memset(t, 0, sizeof *t);
    t->cap_hz = cap_hz > 0 ? cap_hz : 0;
    t->tokens = t->cap_hz / 4;
    t->rng = seed ? seed : 0x9e3779b97f4a7c15ull;
    t->last_s = -1;
}

static double uniform01(thin_rate *t)
{
    uint64_t x = t->rng;
    x ^= x << 13;
    x ^= x >> 7;
    x ^= x << 17;
    t->rng = x;
    return (double)(x >> 11) * 0x1.0p-53;
}

int thin_rate_keep(thin_rate *t, double now_s)
{
    t->in_count++;
    if (t->last_s >= 0 && now_s > t->last_s)
        t->tokens = fmin(t->cap_hz / 4 + 1, t->tokens + (now_s - t->last_s) * t->cap_hz);
    t->last_s = now_s;
    double p = t->in_hz > t->cap_hz ? t->cap_hz / t->in_hz : 1.0;
    if (t->tokens < 1 || uniform01(t) >= p) {
        t->thinned++;
        return 0;
    }
    t->tokens -= 1;
    t->kept++;
    return 1;
}

void thin_rate_second(thin_rate *t, double dt_s)
{
    if (dt_s <= 0)
        return;
    t->in_hz = (double)t->in_count / dt_s;
    t->in_count = 0;
}

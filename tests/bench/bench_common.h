/* bench_common.h - helpers shared by the GSL/SUNDIALS benchmarks: a clock,
 * medians, and the model's right-hand side in the form a general-purpose
 * integrator calls it (excitation evaluated at the stage time with libm,
 * then the reference RHS wg_rhs). Static functions only; no global state. */
#ifndef WG_BENCH_COMMON_H
#define WG_BENCH_COMMON_H

#include "wormgear/wg_model.h"

#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

/* CPU time of the calling thread, in ns: on this shared 2-vCPU machine the
 * time a benchmark is descheduled would otherwise land on whichever
 * contender was running (wall time is what bench_step reports). */
static inline double bench_now_ns(void)
{
    struct timespec t;
    clock_gettime(CLOCK_THREAD_CPUTIME_ID, &t);
    return 1e9 * (double)t.tv_sec + (double)t.tv_nsec;
}

static int bench_cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Median of n values (sorts a copy). */
static inline double bench_median(const double *v, int n)
{
    double t[64];
    n = n > 64 ? 64 : n;
    memcpy(t, v, sizeof(double) * (size_t)n);
    qsort(t, (size_t)n, sizeof t[0], bench_cmp);
    return n % 2 ? t[n / 2] : 0.5 * (t[n / 2 - 1] + t[n / 2]);
}

/* The ODE as an integrator sees it: time t local to the current mesh
 * period (psi = psi0 + omega t), y the 14 consistent-form states. */
typedef struct bench_ode {
    const wg_params *p;
    double omega, psi0;
    uint64_t nrhs; /* right-hand side evaluations */
} bench_ode;

static inline void bench_rhs(bench_ode *o, double t, const double *y, double *dy)
{
    wg_exc e;
    wg_exc_eval(o->p, o->psi0 + o->omega * t, o->omega, &e);
    wg_rhs(WG_MODEL_CONSISTENT, o->p, &e, y, dy);
    o->nrhs++;
}

/* GSL odeiv2 signature. */
static inline int bench_gsl_rhs(double t, const double y[], double dy[], void *params)
{
    bench_rhs(params, t, y, dy);
    return 0; /* GSL_SUCCESS */
}

/* One classical RK4 step by hand on the same RHS (4 calls, libm excitation). */
static inline void bench_hand_rk4(bench_ode *o, double t, double h, double *y)
{
    double k1[14], k2[14], k3[14], k4[14], yt[14];
    bench_rhs(o, t, y, k1);
    for (int i = 0; i < 14; i++)
        yt[i] = y[i] + 0.5 * h * k1[i];
    bench_rhs(o, t + 0.5 * h, yt, k2);
    for (int i = 0; i < 14; i++)
        yt[i] = y[i] + 0.5 * h * k2[i];
    bench_rhs(o, t + 0.5 * h, yt, k3);
    for (int i = 0; i < 14; i++)
        yt[i] = y[i] + h * k3[i];
    bench_rhs(o, t + h, yt, k4);
    for (int i = 0; i < 14; i++)
        y[i] += h / 6.0 * ((k1[i] + k4[i]) + 2.0 * (k2[i] + k3[i]));
}

#endif

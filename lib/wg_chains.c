/* wg_chains.c - chains with continuation (each point seeded by the one
 * before), run on POSIX threads, o->pair chains at once on each (their
 * main sims' runs paired or batched: duo.h). A point's analysis is
 * wg_sweep.c's (sweep.h). */
#include "sweep.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <pthread.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

double wg_chain_value(const wg_chain *c, int i)
{
    int j = c->dir < 0 ? c->npts - 1 - i : i;
    if (c->npts < 2)
        return c->v0;
    /* exact end points; interior by the same formula in either direction */
    return j == c->npts - 1 ? c->v1 : c->v0 + (c->v1 - c->v0) * j / (c->npts - 1);
}

static int chain_run(wg_chain *c, const wg_sweep_opts *o, volatile sig_atomic_t *stop,
                     wg_progress_fn progress, void *ctx, duo *d)
{
    work w, v;
    wg_sweep_opts ov = *o;
    ov.steps = 2 * o->steps;
    ov.verify = ov.floquet = 0;
    c->ndone = 0;
    c->why[0] = 0;
    if ((c->rc = sweep_work_init(&w, o, stop, d)) == WG_OK && o->verify &&
        (c->rc = sweep_work_init(&v, &ov, stop, d)) != WG_OK)
        sweep_work_fini(&w);
    if (c->rc) {
        snprintf(c->why, sizeof c->why, "out of memory for the record buffer");
        return c->rc;
    }
    double y[WG_NSTATE_MAX] = {0};
    wg_params p = c->base;
    p.v[c->param] = wg_chain_value(c, 0);
    if (c->has_y0)
        memcpy(y, c->y0, sizeof y);
    else
        wg_equilibrium(o->model, &p, y);
    for (int i = 0; i < c->npts && !(stop && *stop); i++) {
        p.v[c->param] = wg_chain_value(c, i);
        wg_point *pt = &c->pts[i];
        int rc = wg_params_check(&p, c->why, sizeof c->why);
        if (!rc)
            rc = sweep_point_analyse(&w, &p, y, pt, c->why, sizeof c->why);
        if (!rc && o->verify)
            sweep_verify_point(&v, &p, y, pt);
        pt->value = p.v[c->param];
        pt->value2 = c->param2 >= 0 ? p.v[c->param2] : NAN;
        if (rc && rc != WG_ENONFINITE) {
            c->rc = rc;
            break;
        }
        if (rc) /* diverged: keep the point, restart from equilibrium */
            wg_equilibrium(o->model, &p, y);
        c->ndone = i + 1;
        if (progress)
            progress(ctx, -1, c->ndone); /* the pool knows the index */
    }
    sweep_work_fini(&w);
    if (o->verify)
        sweep_work_fini(&v);
    return c->rc;
}

int wg_chain_run(wg_chain *c, const wg_sweep_opts *o, volatile sig_atomic_t *stop,
                 wg_progress_fn progress, void *ctx)
{
    return chain_run(c, o, stop, progress, ctx, NULL);
}

/* ---- threads ------------------------------------------------------------- */

enum { TMAX = 256 }; /* threads */

typedef struct pool {
    wg_chain *cs;
    int n, next;
    const wg_sweep_opts *o;
    volatile sig_atomic_t *stop;
    wg_progress_fn progress;
    void *ctx;
    pthread_mutex_t lock;
    int nt;          /* threads */
    long left[TMAX]; /* per thread: the points its running chains have left */
    int live[TMAX];  /* per thread: its tasks still taking chains */
    int running[TMAX]; /* per thread: its chains running */
} pool;

typedef struct pool_thread {
    pool *pl;
    int t;
} pool_thread;

typedef struct pool_cb {
    pool *pl;
    int chain, t;
} pool_cb;

static void pool_progress(void *ctx, int chain, int ndone)
{
    (void)chain;
    pool_cb *cb = ctx;
    pthread_mutex_lock(&cb->pl->lock);
    cb->pl->left[cb->t]--;
    if (cb->pl->progress)
        cb->pl->progress(cb->pl->ctx, cb->chain, ndone);
    pthread_mutex_unlock(&cb->pl->lock);
}

/* Does thread t take the next chain (under the lock)? Yes while at least
 * as many are left as there are threads. Of the last few, only if no other
 * thread still taking chains has fewer points left in its running ones:
 * the thread about to be free takes the last chain, rather than a thread
 * that would start it after its own (the study's six chains: a thread
 * whose first two ended early took both of the last two, and the other
 * sat idle for a third of the run). A thread with no chain running always
 * takes it (its left is 0), so the pool drains. */
static int pool_mine(const pool *pl, int t)
{
    if (pl->running[t] >= (pl->n + pl->nt - 1) / pl->nt)
        return 0; /* its share at once: a thread's tasks do not take them all */
    if (pl->n - pl->next >= pl->nt)
        return 1;
    for (int u = 0; u < pl->nt; u++)
        if (u != t && pl->live[u] > 0 && pl->left[u] < pl->left[t])
            return 0;
    return 1;
}

/* Chains from the pool until it is empty, or until the last ones are
 * better left to another thread (d: as one of the thread's tasks). */
static void pool_chains(duo *d, void *arg)
{
    const pool_thread *pt = arg;
    pool *pl = pt->pl;
    const int t = pt->t;
    for (;;) {
        pthread_mutex_lock(&pl->lock);
        int stopped = pl->stop && *pl->stop;
        int i = !stopped && pl->next < pl->n && pool_mine(pl, t) ? pl->next++ : -1;
        if (i >= 0)
            pl->left[t] += pl->cs[i].npts, pl->running[t]++;
        else
            pl->live[t]--;
        pthread_mutex_unlock(&pl->lock);
        if (i < 0)
            return;
        pool_cb cb = {pl, i, t};
        chain_run(&pl->cs[i], pl->o, pl->stop, pool_progress, &cb, d);
        pthread_mutex_lock(&pl->lock);
        pl->left[t] -= pl->cs[i].npts - pl->cs[i].ndone; /* what progress did not count */
        pl->running[t]--;
        pthread_mutex_unlock(&pl->lock);
    }
}

/* A thread: o->pair chains at once (at most two when the chains are too
 * few for batches), or one at a time (also when the tasks' stacks cannot
 * be had). */
static void *pool_worker(void *arg)
{
    pool_thread *pt = arg;
    pool *pl = pt->pl;
    int k = pl->o->pair < 1 ? 1 : pl->o->pair > DUO_MAX ? DUO_MAX : pl->o->pair;
    if (k > 2 && (pl->n + pl->nt - 1) / pl->nt < DUO_BATCH_MIN)
        k = 2; /* too few chains a thread to batch: two paired, the rest left to
                  whichever thread is free first (the study's six chains) */
    void *args[DUO_MAX];
    for (int i = 0; i < k; i++)
        args[i] = pt;
    pthread_mutex_lock(&pl->lock);
    pl->live[pt->t] = k;
    pthread_mutex_unlock(&pl->lock);
    if (k < 2 || duo_main(k, pool_chains, args, NULL, NULL) != WG_OK) {
        pthread_mutex_lock(&pl->lock);
        pl->live[pt->t] = 1;
        pthread_mutex_unlock(&pl->lock);
        pool_chains(NULL, pt);
    }
    return NULL;
}

int wg_chains_run(wg_chain *cs, int n, const wg_sweep_opts *o, int threads,
                  volatile sig_atomic_t *stop, wg_progress_fn progress, void *ctx)
{
    if (n <= 0) /* no chains (an MPI rank with none dealt to it): no threads either */
        return n == 0 ? WG_OK : WG_EINVAL;
    pool pl = {cs, n, 0, o, stop, progress, ctx, PTHREAD_MUTEX_INITIALIZER, 0, {0}, {0}, {0}};
    pthread_t tid[TMAX];
    pool_thread pt[TMAX];
    int nt = threads < 1 ? 1 : threads > TMAX ? TMAX : threads;
    if (nt > n)
        nt = n;
    pl.nt = nt; /* a thread that cannot be had is never live */
    int started = 0;
    for (int t = 0; t < nt; t++)
        pt[t] = (pool_thread){&pl, t};
    for (int t = 1; t < nt; t++)
        if (pthread_create(&tid[started], NULL, pool_worker, &pt[t]) == 0)
            started++;
    pool_worker(&pt[0]);
    for (int t = 0; t < started; t++)
        pthread_join(tid[t], NULL);
    pthread_mutex_destroy(&pl.lock);
    for (int i = 0; i < n; i++)
        if (cs[i].rc)
            return cs[i].rc;
    return WG_OK;
}

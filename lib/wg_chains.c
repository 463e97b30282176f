/* wg_chains.c - chains with continuation (each point seeded by the one
 * before), run on POSIX threads, o->pair chains at once on each (their
 * main sims' runs paired or batched: duo.h), with their points'
 * step-halving checks as jobs beside them, and a chain moved between two
 * of its points to a thread with fewer. A point's analysis is wg_sweep.c's
 * (sweep.h). */
#include "sweep.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <pthread.h>
#include <stdatomic.h>
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

/* ---- a chain's step-halving checks in flight -----------------------------
 *
 * With o->verify each point's attractor is analysed again at 2N
 * (sweep_verify_point) from the point's final state, which also seeds the
 * next point. That point does not wait for the check: it is a job that any
 * task of any thread of a pool (duo.h) may run, up to SLOTS of a chain's
 * at once. Points are committed (ndone, progress) in order, once checked;
 * one at a time (wg_chain_run, --pair 1) gives the same points. */

enum { SLOTS = 4 };
enum { S_FREE, S_QUEUED, S_RUNNING, S_DONE };

struct crun;

typedef struct slot {
    work v;            /* the check's workspace */
    int ready;         /* v initialised */
    int state;         /* S_*, under the jobs' lock when there are jobs */
    int i;             /* its point */
    wg_params p;
    double y[WG_NSTATE_MAX]; /* the point's final state */
    struct slot *next; /* in the queue */
    struct crun *cr;
} slot;

/* A pool's jobs: the checks of points whose chains have gone on. */
typedef struct jobs {
    pthread_mutex_t lock; /* the queue and every slot's state */
    pthread_cond_t cond;  /* gen moved */
    atomic_ulong gen;     /* events: a check queued or ended, a chain ended */
    slot *head, *tail;
} jobs;

typedef struct crun {
    wg_chain *c;
    wg_progress_fn progress;
    void *ctx;
    duo *d;
    jobs *J;  /* NULL: one point at a time */
    slot *sl; /* SLOTS of them */
} crun;

/* Under J->lock: the waiting tasks of every thread look again. */
static void jobs_event(jobs *J)
{
    atomic_fetch_add(&J->gen, 1);
    pthread_cond_broadcast(&J->cond);
}

/* J's lock: every use of the queue and the slots takes it here (J NULL, one
 * point at a time: nothing to lock). */
static void jobs_lock(jobs *J)
{
    if (J)
        pthread_mutex_lock(&J->lock);
}

static void jobs_unlock(jobs *J)
{
    if (J)
        pthread_mutex_unlock(&J->lock);
}

/* Under the lock: commit the chain's checked points in order. */
static void chain_commit(crun *cr)
{
    for (int found = 1; found;) {
        found = 0;
        for (int k = 0; k < SLOTS; k++) {
            slot *s = &cr->sl[k];
            if (s->state == S_DONE && s->i == cr->c->ndone) {
                s->state = S_FREE;
                found = 1;
                cr->c->ndone++;
                if (cr->progress)
                    cr->progress(cr->ctx, -1, cr->c->ndone); /* the pool knows the index */
            }
        }
    }
}

/* Slot s's point is done (checked, or not to be): commit what can be. */
static void slot_done(crun *cr, slot *s)
{
    jobs_lock(cr->J);
    s->state = S_DONE;
    chain_commit(cr);
    if (cr->J)
        jobs_event(cr->J); /* a slot is free */
    jobs_unlock(cr->J);
}

/* Queue slot s's check. */
static void job_push(jobs *J, slot *s)
{
    jobs_lock(J);
    s->state = S_QUEUED;
    s->next = NULL;
    if (J->tail)
        J->tail->next = s;
    else
        J->head = s;
    J->tail = s;
    jobs_event(J);
    jobs_unlock(J);
}

/* Run one queued check (any chain's) here, its runs through d; 0 if there
 * is none. */
static int run_job(jobs *J, duo *d)
{
    if (!J)
        return 0;
    jobs_lock(J);
    slot *s = J->head;
    if (s) {
        if (!(J->head = s->next))
            J->tail = NULL;
        s->state = S_RUNNING;
    }
    jobs_unlock(J);
    if (!s)
        return 0;
    s->v.duo = d;
    sweep_verify_point(&s->v, &s->p, s->y, &s->cr->c->pts[s->i]);
    slot_done(s->cr, s);
    return 1;
}

/* From a task waiting for the jobs (a slot, its chain's checks, a chain):
 * run a queued check here, or give way until something changes. */
static void help_or_wait(jobs *J, duo *d)
{
    if (!run_job(J, d))
        duo_wait(d);
}

/* Are any of the chain's points in flight (under the lock)? */
static int in_flight(const crun *cr)
{
    for (int k = 0; k < SLOTS; k++)
        if (cr->sl[k].state == S_QUEUED || cr->sl[k].state == S_RUNNING)
            return 1;
    return 0;
}

/* A free slot for the chain's next point: runs queued checks, or waits for
 * one to end, while every slot is in flight. */
static slot *slot_get(crun *cr)
{
    for (;;) {
        slot *s = NULL;
        jobs_lock(cr->J);
        for (int k = 0; k < SLOTS && !s; k++)
            if (cr->sl[k].state == S_FREE)
                s = &cr->sl[k];
        if (s)
            s->state = S_RUNNING;
        jobs_unlock(cr->J);
        if (s)
            return s;
        help_or_wait(cr->J, cr->d);
    }
}

/* ---- a chain handed from one thread to another ----------------------------
 *
 * Once every chain has been taken, a thread that runs two chains fewer
 * than another (its task whose chain has ended) asks that one for a chain
 * (the pool's, below): the chain stops before its next point, once it has
 * run one here, and is parked with its workspace and seed; the asking
 * thread's task takes it up from that point. A chain's points depend only
 * on its seeds and parameters, not on the thread or the lanes its runs
 * had, so the bytes are the same; only the lanes change. The Table-3
 * study's six chains are dealt three a thread, and in one run the second
 * thread's three ended 0.6 s before the first's. */

/* A chain stopped between two points, for another thread to go on with. */
typedef struct parked {
    work *w;                 /* its workspace: the sims as they were */
    double y[WG_NSTATE_MAX]; /* the next point's seed */
    int next;                /* the next point */
} parked;

/* A chain's hand-off state in a pool. */
typedef struct handoff {
    atomic_int to; /* 1 + the thread that asked for the chain (0: none) */
    int owner;     /* the thread running it (-1: none; under the pool's lock) */
    int done;      /* its points done, as the pool's progress saw them (ditto) */
    parked *pk;    /* stopped, for thread to - 1 (under the pool's lock) */
} handoff;

/* Chain c's points, one at a time (d NULL), or with their checks as jobs J
 * for the tasks of duo d and of the pool's other threads; from where it was
 * parked (from, freed here), else from its start. When *asked is set (asked
 * may be NULL: never), the chain stops before its next point once it has
 * run one here, and *out is where it stopped (else NULL). */
static int chain_run(wg_chain *c, const wg_sweep_opts *o, volatile sig_atomic_t *stop,
                     wg_progress_fn progress, void *ctx, duo *d, jobs *J, parked *from,
                     atomic_int *asked, parked **out)
{
    wg_sweep_opts ov = *o;
    ov.steps = 2 * o->steps;
    ov.verify = ov.floquet = 0;
    slot sl[SLOTS];
    memset(sl, 0, sizeof sl);
    crun cr = {c, progress, ctx, d, d ? J : NULL, sl};
    double y[WG_NSTATE_MAX] = {0};
    wg_params p = c->base;
    parked *pk;
    work *w;
    int i0 = 0;
    *out = NULL;
    if (from) { /* taken up from another thread */
        w = from->w;
        w->duo = d;
        memcpy(y, from->y, sizeof y);
        i0 = from->next;
        free(from);
    } else {
        c->ndone = 0;
        c->why[0] = 0;
        const char *field = "";
        char msg[128];
        if ((c->rc = wg_sweep_opts_check(o, &field, msg, sizeof msg)) != WG_OK) {
            snprintf(c->why, sizeof c->why, "option %s: %s", field, msg);
            return c->rc;
        }
        if (!(w = malloc(sizeof *w)) || (c->rc = sweep_work_init(w, o, stop, d)) != WG_OK) {
            free(w);
            c->rc = WG_ENOMEM;
            snprintf(c->why, sizeof c->why, "out of memory for the record buffer");
            return c->rc;
        }
        p.v[c->param] = wg_chain_value(c, 0);
        if (c->has_y0)
            memcpy(y, c->y0, sizeof y);
        else
            wg_equilibrium(o->model, &p, y);
    }
    for (int i = i0; i < c->npts && !(stop && *stop); i++) {
        if (asked && i > i0 && atomic_load_explicit(asked, memory_order_relaxed) &&
            (pk = malloc(sizeof *pk))) { /* asked for, and it has run a point here */
            pk->w = w;
            pk->next = i;
            memcpy(pk->y, y, sizeof pk->y);
            *out = pk;
            break;
        }
        p.v[c->param] = wg_chain_value(c, i);
        wg_point *pt = &c->pts[i];
        int rc = wg_params_check(&p, c->why, sizeof c->why);
        if (!rc)
            rc = sweep_point_analyse(w, &p, y, pt, c->why, sizeof c->why);
        pt->value = p.v[c->param];
        pt->value2 = c->param2 >= 0 ? p.v[c->param2] : NAN;
        if (rc && rc != WG_ENONFINITE) {
            c->rc = rc;
            break;
        }
        slot *s = slot_get(&cr);
        s->i = i;
        int queued = 0;
        if (!rc && o->verify && !s->ready) {
            if (sweep_work_init(&s->v, &ov, stop, d) != WG_OK) {
                c->rc = WG_ENOMEM;
                snprintf(c->why, sizeof c->why, "out of memory for the record buffer");
                jobs_lock(cr.J);
                s->state = S_FREE;
                jobs_unlock(cr.J);
                break;
            }
            s->ready = 1;
        }
        if (!rc && o->verify) {
            if (cr.J) {
                queued = 1;
                s->p = p;
                s->cr = &cr;
                memcpy(s->y, y, sizeof s->y);
                job_push(cr.J, s);
            } else {
                sweep_verify_point(&s->v, &p, y, pt);
            }
        }
        if (rc) /* diverged: keep the point, restart from equilibrium */
            wg_equilibrium(o->model, &p, y);
        if (!queued) /* else the job's end commits it */
            slot_done(&cr, s);
    }
    for (;;) { /* the checks still in flight */
        jobs_lock(cr.J);
        int busy = in_flight(&cr);
        jobs_unlock(cr.J);
        if (!busy)
            break;
        help_or_wait(cr.J, d);
    }
    if (!*out) {
        sweep_work_fini(w);
        free(w);
    }
    for (int k = 0; k < SLOTS; k++)
        if (sl[k].ready)
            sweep_work_fini(&sl[k].v);
    return c->rc;
}

int wg_chain_run(wg_chain *c, const wg_sweep_opts *o, volatile sig_atomic_t *stop,
                 wg_progress_fn progress, void *ctx)
{
    parked *none;
    return chain_run(c, o, stop, progress, ctx, NULL, NULL, NULL, NULL, &none);
}

/* ---- threads ------------------------------------------------------------- */

enum { TMAX = 256 }; /* threads */

typedef struct pool {
    wg_chain *cs;
    int n, taken;    /* chains, and how many pool_take has handed out */
    int tasks;       /* chains a thread advances at once (pool_tasks) */
    int fill;        /* chains dealt to each thread for its start (pool_take) */
    int cursor;      /* the next chain past the dealt ones */
    const wg_sweep_opts *o;
    volatile sig_atomic_t *stop;
    wg_progress_fn progress;
    void *ctx;
    pthread_mutex_t lock;
    int nt;          /* threads */
    long left[TMAX]; /* per thread: the points its running chains have left */
    int live[TMAX];  /* per thread: its tasks still taking chains */
    int running[TMAX]; /* per thread: its chains running */
    int dealt[TMAX];   /* per thread: its dealt chains taken */
    jobs J;
    handoff *H;        /* per chain (NULL: no hand-offs) */
    int asked[TMAX];   /* per thread: chains it asked for, not yet taken */
    int giving[TMAX];  /* per thread: its chains asked for, not yet parked */
    int moves;         /* chains taken up from another thread */
} pool;

typedef struct pool_thread {
    pool *pl;
    int t;
    unsigned long seen; /* pl->J.gen when its waiting tasks last looked */
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
    if (cb->pl->H)
        cb->pl->H[cb->chain].done = ndone;
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
    if (pl->n - pl->taken >= pl->nt)
        return 1;
    for (int u = 0; u < pl->nt; u++)
        if (u != t && pl->live[u] > 0 && pl->left[u] < pl->left[t])
            return 0;
    return 1;
}

/* Chains a thread advances at once: o->pair tasks (1..DUO_MAX), two
 * when the chains are too few a thread to batch and there are no checks. */
static int pool_tasks(const pool *pl)
{
    int k = pl->o->pair < 1 ? 1 : pl->o->pair > DUO_MAX ? DUO_MAX : pl->o->pair;
    if (k > 2 && !pl->o->verify && (pl->n + pl->nt - 1) / pl->nt < DUO_BATCH_MIN)
        k = 2; /* too few chains a thread to batch: two at once (their runs
                  paired, or batched with a twin's), the rest left to
                  whichever thread is free first (the study's six chains) */
    return k;
}

/* The chain thread t takes (under the lock; at least one is left). In
 * index order a thread would take neighbours, whose costs go together:
 * the study's first thread took both of xi_p 0.08's chains and 0.10's up
 * (4.27 s of work) and the other the rest (3.03 s). So the first nt * fill
 * chains are dealt as cards are, back and forth: thread h's are h,
 * 2nt-1-h, 2nt+h, ... A thread takes its own first, then the rest in
 * index order, then another thread's dealt ones (one that never started,
 * or has not taken them yet). */
static int pool_take(pool *pl, int t)
{
    int h = t;
    pl->taken++;
    if (pl->dealt[t] >= pl->fill) {
        if (pl->cursor < pl->n)
            return pl->cursor++;
        for (h = 0; pl->dealt[h] >= pl->fill; h++)
            ;
    }
    const int r = pl->dealt[h]++;
    return r * pl->nt + (r % 2 ? pl->nt - 1 - h : h);
}

/* Under the lock: a chain parked for thread t, or -1. */
static int pool_parked(const pool *pl, int t)
{
    for (int i = 0; pl->H && i < pl->n; i++)
        if (pl->H[i].pk && atomic_load(&pl->H[i].to) == t + 1)
            return i;
    return -1;
}

/* Under the lock, from a task of thread t with no chain to take: once
 * every chain has been taken, ask the thread running the most, if it runs
 * two more than t (counting those asked for and not yet moved), for the one
 * of them with the most points left. Does t have a chain coming? */
static int pool_ask(pool *pl, int t)
{
    if (!pl->H || pl->taken < pl->n || (pl->stop && *pl->stop))
        return pl->asked[t] > 0;
    int u = -1, most = pl->running[t] + pl->asked[t] + 1;
    for (int v = 0; v < pl->nt; v++)
        if (v != t && pl->running[v] - pl->giving[v] > most)
            u = v, most = pl->running[v] - pl->giving[v];
    int j = -1;
    for (int i = 0; u >= 0 && i < pl->n; i++)
        if (pl->H[i].owner == u && !atomic_load(&pl->H[i].to) &&
            (j < 0 || pl->cs[i].npts - pl->H[i].done > pl->cs[j].npts - pl->H[j].done))
            j = i;
    if (j >= 0) {
        atomic_store(&pl->H[j].to, t + 1);
        pl->asked[t]++;
        pl->giving[u]++;
    }
    return pl->asked[t] > 0;
}

/* The thread's duo_idle_fn: has the jobs' generation moved since its
 * waiting tasks last looked (block: wait until it does)? */
static int pool_idle(void *arg, int block)
{
    pool_thread *pt = arg;
    jobs *J = &pt->pl->J;
    unsigned long g = atomic_load(&J->gen);
    if (g == pt->seen && block) {
        jobs_lock(J);
        while ((g = atomic_load(&J->gen)) == pt->seen)
            pthread_cond_wait(&J->cond, &J->lock);
        jobs_unlock(J);
    }
    if (g == pt->seen)
        return 0;
    pt->seen = g;
    return 1;
}

/* Give way until something changes: a task (d) as duo_wait does; else
 * the thread itself, as its idle function blocks. */
static void pool_wait(pool_thread *pt, duo *d)
{
    if (d)
        duo_wait(d);
    else
        pool_idle(pt, 1);
}

/* Chains from the pool until it is empty, or until the last ones are
 * better left to another thread (d: as one of the thread's tasks); then a
 * chain of a thread running two more than this one, taken over between
 * two of its points (pool_ask). With step-halving checks to run
 * (o->verify, d), the task goes on taking them, any chain's, until no
 * chain runs on any thread. */
static void pool_chains(duo *d, void *arg)
{
    pool_thread *pt = arg;
    pool *pl = pt->pl;
    const int t = pt->t;
    jobs *J = d && pl->o->verify ? &pl->J : NULL; /* the checks are the only jobs */
    for (;;) {
        pthread_mutex_lock(&pl->lock);
        int stopped = pl->stop && *pl->stop;
        int i = pool_parked(pl, t), coming = 0;
        parked *from = NULL;
        if (i >= 0) { /* taken up here */
            from = pl->H[i].pk;
            pl->H[i].pk = NULL;
            atomic_store(&pl->H[i].to, 0);
            pl->asked[t]--;
            pl->moves++;
            pl->left[t] += pl->cs[i].npts - pl->cs[i].ndone, pl->running[t]++;
        } else if (!stopped && pl->taken < pl->n && pool_mine(pl, t)) {
            i = pool_take(pl, t);
            pl->left[t] += pl->cs[i].npts, pl->running[t]++;
        } else {
            coming = pool_ask(pl, t);
        }
        if (i >= 0 && pl->H)
            pl->H[i].owner = t;
        int more = !stopped && pl->taken < pl->n;
        for (int u = 0; u < pl->nt; u++)
            more |= pl->running[u] > 0;
        if (i < 0 && !coming && (!J || !more))
            pl->live[t]--; /* it returns */
        pthread_mutex_unlock(&pl->lock);
        if (i < 0) {
            if (coming)
                pool_wait(pt, d); /* it comes once parked, or the ask lapses */
            else if (J && more)
                help_or_wait(J, d); /* a job, or a chain, may come */
            else
                return;
            continue;
        }
        pool_cb cb = {pl, i, t};
        parked *pk;
        chain_run(&pl->cs[i], pl->o, pl->stop, pool_progress, &cb, d, J, from,
                  pl->H ? &pl->H[i].to : NULL, &pk);
        pthread_mutex_lock(&pl->lock);
        pl->left[t] -= pl->cs[i].npts - pl->cs[i].ndone; /* what progress did not count */
        pl->running[t]--;
        int to = pl->H ? atomic_load(&pl->H[i].to) - 1 : -1;
        if (pl->H)
            pl->H[i].owner = -1;
        if (to >= 0) {
            pl->giving[t]--;
            if (pk) {
                pl->H[i].pk = pk; /* for thread to */
            } else { /* it ended before its next point: the ask lapses */
                atomic_store(&pl->H[i].to, 0);
                pl->asked[to]--;
            }
        }
        pthread_mutex_unlock(&pl->lock);
        jobs_lock(&pl->J);  /* also from a thread without tasks (d NULL): */
        jobs_event(&pl->J); /* others' waiting ones may be done now */
        jobs_unlock(&pl->J);
    }
}

/* A thread: o->pair tasks taking chains and checks (at most two when the
 * chains are too few for batches and there are no checks), or one chain at
 * a time (also when the tasks' stacks cannot be had). */
static void *pool_worker(void *arg)
{
    pool_thread *pt = arg;
    pool *pl = pt->pl;
    int k = pl->tasks;
    void *args[DUO_MAX];
    for (int i = 0; i < k; i++)
        args[i] = pt;
    pthread_mutex_lock(&pl->lock);
    pl->live[pt->t] = k;
    pthread_mutex_unlock(&pl->lock);
    if (k < 2 || duo_main(k, pool_chains, args, pool_idle, pt) != WG_OK) {
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
    int moves;
    return chains_run(cs, n, o, threads, stop, progress, ctx, &moves);
}

int chains_run(wg_chain *cs, int n, const wg_sweep_opts *o, int threads,
               volatile sig_atomic_t *stop, wg_progress_fn progress, void *ctx, int *moves)
{
    *moves = 0;
    if (n <= 0) /* no chains (an MPI rank with none dealt to it): no threads either */
        return n == 0 ? WG_OK : WG_EINVAL;
    pool pl = {cs, n, 0, 0, 0, 0, o, stop, progress, ctx, PTHREAD_MUTEX_INITIALIZER, 0,
               {0}, {0}, {0}, {0},
               {PTHREAD_MUTEX_INITIALIZER, PTHREAD_COND_INITIALIZER, 0, NULL, NULL},
               NULL, {0}, {0}, 0};
    pthread_t tid[TMAX];
    pool_thread pt[TMAX];
    int nt = threads < 1 ? 1 : threads > TMAX ? TMAX : threads;
    if (nt > n)
        nt = n;
    pl.nt = nt; /* a thread that cannot be had is never live */
    if (nt > 1 && (pl.H = calloc((size_t)n, sizeof *pl.H))) /* else no hand-offs */
        for (int i = 0; i < n; i++)
            pl.H[i].owner = -1;
    pl.tasks = pool_tasks(&pl);
    pl.fill = pl.tasks < n / nt ? pl.tasks : n / nt;
    pl.cursor = nt * pl.fill;
    int started = 0;
    for (int t = 0; t < nt; t++)
        pt[t] = (pool_thread){&pl, t, 0};
    for (int t = 1; t < nt; t++)
        if (pthread_create(&tid[started], NULL, pool_worker, &pt[t]) == 0)
            started++;
    pool_worker(&pt[0]);
    for (int t = 0; t < started; t++)
        pthread_join(tid[t], NULL);
    for (int i = 0; pl.H && i < n; i++)
        if (pl.H[i].pk) { /* never taken up (cannot be: its asker waits for it) */
            sweep_work_fini(pl.H[i].pk->w);
            free(pl.H[i].pk->w);
            free(pl.H[i].pk);
        }
    free(pl.H);
    *moves = pl.moves;
    pthread_mutex_destroy(&pl.lock);
    pthread_mutex_destroy(&pl.J.lock);
    pthread_cond_destroy(&pl.J.cond);
    for (int i = 0; i < n; i++)
        if (cs[i].rc)
            return cs[i].rc;
    return WG_OK;
}

/* sweep_par_mpi.c - the MPI layer of sweep_par.h (built with WG_MPI=ON): chains
 * are dealt round-robin to ranks, each rank runs its share on threads, and
 * rank 0 receives every foreign chain's points as raw bytes (homogeneous
 * nodes: same struct layout everywhere). While the chains run on a thread of
 * their own, each rank's main thread (the only one calling MPI: FUNNELED)
 * sums the points done over the ranks every PROGRESS_S, so rank 0 shows one
 * progress bar for the whole run. */
#include "sweep_par.h"
#include "wormgear/wg_status.h"

#include <mpi.h>
#include <pthread.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

#define PROGRESS_S 0.2 /* seconds between the ranks' progress sums */

int par_init(int *argc, char ***argv, int *rank, int *size)
{
    int provided;
    if (MPI_Init_thread(argc, argv, MPI_THREAD_FUNNELED, &provided) != MPI_SUCCESS)
        return -1;
    MPI_Comm_rank(MPI_COMM_WORLD, rank);
    MPI_Comm_size(MPI_COMM_WORLD, size);
    return 0;
}

/* Header of a chain's result on the wire. */
typedef struct wire {
    int ndone, rc;            /* rc: the chain's return code (wg_chain.rc) */
    char why[160];
} wire;

static void send_chain(const wg_chain *c, int tag)
{
    wire w = {c->ndone, c->rc, {0}};
    memcpy(w.why, c->why, sizeof w.why);
    MPI_Send(&w, (int)sizeof w, MPI_BYTE, 0, tag, MPI_COMM_WORLD);
    if (c->ndone)
        MPI_Send(c->pts, (int)(sizeof(wg_point) * (size_t)c->ndone), MPI_BYTE, 0, tag,
                 MPI_COMM_WORLD);
}

static void recv_chain(wg_chain *c, int from, int tag)
{
    wire w;
    MPI_Recv(&w, (int)sizeof w, MPI_BYTE, from, tag, MPI_COMM_WORLD, MPI_STATUS_IGNORE);
    c->ndone = w.ndone;
    c->rc = w.rc;
    memcpy(c->why, w.why, sizeof c->why);
    if (w.ndone)
        MPI_Recv(c->pts, (int)(sizeof(wg_point) * (size_t)w.ndone), MPI_BYTE, from, tag,
                 MPI_COMM_WORLD, MPI_STATUS_IGNORE);
}

/* This rank's chains, run on a thread; done and finished under lock. */
typedef struct runner {
    wg_chain *cs;
    int n, threads, rc;
    const wg_sweep_opts *o;
    volatile sig_atomic_t *stop;
    pthread_mutex_t lock;
    long done;
    int finished;
} runner;

static void count(void *ctx, int chain, int ndone)
{
    (void)chain, (void)ndone;
    runner *r = ctx;
    pthread_mutex_lock(&r->lock);
    r->done++;
    pthread_mutex_unlock(&r->lock);
}

static void *run_chains(void *arg)
{
    runner *r = arg;
    int rc = wg_chains_run(r->cs, r->n, r->o, r->threads, r->stop, count, r);
    pthread_mutex_lock(&r->lock);
    r->rc = rc;
    r->finished = 1;
    pthread_mutex_unlock(&r->lock);
    return NULL;
}

/* Every PROGRESS_S, the points done and the ranks still running, summed
 * over the ranks (collective: each rank loops until none runs). */
static void watch(runner *r, int g_rank, par_progress_fn progress, void *ctx)
{
    long last = -1;
    for (;;) {
        struct timespec ts = {0, (long)(PROGRESS_S * 1e9)};
        nanosleep(&ts, NULL);
        pthread_mutex_lock(&r->lock);
        long in[2] = {r->done, !r->finished}, out[2];
        pthread_mutex_unlock(&r->lock);
        MPI_Allreduce(in, out, 2, MPI_LONG, MPI_SUM, MPI_COMM_WORLD);
        if (g_rank == 0 && progress && out[0] != last)
            progress(ctx, out[0]);
        last = out[0];
        if (out[1] == 0)
            return;
    }
}

int par_run(wg_chain *cs, int n, const wg_sweep_opts *o, int threads,
            volatile sig_atomic_t *stop, par_progress_fn progress, void *ctx)
{
    int mine = 0, g_rank, g_size;
    MPI_Comm_rank(MPI_COMM_WORLD, &g_rank);
    MPI_Comm_size(MPI_COMM_WORLD, &g_size);
    wg_chain *local = malloc(sizeof *local * (size_t)(n + 1));
    int *idx = malloc(sizeof *idx * (size_t)(n + 1));
    if (!local || !idx) {
        free(local);
        free(idx);
        return WG_ENOMEM;
    }
    for (int i = g_rank; i < n; i += g_size) {
        local[mine] = cs[i];
        idx[mine++] = i;
    }
    runner r = {local, mine, threads, WG_OK, o, stop, PTHREAD_MUTEX_INITIALIZER, 0, 0};
    pthread_t tid;
    int threaded = pthread_create(&tid, NULL, run_chains, &r) == 0;
    if (!threaded)
        run_chains(&r); /* no thread: run here, then sum once */
    watch(&r, g_rank, progress, ctx);
    if (threaded)
        pthread_join(tid, NULL);
    pthread_mutex_destroy(&r.lock);
    for (int k = 0; k < mine; k++) /* copy back the return code, ndone (pts are shared) */
        cs[idx[k]] = local[k];
    free(local);
    free(idx);
    for (int i = 0; i < n; i++) {
        int owner = i % g_size;
        if (owner == 0)
            continue;
        if (g_rank == owner)
            send_chain(&cs[i], i);
        else if (g_rank == 0)
            recv_chain(&cs[i], owner, i);
    }
    for (int i = 0; i < n; i++)
        if (cs[i].rc)
            return cs[i].rc;
    return WG_OK;
}

int par_any(int flag)
{
    int in = flag != 0, out = 0;
    MPI_Allreduce(&in, &out, 1, MPI_INT, MPI_MAX, MPI_COMM_WORLD);
    return out;
}

void par_fini(void) { MPI_Finalize(); }

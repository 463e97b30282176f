/* sweep_par_mpi.c - the MPI layer of sweep_par.h (built with WG_MPI=ON): chains
 * are dealt round-robin to ranks, each rank runs its share on threads, and
 * rank 0 receives every foreign chain's points as raw bytes (homogeneous
 * nodes: same struct layout everywhere). */
#include "sweep_par.h"
#include "wormgear/wg_status.h"

#include <mpi.h>
#include <stdlib.h>
#include <string.h>

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

int par_run(wg_chain *cs, int n, const wg_sweep_opts *o, int threads,
            volatile sig_atomic_t *stop, wg_progress_fn progress, void *ctx)
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
    wg_chains_run(local, mine, o, threads, stop, progress, ctx);
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

/* sweep_par.c - the single-process layer of sweep_par.h: threads only (the
 * MPI layer is sweep_par_mpi.c). */
#include "sweep_par.h"

int par_init(int *argc, char ***argv, int *rank, int *size)
{
    (void)argc;
    (void)argv;
    *rank = 0;
    *size = 1;
    return 0;
}

typedef struct counter {
    par_progress_fn fn;
    void *ctx;
    long done;
} counter;

/* wg_chains_run calls this under its lock, one point at a time. */
static void count(void *ctx, int chain, int ndone)
{
    (void)chain, (void)ndone;
    counter *c = ctx;
    if (c->fn)
        c->fn(c->ctx, ++c->done);
}

int par_run(wg_chain *cs, int n, const wg_sweep_opts *o, int threads,
            volatile sig_atomic_t *stop, par_progress_fn progress, void *ctx)
{
    counter c = {progress, ctx, 0};
    return wg_chains_run(cs, n, o, threads, stop, count, &c);
}

int par_any(int flag) { return flag != 0; }

void par_fini(void) {}

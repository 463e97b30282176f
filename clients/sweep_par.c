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

int par_run(wg_chain *cs, int n, const wg_sweep_opts *o, int threads,
            volatile sig_atomic_t *stop, wg_progress_fn progress, void *ctx)
{
    return wg_chains_run(cs, n, o, threads, stop, progress, ctx);
}

int par_any(int flag) { return flag != 0; }

void par_fini(void) {}

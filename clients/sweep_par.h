/* sweep_par.h - running a study's chains: POSIX threads in one process, and
 * (built with WG_MPI=ON) chains spread over MPI ranks, gathered on rank 0.
 * A chain's result does not depend on where it ran, so every layout gives
 * the same bytes as the serial run. */
#ifndef WG_SWEEP_PAR_H
#define WG_SWEEP_PAR_H

#include <signal.h>
#include "wormgear/wg_sweep.h"

/* Start the parallel layer; *rank and *size are 0 and 1 without MPI. */
int par_init(int *argc, char ***argv, int *rank, int *size);

/* Progress of a whole run: done points finished so far over every rank.
 * Called on rank 0 only, from one thread at a time, done never falling. */
typedef void (*par_progress_fn)(void *ctx, long done);

/* Run the n chains: rank r runs chains r, r + size, ... on `threads`
 * threads, then rank 0 receives every chain's points and return code.
 * Returns WG_OK or the first chain's failure code (on rank 0). */
int par_run(wg_chain *cs, int n, const wg_sweep_opts *o, int threads,
            volatile sig_atomic_t *stop, par_progress_fn progress, void *ctx);

/* Any rank saw a stop request (collective; 0/1). */
int par_any(int flag);

/* Shut the parallel layer down. */
void par_fini(void);

#endif

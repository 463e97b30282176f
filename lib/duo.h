/* duo.h - several tasks on one thread whose long sim runs are paired
 * (wg_duo.c). Each task is a coroutine with its own stack; when it asks
 * for a run (duo_run), or two (duo_run2), it yields, and the thread's
 * scheduler advances two waiting runs at once with wg_sim_run_pair (three
 * or more of one kind where the CPU has a batched loop: up to eight of
 * them with wg_sim_run_batch) until one is done, and resumes a task once
 * its runs are. A run alone (no other waiting) goes by wg_sim_run. A task
 * may also wait for work another task or thread makes (duo_wait). Each
 * sim's bits are what wg_sim_run would give: only the interleaving
 * changes. Private to the library (the sweeps use it). */
#ifndef WG_DUO_H
#define WG_DUO_H

#include "wormgear/wg_sim.h"

typedef struct duo duo;

/* The body of a task: runs on its own stack; d is for duo_run. */
typedef void (*duo_task_fn)(duo *d, void *arg);

/* What the tasks in duo_wait wait for, when it comes from another thread:
 * called with block 0 at every turn of the scheduler, 1 when no task can go
 * on (then it returns once something may have changed). Returns 1 if the
 * waiting tasks should look again. */
typedef int (*duo_idle_fn)(void *ctx, int block);

/* Runs fn(d, args[i]) for each i < n (1..DUO_MAX) as tasks on the calling
 * thread and returns when every one has returned: WG_OK, or WG_ENOMEM if
 * the stacks could not be had (then nothing ran). idle (may be NULL: then
 * the tasks in duo_wait are woken whenever no task can go on) is asked as
 * duo_idle_fn says, with ctx. */
enum { DUO_MAX = 8 };

/* Runs of one kind waiting at once from which the scheduler batches them
 * (wg_sim_run_batch, where the CPU has a batched loop); fewer are paired. */
enum { DUO_BATCH_MIN = 3 };
int duo_main(int n, duo_task_fn fn, void *const args[], duo_idle_fn idle, void *ctx);

/* From a task: wg_sim_run(s, n, sink, NULL), interleaved with another
 * task's run when one is waiting. */
int duo_run(duo *d, wg_sim *s, uint64_t n, const wg_sink *sink);

/* Runs a task may ask for at once (duo_run2). */
enum { DUO_RUNS = 2 };

/* From a task: wg_sim_run(a, n, NULL, NULL) and wg_sim_run(b, n, NULL,
 * NULL) of two distinct sims at once, each interleaved with the other and
 * with other tasks' runs (a twin trajectory beside its base). Returns a's
 * status, or b's if a's is WG_OK; both run to their end or failure.
 * WG_EINVAL if a is b (nothing runs). */
int duo_run2(duo *d, wg_sim *a, wg_sim *b, uint64_t n);

/* From a task: give way until the idle function says to look again (a
 * task waiting for work another task or thread makes), or, without one,
 * until no task can go on: then it must look again at what it waits for. */
void duo_wait(duo *d);

#endif

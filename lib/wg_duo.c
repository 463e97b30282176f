/* wg_duo.c - tasks on one thread whose sim runs are paired (duo.h).
 *
 * The tasks are ucontext coroutines, each on an mmap'd stack with a guard
 * page below it. The scheduler runs on the thread's own stack: it resumes
 * every task that can go on until each has asked for a run (or returned),
 * then advances the two runs asked for longest ago with wg_sim_run_pair
 * (three or more of one kind, on a CPU with a batched loop: all of those
 * with wg_sim_run_batch, one sim a vector lane) until one is done, and
 * resumes that task; a run with no partner goes by wg_sim_run. The runs
 * themselves (and their sinks' callbacks) execute on the scheduler's stack.
 * A task in duo_wait is resumed when the idle function says so, or, with
 * none, when no task can go on. Under AddressSanitizer every switch is announced
 * (__sanitizer_start/finish_switch_fiber) so it tracks the stacks. */
#include "duo.h"
#include "internal.h"
#include "wormgear/wg_status.h"

#include <stdint.h>
#include <stdlib.h>
#include <sys/mman.h>
#include <ucontext.h>
#include <unistd.h>

#if defined(__SANITIZE_ADDRESS__)
#include <sanitizer/common_interface_defs.h>
#define DUO_ASAN 1
#else
#define DUO_ASAN 0
#endif

enum { STACK_BYTES = 1 << 20 }; /* touched pages only: a sweep point needs ~20 kB */
enum { T_READY, T_WAIT, T_IDLE, T_DONE }; /* T_IDLE: in duo_wait */

typedef struct task {
    ucontext_t ctx;
    char *map;      /* guard page, then the stack */
    size_t maplen;
    duo *d;
    void *arg;
    int state;
    /* the run asked for (T_WAIT) and its progress */
    wg_sim *s;
    const wg_sink *sink;
    uint64_t n, done, asked; /* asked: order of asking, oldest first */
    int rc;
} task;

struct duo {
    ucontext_t main;
    task t[DUO_MAX];
    int n, cur;
    duo_task_fn fn;
    uint64_t clock;
    long page;
    const void *main_bottom; /* the thread's stack, for AddressSanitizer */
    size_t main_size;
};

/* Scheduler -> task i. */
static void to_task(duo *d, int i)
{
    task *t = &d->t[i];
    d->cur = i;
#if DUO_ASAN
    void *fake = NULL;
    __sanitizer_start_switch_fiber(&fake, t->map + d->page, STACK_BYTES);
#endif
    swapcontext(&d->main, &t->ctx);
#if DUO_ASAN
    __sanitizer_finish_switch_fiber(fake, NULL, NULL);
#endif
}

/* Task -> scheduler; a task that has returned never comes back. */
static void to_main(task *t)
{
    duo *d = t->d;
#if DUO_ASAN
    void *fake = NULL;
    __sanitizer_start_switch_fiber(t->state == T_DONE ? NULL : &fake, d->main_bottom,
                                   d->main_size);
#endif
    swapcontext(&t->ctx, &d->main);
#if DUO_ASAN
    __sanitizer_finish_switch_fiber(fake, &d->main_bottom, &d->main_size);
#endif
}

/* A task's first frame: makecontext passes ints, so the task's address
 * comes in two halves. */
static void entry(unsigned hi, unsigned lo)
{
    task *t = (task *)(((uintptr_t)hi << 32) | (uintptr_t)lo);
#if DUO_ASAN
    __sanitizer_finish_switch_fiber(NULL, &t->d->main_bottom, &t->d->main_size);
#endif
    t->d->fn(t->d, t->arg);
    t->state = T_DONE;
    to_main(t);
}

int duo_run(duo *d, wg_sim *s, uint64_t n, const wg_sink *sink)
{
    task *t = &d->t[d->cur];
    if (n == 0)
        return WG_OK;
    t->s = s, t->n = n, t->sink = sink, t->done = 0, t->rc = WG_OK;
    t->state = T_WAIT;
    t->asked = d->clock++;
    to_main(t);
    return t->rc;
}

void duo_wait(duo *d)
{
    task *t = &d->t[d->cur];
    t->state = T_IDLE;
    to_main(t);
}

/* Every task in duo_wait may go on. */
static void duo_wake(duo *d)
{
    for (int i = 0; i < d->n; i++)
        if (d->t[i].state == T_IDLE)
            d->t[i].state = T_READY;
}

/* The waiting task asked longest ago other than `not` (-1: none). */
static int oldest_waiting(const duo *d, int not)
{
    int best = -1;
    for (int i = 0; i < d->n; i++)
        if (i != not && d->t[i].state == T_WAIT &&
            (best < 0 || d->t[i].asked < d->t[best].asked))
            best = i;
    return best;
}

/* Advance the runs of tasks a and b (b < 0: a alone) until one is done;
 * a task whose run is done (or failed) can go on. */
static void advance(duo *d, int a, int b)
{
    task *ta = &d->t[a];
    if (b < 0) {
        uint64_t m = 0;
        ta->rc = wg_sim_run(ta->s, ta->n - ta->done, ta->sink, &m);
        ta->done += m;
        ta->state = T_READY;
        return;
    }
    task *tb = &d->t[b];
    wg_sim *const s[2] = {ta->s, tb->s};
    const uint64_t n[2] = {ta->n - ta->done, tb->n - tb->done};
    const wg_sink *const sk[2] = {ta->sink, tb->sink};
    uint64_t m[2] = {0, 0};
    int rc[2];
    wg_sim_run_pair(s, n, sk, m, rc);
    task *both[2] = {ta, tb};
    for (int j = 0; j < 2; j++) {
        both[j]->done += m[j];
        both[j]->rc = rc[j];
        if (rc[j] != WG_OK || both[j]->done == both[j]->n)
            both[j]->state = T_READY;
    }
}

/* The waiting tasks whose sims are of the oldest one's (a) kind, into idx:
 * how many. */
static int same_kind(const duo *d, int a, int idx[DUO_MAX])
{
    const wg_sim_core *c = d->t[a].s->core;
    int L = 0;
    for (int i = 0; i < d->n; i++)
        if (d->t[i].state == T_WAIT && d->t[i].s->core->kflags == c->kflags &&
            d->t[i].s->core->isa == c->isa)
            idx[L++] = i;
    return L;
}

/* Advance the runs of tasks idx[0..L) in one batch (wg_sim_run_batch)
 * until one is done; as advance. */
static void advance_batch(duo *d, const int idx[], int L)
{
    wg_sim *s[DUO_MAX] = {NULL};
    uint64_t n[DUO_MAX] = {0}, m[DUO_MAX] = {0};
    const wg_sink *sk[DUO_MAX] = {NULL};
    int rc[DUO_MAX] = {0};
    for (int j = 0; j < L; j++) {
        const task *t = &d->t[idx[j]];
        s[j] = t->s, n[j] = t->n - t->done, sk[j] = t->sink;
    }
    wg_sim_run_batch(L, s, n, sk, m, rc);
    for (int j = 0; j < L; j++) {
        task *t = &d->t[idx[j]];
        t->done += m[j];
        t->rc = rc[j];
        if (rc[j] != WG_OK || t->done == t->n)
            t->state = T_READY;
    }
}

static void duo_free(duo *d)
{
    for (int i = 0; i < d->n; i++)
        if (d->t[i].map)
            munmap(d->t[i].map, d->t[i].maplen);
    free(d);
}

int duo_main(int n, duo_task_fn fn, void *const args[], duo_idle_fn idle, void *ctx)
{
    if (n < 1 || n > DUO_MAX)
        return WG_EINVAL;
    duo *d = calloc(1, sizeof *d);
    if (!d)
        return WG_ENOMEM;
    d->n = n;
    d->fn = fn;
    d->page = sysconf(_SC_PAGESIZE);
    for (int i = 0; i < n; i++) {
        task *t = &d->t[i];
        t->d = d;
        t->arg = args[i];
        t->maplen = STACK_BYTES + (size_t)d->page;
        void *m = mmap(NULL, t->maplen, PROT_READ | PROT_WRITE, MAP_PRIVATE | MAP_ANONYMOUS,
                       -1, 0);
        if (m == MAP_FAILED || mprotect(m, (size_t)d->page, PROT_NONE) != 0 ||
            getcontext(&t->ctx) != 0) {
            if (m != MAP_FAILED)
                munmap(m, t->maplen);
            duo_free(d);
            return WG_ENOMEM;
        }
        t->map = m;
        t->ctx.uc_stack.ss_sp = t->map + d->page;
        t->ctx.uc_stack.ss_size = STACK_BYTES;
        t->ctx.uc_link = NULL;
        uintptr_t p = (uintptr_t)t;
        makecontext(&t->ctx, (void (*)(void))entry, 2, (unsigned)(p >> 32),
                    (unsigned)(p & 0xffffffffu));
        t->state = T_READY;
    }
    for (;;) {
        if (idle && idle(ctx, 0))
            duo_wake(d);
        for (int i = 0; i < n; i++)
            if (d->t[i].state == T_READY)
                to_task(d, i); /* back when it asks for a run, waits or returns */
        int a = oldest_waiting(d, -1);
        if (a < 0) {
            int waiting = 0;
            for (int i = 0; i < n; i++)
                waiting |= d->t[i].state == T_IDLE;
            if (!waiting)
                break; /* every task has returned */
            if (!idle || idle(ctx, 1)) /* no run to advance: until something changes */
                duo_wake(d);
            continue;
        }
        /* three or more runs of one kind, with a batched loop: all of them
         * in one batch (one sim a vector lane); else the two oldest paired */
        const wg_sim_core *c = d->t[a].s->core;
        int idx[DUO_MAX], L = same_kind(d, a, idx);
        if (L >= DUO_BATCH_MIN && kbatch_select(c->kflags, c->isa, L))
            advance_batch(d, idx, L);
        else
            advance(d, a, oldest_waiting(d, a));
    }
    duo_free(d);
    return WG_OK;
}

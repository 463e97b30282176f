/* wg_duo.c - tasks on one thread whose sim runs are paired (duo.h).
 *
 * The tasks are coroutines, each on an mmap'd stack with a guard page
 * below it. A task is entered the first time by setcontext (makecontext
 * built it); after that every switch, either way, is sigsetjmp(env, 0) and
 * siglongjmp to the other side's env. swapcontext saved and set the signal
 * mask, a system call each way (about 1 us a switch on the Zen 5 VM,
 * and 74,625 switches in the study), and no task changes the mask. A
 * fortified siglongjmp (__longjmp_chk) refuses a jump to a stack below the
 * current one, so this file is built without _FORTIFY_SOURCE.
 *
 * The scheduler runs on the thread's own stack: it resumes
 * every task that can go on until each has asked for its runs (one or
 * two) or returned, then advances the two runs asked for longest ago with
 * wg_sim_run_pair (three or more of one kind, on a CPU with a batched
 * loop: up to KB_LANES of those, the oldest, with wg_sim_run_batch, one sim
 * a vector lane) until one is done, and resumes its task once none of the
 * task's runs is busy; a run with no partner goes by wg_sim_run. The runs
 * themselves (and their sinks' callbacks) execute on the scheduler's stack.
 * A task in duo_wait is resumed when the idle function says so, or, with
 * none, when no task can go on. Under AddressSanitizer every switch is announced
 * (__sanitizer_start/finish_switch_fiber) so it tracks the stacks. */
#undef _FORTIFY_SOURCE /* before any header: siglongjmp between stacks */
#include "duo.h"
#include "internal.h"
#include "wormgear/wg_status.h"

#include <setjmp.h>
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

/* A run a task asked for (busy until it is done or has failed). */
typedef struct drun {
    wg_sim *s;
    const wg_sink *sink;
    uint64_t n, done, asked; /* asked: order of asking, oldest first */
    int rc, busy;
} drun;

typedef struct task {
    ucontext_t ctx; /* the first entry */
    sigjmp_buf env; /* where it gave way to the scheduler */
    int started;
    char *map;      /* guard page, then the stack */
    size_t maplen;
    duo *d;
    void *arg;
    int state;
    drun r[DUO_RUNS]; /* the runs asked for (T_WAIT: until none is busy) */
} task;

struct duo {
    sigjmp_buf main; /* the scheduler, in to_task */
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
    if (sigsetjmp(d->main, 0) == 0) {
        if (t->started)
            siglongjmp(t->env, 1);
        t->started = 1;
        setcontext(&t->ctx);
    }
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
    if (sigsetjmp(t->env, 0) == 0)
        siglongjmp(d->main, 1);
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

/* The task asks for its runs r[0..k) (n > 0 each) and yields until every
 * one is done or has failed. */
static void ask(task *t, int k)
{
    duo *d = t->d;
    for (int j = 0; j < DUO_RUNS; j++)
        t->r[j].busy = j < k;
    for (int j = 0; j < k; j++)
        t->r[j].done = 0, t->r[j].rc = WG_OK, t->r[j].asked = d->clock++;
    t->state = T_WAIT;
    to_main(t);
}

int duo_run(duo *d, wg_sim *s, uint64_t n, const wg_sink *sink)
{
    task *t = &d->t[d->cur];
    if (n == 0)
        return WG_OK;
    t->r[0].s = s, t->r[0].n = n, t->r[0].sink = sink;
    ask(t, 1);
    return t->r[0].rc;
}

int duo_run2(duo *d, wg_sim *a, wg_sim *b, uint64_t n)
{
    task *t = &d->t[d->cur];
    if (a == b) /* one sim cannot take two runs at once */
        return WG_EINVAL;
    if (n == 0)
        return WG_OK;
    t->r[0] = (drun){.s = a, .n = n};
    t->r[1] = (drun){.s = b, .n = n};
    ask(t, 2);
    return t->r[0].rc != WG_OK ? t->r[0].rc : t->r[1].rc;
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

/* Run ids: task i's run j is i * DUO_RUNS + j. */
static drun *run_of(duo *d, int id) { return &d->t[id / DUO_RUNS].r[id % DUO_RUNS]; }

/* The busy run asked for longest ago other than `not` (-1: none). */
static int oldest_waiting(duo *d, int not)
{
    int best = -1;
    for (int id = 0; id < d->n * DUO_RUNS; id++)
        if (id != not && run_of(d, id)->busy &&
            (best < 0 || run_of(d, id)->asked < run_of(d, best)->asked))
            best = id;
    return best;
}

/* Run `id` took m steps more and returned rc: once it is done (or failed)
 * it is no longer busy, and its task can go on when none of its runs is. */
static void run_moved(duo *d, int id, uint64_t m, int rc)
{
    drun *r = run_of(d, id);
    task *t = &d->t[id / DUO_RUNS];
    r->done += m;
    r->rc = rc;
    if (rc != WG_OK || r->done == r->n)
        r->busy = 0;
    int busy = 0;
    for (int j = 0; j < DUO_RUNS; j++)
        busy |= t->r[j].busy;
    if (!busy)
        t->state = T_READY;
}

/* Advance runs a and b (b < 0: a alone, to its end) until one is done. */
static void advance(duo *d, int a, int b)
{
    drun *ra = run_of(d, a);
    if (b < 0) {
        uint64_t m = 0;
        int rc = wg_sim_run(ra->s, ra->n - ra->done, ra->sink, &m);
        run_moved(d, a, m, rc);
        return;
    }
    drun *rb = run_of(d, b);
    wg_sim *const s[2] = {ra->s, rb->s};
    const uint64_t n[2] = {ra->n - ra->done, rb->n - rb->done};
    const wg_sink *const sk[2] = {ra->sink, rb->sink};
    uint64_t m[2] = {0, 0};
    int rc[2];
    wg_sim_run_pair(s, n, sk, m, rc);
    run_moved(d, a, m[0], rc[0]);
    run_moved(d, b, m[1], rc[1]);
}

/* The busy runs whose sims are of run a's kind, into idx, oldest first (a
 * is the oldest busy run), at most a batch's KB_LANES: how many. */
static int same_kind(duo *d, int a, int idx[KB_LANES])
{
    const wg_sim_core *c = run_of(d, a)->s->core;
    int all[DUO_MAX * DUO_RUNS], L = 0;
    for (int id = 0; id < d->n * DUO_RUNS; id++) {
        const drun *r = run_of(d, id);
        if (!r->busy || r->s->core->kflags != c->kflags || r->s->core->isa != c->isa)
            continue;
        int k = L++;
        for (; k > 0 && run_of(d, all[k - 1])->asked > r->asked; k--)
            all[k] = all[k - 1];
        all[k] = id;
    }
    if (L > KB_LANES)
        L = KB_LANES;
    for (int k = 0; k < L; k++)
        idx[k] = all[k];
    return L;
}

/* Advance runs idx[0..L) in one batch (wg_sim_run_batch) until one is
 * done; as advance. */
static void advance_batch(duo *d, const int idx[], int L)
{
    wg_sim *s[KB_LANES] = {NULL};
    uint64_t n[KB_LANES] = {0}, m[KB_LANES] = {0};
    const wg_sink *sk[KB_LANES] = {NULL};
    int rc[KB_LANES] = {0};
    for (int j = 0; j < L; j++) {
        const drun *r = run_of(d, idx[j]);
        s[j] = r->s, n[j] = r->n - r->done, sk[j] = r->sink;
    }
    wg_sim_run_batch(L, s, n, sk, m, rc);
    for (int j = 0; j < L; j++)
        run_moved(d, idx[j], m[j], rc[j]);
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
        /* three or more runs of one kind, with a batched loop: up to
         * KB_LANES, the oldest, in one batch (one sim a vector lane); else
         * the two oldest paired */
        const wg_sim_core *c = run_of(d, a)->s->core;
        int idx[KB_LANES], L = same_kind(d, a, idx);
        if (L >= DUO_BATCH_MIN && kbatch_select(c->kflags, c->isa, L))
            advance_batch(d, idx, L);
        else
            advance(d, a, oldest_waiting(d, a));
    }
    duo_free(d);
    return WG_OK;
}

/* mon_out.c - a frame writer thread for wgmon: see mon_out.h. */
#include "mon_out.h"

#include "cli.h"
#include "wormgear/wg_file.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <pthread.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

struct mon_out {
    int fd;             /* where frames go */
    int done[2];        /* a byte for each frame written; read end non-blocking */
    pthread_t th;
    pthread_mutex_t mu; /* guards what follows */
    pthread_cond_t cv;
    const char *buf;    /* the frame handed over and not yet taken, or 0 */
    size_t len;
    int busy;           /* a frame handed over and not yet written */
    int err;            /* errno of a failed write, or 0 */
    int quit;
    int abandoned;      /* mon_out_stop gave up on it: it frees itself when its write ends */
};

static void destroy(mon_out *o)
{
    close(o->done[0]), close(o->done[1]);
    pthread_cond_destroy(&o->cv);
    pthread_mutex_destroy(&o->mu);
    free(o);
}

static void *writer(void *arg)
{
    mon_out *o = arg;
    pthread_mutex_lock(&o->mu);
    for (;;) {
        while (!o->buf && !o->quit)
            pthread_cond_wait(&o->cv, &o->mu);
        if (!o->buf || o->abandoned)
            break;
        const char *p = o->buf;
        size_t n = o->len;
        o->buf = 0;
        int fail = o->err;
        pthread_mutex_unlock(&o->mu);
        if (!fail)
            fail = wg_file_write_all(o->fd, p, n); /* may block for as long as the reader likes */
        pthread_mutex_lock(&o->mu);
        o->err = fail;
        o->busy = 0;
        char b = 1;
        while (write(o->done[1], &b, 1) < 0 && errno == EINTR)
            ;
    }
    int gone = o->abandoned;
    pthread_mutex_unlock(&o->mu);
    if (gone)
        destroy(o);
    return 0;
}

mon_out *mon_out_start(int fd)
{
    mon_out *o = calloc(1, sizeof *o);
    if (!o)
        return 0;
    o->fd = fd;
    if (pipe(o->done)) {
        free(o);
        return 0;
    }
    fcntl(o->done[0], F_SETFL, fcntl(o->done[0], F_GETFL) | O_NONBLOCK);
    pthread_mutex_init(&o->mu, 0);
    pthread_cond_init(&o->cv, 0);
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    int rc = pthread_create(&o->th, 0, writer, o);
    pthread_sigmask(SIG_SETMASK, &old, 0);
    if (rc) {
        destroy(o);
        errno = rc;
        return 0;
    }
    return o;
}

int mon_out_send(mon_out *o, const char *buf, size_t len)
{
    pthread_mutex_lock(&o->mu);
    int busy = o->busy;
    if (!busy) {
        o->buf = buf, o->len = len, o->busy = 1;
        pthread_cond_signal(&o->cv);
    }
    pthread_mutex_unlock(&o->mu);
    return busy ? -1 : 0;
}

int mon_out_fd(const mon_out *o) { return o->done[0]; }

int mon_out_busy(mon_out *o)
{
    char b[64];
    while (read(o->done[0], b, sizeof b) > 0)
        ;
    pthread_mutex_lock(&o->mu);
    int busy = o->busy;
    pthread_mutex_unlock(&o->mu);
    return busy;
}

int mon_out_error(mon_out *o)
{
    pthread_mutex_lock(&o->mu);
    int err = o->err;
    pthread_mutex_unlock(&o->mu);
    return err;
}

/* 1 if the frame in flight is written by `end` (monotonic seconds). */
static int written_by(mon_out *o, double end)
{
    struct pollfd p = {.fd = o->done[0], .events = POLLIN};
    for (double left; mon_out_busy(o);) {
        if ((left = end - cli_mono_s()) <= 0)
            return 0;
        poll(&p, 1, (int)(left * 1000) + 1);
    }
    return 1;
}

int mon_out_stop(mon_out *o, double wait_s, const char *last, size_t len)
{
    double end = cli_mono_s() + wait_s;
    int done = written_by(o, end);
    if (done && last && len)
        done = mon_out_send(o, last, len) == 0 && written_by(o, end);
    if (!done)
        pthread_detach(o->th); /* blocked in write(): it ends (and frees o) when that returns */
    pthread_mutex_lock(&o->mu);
    o->quit = 1;
    o->abandoned = !done;
    pthread_cond_signal(&o->cv);
    pthread_mutex_unlock(&o->mu); /* abandoned: o is the writer's from here */
    if (!done)
        return -1;
    pthread_join(o->th, 0);
    destroy(o);
    return 0;
}

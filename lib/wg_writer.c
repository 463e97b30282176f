/* wg_writer.c - a writer thread with a bounded queue of records: see
 * include/wormgear/wg_writer.h. */
#define _GNU_SOURCE /* pipe2 */
#include "wormgear/wg_writer.h"

#include "wormgear/wg_file.h"

#include <errno.h>
#include <fcntl.h>
#include <pthread.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>
#include <unistd.h>

enum { NFD = 8 }; /* fds whose write error is kept */

typedef struct rec {
    struct rec *next;
    int fd;
    size_t n;
    unsigned char b[];
} rec;

struct wg_writer {
    pthread_t th;
    int idle_fd[2];      /* a byte each time the queue is written out; both ends non-blocking */
    size_t cap;
    pthread_mutex_t mu;  /* guards what follows */
    char *note_fmt;      /* tells drops on note_fd; NULL: no notes */
    int note_fd;
    pthread_cond_t more, idle;
    rec *head, *tail;    /* the queue, oldest first */
    size_t used;         /* bytes queued */
    int busy;            /* a record taken and being written */
    struct { int fd, err; } errs[NFD];
    int nerrs;
    unsigned long dropped, untold; /* all drops; those no note has told yet */
    int quit, abandoned;
};

static void drain(rec *r)
{
    while (r) {
        rec *next = r->next;
        free(r);
        r = next;
    }
}

/* Everything freed, and only then the fds closed: a closed wg_writer_fd
 * says an abandoned writer is gone. */
static void destroy(wg_writer *w)
{
    int fd0 = w->idle_fd[0], fd1 = w->idle_fd[1];
    drain(w->head);
    pthread_cond_destroy(&w->idle);
    pthread_cond_destroy(&w->more);
    pthread_mutex_destroy(&w->mu);
    free(w->note_fmt);
    free(w);
    close(fd0), close(fd1);
}

/* Under w->mu: the errno kept for fd, or 0. */
static int err_of(const wg_writer *w, int fd)
{
    for (int i = 0; i < w->nerrs; i++)
        if (w->errs[i].fd == fd)
            return w->errs[i].err;
    return 0;
}

static void *run(void *arg)
{
    wg_writer *w = arg;
    pthread_mutex_lock(&w->mu);
    for (;;) {
        while (!w->head && !w->quit)
            pthread_cond_wait(&w->more, &w->mu);
        if (!w->head || w->abandoned)
            break;
        rec *r = w->head;
        if (!(w->head = r->next))
            w->tail = NULL;
        w->used -= r->n;
        w->busy = 1;
        int skip = err_of(w, r->fd);
        pthread_mutex_unlock(&w->mu);
        int e = skip ? 0 : wg_file_write_all(r->fd, r->b, r->n); /* as long as the reader likes */
        pthread_mutex_lock(&w->mu);
        w->busy = 0;
        if (e && !err_of(w, r->fd) && w->nerrs < NFD)
            w->errs[w->nerrs].fd = r->fd, w->errs[w->nerrs++].err = e;
        free(r);
        if (!w->head) {
            char b = 1;
            if (write(w->idle_fd[1], &b, 1) < 0) { /* full (EAGAIN): readable already */
            }
            pthread_cond_broadcast(&w->idle);
        }
    }
    int gone = w->abandoned;
    pthread_mutex_unlock(&w->mu);
    if (gone) /* wg_writer_stop gave up on it: its memory is its own */
        destroy(w);
    return NULL;
}

wg_writer *wg_writer_start(size_t cap)
{
    wg_writer *w = calloc(1, sizeof *w);
    if (!w)
        return NULL;
    w->cap = cap;
    if (pipe2(w->idle_fd, O_NONBLOCK | O_CLOEXEC)) {
        free(w);
        return NULL;
    }
    pthread_mutex_init(&w->mu, NULL);
    pthread_condattr_t ca;
    pthread_condattr_init(&ca);
    pthread_condattr_setclock(&ca, CLOCK_MONOTONIC);
    pthread_cond_init(&w->more, NULL);
    pthread_cond_init(&w->idle, &ca);
    pthread_condattr_destroy(&ca);
    sigset_t all, old;
    sigfillset(&all);
    pthread_sigmask(SIG_SETMASK, &all, &old);
    int rc = pthread_create(&w->th, NULL, run, w);
    pthread_sigmask(SIG_SETMASK, &old, NULL);
    if (rc) {
        destroy(w);
        errno = rc;
        return NULL;
    }
    return w;
}

int wg_writer_note(wg_writer *w, int fd, const char *fmt)
{
    char *f = fmt ? strdup(fmt) : NULL;
    if (fmt && !f)
        return ENOMEM;
    pthread_mutex_lock(&w->mu);
    char *old = w->note_fmt;
    w->note_fmt = f, w->note_fd = fd;
    pthread_mutex_unlock(&w->mu);
    free(old);
    return 0;
}

/* Under w->mu: a record of n bytes for fd at the queue's end, if it fits. */
static int push(wg_writer *w, int fd, const void *p, size_t n)
{
    if ((w->head || w->busy) && (n > w->cap || w->used > w->cap - n))
        return ENOBUFS;
    rec *r = malloc(sizeof *r + n);
    if (!r)
        return ENOMEM;
    r->next = NULL, r->fd = fd, r->n = n;
    memcpy(r->b, p, n);
    if (w->tail)
        w->tail->next = r;
    else
        w->head = r;
    w->tail = r;
    w->used += n;
    return 0;
}

/* Under w->mu: 1 if records of k and then n bytes both fit in the queue. */
static int both_fit(const wg_writer *w, size_t k, size_t n)
{
    return k <= w->cap && n <= w->cap - k && w->used <= w->cap - k - n;
}

int wg_writer_put(wg_writer *w, int fd, const void *p, size_t n)
{
    pthread_mutex_lock(&w->mu);
    int e = err_of(w, fd);
    if (!e && w->untold && w->note_fmt && !err_of(w, w->note_fd)) {
        char note[256];
        int k = snprintf(note, sizeof note, w->note_fmt, w->untold);
        size_t len = k < 0 ? 0 : (size_t)k < sizeof note ? (size_t)k : sizeof note - 1;
        if (both_fit(w, len, n) && push(w, w->note_fd, note, len) == 0)
            w->untold = 0;
    }
    if (!e && (e = push(w, fd, p, n)) != 0)
        w->dropped++, w->untold++;
    else if (!e)
        pthread_cond_signal(&w->more);
    pthread_mutex_unlock(&w->mu);
    return e;
}

int wg_writer_fd(const wg_writer *w) { return w->idle_fd[0]; }

int wg_writer_idle(wg_writer *w)
{
    char b[64];
    while (read(w->idle_fd[0], b, sizeof b) > 0)
        ;
    pthread_mutex_lock(&w->mu);
    int idle = !w->head && !w->busy;
    pthread_mutex_unlock(&w->mu);
    return idle;
}

int wg_writer_error(wg_writer *w, int fd)
{
    pthread_mutex_lock(&w->mu);
    int e = err_of(w, fd);
    pthread_mutex_unlock(&w->mu);
    return e;
}

unsigned long wg_writer_dropped(wg_writer *w)
{
    pthread_mutex_lock(&w->mu);
    unsigned long d = w->dropped;
    pthread_mutex_unlock(&w->mu);
    return d;
}

int wg_writer_stop(wg_writer *w, double wait_s)
{
    struct timespec end;
    clock_gettime(CLOCK_MONOTONIC, &end);
    wait_s = wait_s > 0 ? wait_s : 0;
    end.tv_sec += (time_t)wait_s;
    end.tv_nsec += (long)((wait_s - (double)(time_t)wait_s) * 1e9);
    if (end.tv_nsec >= 1000000000)
        end.tv_sec++, end.tv_nsec -= 1000000000;
    pthread_mutex_lock(&w->mu);
    while ((w->head || w->busy) && pthread_cond_timedwait(&w->idle, &w->mu, &end) != ETIMEDOUT)
        ;
    int left = w->head || w->busy;
    w->quit = 1;
    w->abandoned = left;
    if (left)
        pthread_detach(w->th);
    pthread_cond_signal(&w->more);
    pthread_mutex_unlock(&w->mu); /* abandoned: w is the thread's from here */
    if (left)
        return -1;
    pthread_join(w->th, NULL);
    destroy(w);
    return 0;
}

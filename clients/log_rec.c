/* log_rec.c - record an LCM bus to a log file (wglog record; log_rec.h). */
#include "log_rec.h"

#include "bus.h"
#include "cli.h"
#include "wormgear/wg_mcast.h"

#include <errno.h>
#include <fcntl.h>
#include <lcm/eventlog.h>
#include <lcm/lcm.h>
#include <signal.h>
#include <stdint.h>
#include <stdio.h>
#include <string.h>
#include <unistd.h>

#define PROG "wglog"

static volatile sig_atomic_t rec_stop; /* set by the signal handler only */

static void on_signal(int sig)
{
    (void)sig;
    rec_stop = 1;
}

typedef struct rec {
    const log_rec_opts *o;
    lcm_eventlog_t *log;
    long long kept, left_out, bytes;
    long long flushed; /* messages in the file for sure: kept at the last flush */
    int write_errno; /* a write failed: its errno (0: none) */
} rec;

static void on_msg(const lcm_recv_buf_t *rb, const char *channel, void *user)
{
    rec *r = user;
    if (r->write_errno)
        return;
    if (r->o->re && regexec(r->o->re, channel, 0, NULL, 0)) {
        r->left_out++;
        return;
    }
    lcm_eventlog_event_t ev = {.timestamp = rb->recv_utime,
                               .channellen = (int32_t)strlen(channel),
                               .datalen = (int32_t)rb->data_size,
                               .channel = (char *)channel,
                               .data = rb->data};
    errno = 0;
    if (lcm_eventlog_write_event(r->log, &ev)) {
        r->write_errno = errno ? errno : EIO;
        return;
    }
    r->kept++;
    r->bytes += rb->data_size;
}

/* The log's file, created (or, with --force, emptied) before LCM opens it:
 * 0, or 1 said. */
static int make_file(const log_rec_opts *o)
{
    int fd = open(o->path, O_WRONLY | O_CREAT | (o->force ? O_TRUNC : O_EXCL), 0666);
    if (fd < 0) {
        if (errno == EEXIST)
            fprintf(stderr, "wglog: %s exists; give another name, or --force to overwrite it\n",
                    o->path);
        else
            fprintf(stderr, "wglog: cannot create %s: %s\n", o->path, strerror(errno));
        return 1;
    }
    close(fd);
    return 0;
}

/* LCM on the URL, every channel subscribed and its socket filtered: the
 * handle, or NULL said, with *rc CLI_EUSAGE for a URL LCM refuses or port 0
 * (as every client takes them), else 1. */
static lcm_t *open_bus(const log_rec_opts *o, rec *r, int *rc)
{
    char why[512] = "";
    lcm_t *lcm = bus_lcm_open(o->url, rc, why, sizeof why);
    if (!lcm) {
        fprintf(stderr, "wglog: %s\n", why);
        *rc = bus_exit_status(*rc);
        return NULL;
    }
    *rc = 1;
    if (!lcm_subscribe(lcm, ".*", on_msg, r) ||
        wg_mcast_guard(o->url, WG_MCAST_FRAGMENTS, why, sizeof why)) {
        fprintf(stderr, "wglog: %s: %s\n", o->url,
                *why ? why : "LCM could not subscribe (its reason is above)");
        lcm_destroy(lcm);
        return NULL;
    }
    return lcm;
}

/* What was written reached the file: 0, or the errno of the failed write. */
static int flush_log(rec *r)
{
    if (!r->write_errno && fflush(r->log->f))
        r->write_errno = errno ? errno : EIO;
    if (!r->write_errno)
        r->flushed = r->kept;
    return r->write_errno;
}

static int record(const log_rec_opts *o, rec *r, lcm_t *lcm)
{
    double t0 = cli_mono_s(), next_flush = t0 + 0.25;
    if (!o->quiet)
        fprintf(stderr, "wglog: recording %s to %s (%s)%s; SIGINT (Ctrl-C) stops\n", o->url,
                o->path, o->re ? "channels matching --channel" : "every channel",
                o->duration_s > 0 ? ", for --duration" : "");
    while (!rec_stop) {
        double now = cli_mono_s(), left = o->duration_s > 0 ? t0 + o->duration_s - now : 1;
        if (left <= 0)
            break;
        int ms = left < 0.1 ? (int)(left * 1000) + 1 : 100;
        if (lcm_handle_timeout(lcm, ms) < 0 && !rec_stop) {
            fprintf(stderr, "wglog: receiving from %s failed\n", o->url);
            return 1;
        }
        if (r->write_errno || cli_mono_s() >= next_flush) {
            if (flush_log(r))
                break;
            next_flush = cli_mono_s() + 0.25;
        }
    }
    int err = flush_log(r);
    if (err) {
        fprintf(stderr, "wglog: writing %s failed: %s; the file holds the %lld messages "
                "written before the last flush that succeeded\n", o->path, strerror(err),
                r->flushed);
        return 1;
    }
    if (o->quiet)
        return 0;
    double s = cli_mono_s() - t0;
    if (r->kept)
        fprintf(stderr, "wglog: recorded %lld messages (%lld bytes) in %.1f s to %s; `wglog "
                "summary %s` lists them\n", r->kept, r->bytes, s, o->path, o->path);
    else
        fprintf(stderr, "wglog: recorded no message in %.1f s: nothing %swas heard on %s "
                "(is wormgeard running with this URL? `wgctl --url '%s' status` asks it)\n",
                s, r->left_out ? "matching --channel " : "", o->url, o->url);
    if (r->left_out)
        fprintf(stderr, "wglog: %lld messages on channels not matching --channel left out\n",
                r->left_out);
    return 0;
}

int log_rec_run(const log_rec_opts *o)
{
    rec r = {.o = o};
    int rc;
    lcm_t *lcm = open_bus(o, &r, &rc); /* first: a refused URL leaves no file behind */
    if (!lcm)
        return rc;
    rc = make_file(o);
    if (!rc && !(r.log = lcm_eventlog_create(o->path, "w"))) {
        fprintf(stderr, "wglog: cannot write %s: %s\n", o->path, strerror(errno));
        rc = 1;
    }
    if (!rc) { /* LCM calls on_msg only from lcm_handle, so not before r.log is set */
        cli_on_stop_signals(on_signal);
        rc = record(o, &r, lcm);
        lcm_eventlog_destroy(r.log);
    }
    lcm_destroy(lcm);
    return rc;
}

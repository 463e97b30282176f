/* wg_writer.h - bytes for a terminal or a pipe, written by a thread of
 * their own, so that a reader that takes nothing never stops the caller.
 *
 * A terminal stopped with Ctrl-S, a stalled ssh session or a pipe no one
 * reads blocks write() for as long as it likes. A program that writes from
 * the loop that also reads the bus, paces a simulation or drives a rig
 * stops with it: wormgeard answered no command for 30 s, wgmon held up to
 * +0.9 GB of queued LCM messages, wgrig's sweep stood still. Each of them
 * hands its lines (or frames) to a writer instead:
 *
 *  - wg_writer_put copies the bytes into a queue of at most `cap` bytes and
 *    returns at once; the writer's thread writes them whole and in order.
 *    A record that does not fit is dropped and counted (the queue bounds
 *    the memory a reader that takes nothing can cost), except that an
 *    empty queue takes a record of any size (a frame larger than cap).
 *  - The next record that fits after drops is preceded by a note with
 *    their count, when wg_writer_note asked for one.
 *  - wg_writer_fd turns readable when the queue has been written out, for
 *    a loop that waits in select/poll and renders only when it is idle.
 *  - wg_writer_stop waits a bounded time for the queue to be written, and
 *    otherwise leaves the thread blocked in write(): it frees itself when
 *    that write returns, or ends with the process.
 *
 * The thread blocks every signal (they go to the caller's threads) and
 * inherits the caller's scheduling policy. One writer may serve several
 * fds; a write error on one (EPIPE, EIO) is kept for that fd, and later
 * records for it are refused with it. */
#ifndef WG_WRITER_H
#define WG_WRITER_H

#include <stddef.h>

typedef struct wg_writer wg_writer;

/* Start a writer with a queue of cap bytes: the writer, or NULL (errno
 * set). */
wg_writer *wg_writer_start(size_t cap);

/* From now on, records dropped are told on fd by fmt (a printf format
 * with one %lu, their count; copied) ahead of the next record that fits
 * with it; NULL: not told. 0, or ENOMEM (the note as it was). */
int wg_writer_note(wg_writer *w, int fd, const char *fmt);

/* Queue n bytes at p for fd (copied: p is the caller's again at once).
 * 0 queued; ENOBUFS dropped and counted (the queue full); ENOMEM dropped
 * and counted; or the errno of an earlier failed write to fd (refused, not
 * counted). */
int wg_writer_put(wg_writer *w, int fd, const void *p, size_t n);

/* A descriptor that turns readable each time the queue has been written
 * out (wg_writer_idle reads it). */
int wg_writer_fd(const wg_writer *w);

/* 1 when nothing is queued or being written; reads wg_writer_fd, so that a
 * select loop does not spin on it. */
int wg_writer_idle(wg_writer *w);

/* The errno of the write to fd that failed, or 0. */
int wg_writer_error(wg_writer *w, int fd);

/* Records dropped so far (those told by a note included). */
unsigned long wg_writer_dropped(wg_writer *w);

/* Wait wait_s seconds at most for the queue to be written, then end the
 * writer: 0, w freed. -1 if it is still blocked in write(): w is then the
 * thread's, which frees it when that write returns; a caller about to exit
 * should do so without more output to that fd (it would block too). */
int wg_writer_stop(wg_writer *w, double wait_s);

#endif

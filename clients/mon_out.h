/* mon_out.h - wgmon's frames written by a thread of their own, so that a
 * terminal that does not take them (Ctrl-S, a stalled ssh session, a pipe
 * no one reads) never stops the monitor's loop. That loop must go on
 * reading the bus: LCM queues what arrives for a subscription until the
 * loop handles it, so a monitor blocked in write() would hold up to its
 * queue's depth of messages of any size a sender on the group chose
 * (measured: +0.9 GB in 30 s of 1 MB messages, +0.6 GB in 4 s of 250 kB
 * ones; clients.wgmon floods a stalled monitor).
 *
 * One frame is in flight at a time: the caller hands it over and must
 * not touch its bytes until the writer says it is written (the fd of
 * mon_out_fd turns readable; then mon_out_busy is 0). */
#ifndef WG_MON_OUT_H
#define WG_MON_OUT_H

#include <stddef.h>

typedef struct mon_out mon_out;

/* Start a writer for fd, with every signal blocked in its thread (they go
 * to the caller's). 0 (errno set) if it cannot. */
mon_out *mon_out_start(int fd);

/* Hand over len bytes at buf: 0, or -1 if a frame is still in flight. */
int mon_out_send(mon_out *o, const char *buf, size_t len);

/* Readable when a frame has been written: wait on it with select/poll. */
int mon_out_fd(const mon_out *o);

/* 1 while a frame is in flight (reads what the fd has signalled). */
int mon_out_busy(mon_out *o);

/* errno of the write that failed (the writer then writes nothing more),
 * or 0. */
int mon_out_error(mon_out *o);

/* End the writer once the frame in flight and then the len bytes at last
 * (if any: a terminal's closing escapes) are written, waiting wait_s
 * seconds at most: 0, o freed. -1 if it is still blocked in write(): it
 * then frees o itself when that write returns, reading the frame (keep it)
 * until then; a caller that ends the process should do so without more
 * output (another thread's may block on that terminal too). */
int mon_out_stop(mon_out *o, double wait_s, const char *last, size_t len);

#endif

/* inbox.h - commands received and not yet handled, in arrival order.
 *
 * LCM's udpm receive thread has 2,000 receive buffers: while the loop is
 * busy, a burst of commands fills them, the thread stops reading, and the
 * kernel drops what follows (issue 10, defect 5). So the CMD callback only
 * copies the raw message here (a byte ring, no allocation after init) and
 * returns the buffer to LCM at once; the loop handles what waits here
 * between chunks of stepping. What does not fit is counted, never lost
 * silently (STATUS cmds_dropped). */
#ifndef WGD_INBOX_H
#define WGD_INBOX_H

#include <stddef.h>
#include <stdint.h>

enum {
    INBOX_BYTES = 4 << 20,  /* ring size: thousands of commands */
    INBOX_MSG_MAX = 65536   /* a larger message is refused, not queued */
};

typedef struct inbox {
    unsigned char *ring;
    size_t cap, head, tail, used; /* bytes; records [uint32 len][len bytes] */
    uint64_t queued, dropped;     /* messages taken in; refused for lack of room */
    size_t peak;                  /* most bytes in use at once */
} inbox;

/* Allocate the ring of cap bytes. 0, or -1 out of memory. */
int inbox_init(inbox *q, size_t cap);

/* Free the ring. Safe on a zeroed inbox. */
void inbox_fini(inbox *q);

/* Append a message of n bytes (n <= INBOX_MSG_MAX). 0, or -1 when it does
 * not fit (counted in dropped). */
int inbox_push(inbox *q, const void *msg, size_t n);

/* Take the oldest message into out (room for INBOX_MSG_MAX bytes) and its
 * length into *n (an empty message has 0): 1, or 0 when none waits. */
int inbox_pop(inbox *q, void *out, size_t *n);

/* Messages waiting (0 when empty). */
int inbox_waiting(const inbox *q);

#endif

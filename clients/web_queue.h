/* web_queue.h - bounded per-client send queues of shared messages.
 *
 * A message is encoded once and shared by every client queue that holds it
 * (reference counted). A queue is bounded in count and bytes: pushing onto
 * a full queue drops the oldest entries and counts them, so a slow or
 * stalled client never holds up the bridge or another client. */
#ifndef WEB_QUEUE_H
#define WEB_QUEUE_H

#include <stddef.h>
#include <stdint.h>

/* An encoded payload, shared by reference count. */
typedef struct wq_msg {
    int refs;
    size_t len;
    unsigned char data[]; /* len bytes, then a NUL */
} wq_msg;

/* What to send: a text frame (kind WQ_TEXT, the payload as is), a Message
 * Data frame (WQ_DATA: subscription id and timestamp in front) or a Time
 * frame (WQ_TIME: timestamp only, no payload). */
enum { WQ_TEXT, WQ_DATA, WQ_TIME };
typedef struct wq_item {
    wq_msg *m;       /* NULL for WQ_TIME */
    uint64_t ts_ns;  /* WQ_DATA, WQ_TIME */
    uint32_t sub_id; /* WQ_DATA */
    int kind;
} wq_item;

typedef struct wq {
    wq_item *ring;
    size_t cap, head, count;
    size_t bytes, max_bytes;
    uint64_t dropped; /* entries dropped because the queue was full */
} wq;

/* A new message holding a copy of len bytes (refs 1), or NULL. */
wq_msg *wq_msg_new(const void *p, size_t len);

/* Drop one reference; frees at zero. NULL is ignored. */
void wq_msg_unref(wq_msg *m);

/* An empty queue of at most cap entries and max_bytes payload bytes.
 * 0, or -1 when out of memory. */
int wq_init(wq *q, size_t cap, size_t max_bytes);

/* Unreference every entry and free the ring. */
void wq_fini(wq *q);

/* Append it (the queue takes a reference of it.m). Drops the oldest while
 * the queue is full; returns the number dropped. */
size_t wq_push(wq *q, wq_item it);

/* Whether it would fit without dropping anything. */
int wq_fits(const wq *q, const wq_item *it);

/* Take the oldest entry into *out (the caller owns its reference): 1, or 0
 * when empty. */
int wq_pop(wq *q, wq_item *out);

#endif

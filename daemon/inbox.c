/* inbox.c - a byte ring of raw command messages. */
#include "inbox.h"

#include <stdlib.h>
#include <string.h>

enum { HDR = 4 };
#define WRAP 0xffffffffu /* a record header meaning "continue at offset 0" */

int inbox_init(inbox *q, size_t cap)
{
    memset(q, 0, sizeof *q);
    q->ring = malloc(cap);
    q->cap = q->ring ? cap : 0;
    return q->ring ? 0 : -1;
}

void inbox_fini(inbox *q)
{
    free(q->ring);
    memset(q, 0, sizeof *q);
}

static void put_u32(unsigned char *p, uint32_t v) { memcpy(p, &v, HDR); }

static uint32_t get_u32(const unsigned char *p)
{
    uint32_t v;
    memcpy(&v, p, HDR);
    return v;
}

/* Room for a record of need bytes at the tail, wrapping if the end is too
 * short (the skipped end counts as used until the head passes it). */
static int make_room(inbox *q, size_t need)
{
    size_t end = q->cap - q->tail;
    if (q->used && q->tail <= q->head) /* the free space is [tail, head) */
        return q->head - q->tail >= need ? 0 : -1;
    if (end >= need)
        return 0;
    if (q->head < need)
        return -1;
    if (end >= HDR)
        put_u32(q->ring + q->tail, WRAP);
    q->used += end;
    q->tail = 0;
    return 0;
}

int inbox_push(inbox *q, const void *msg, size_t n)
{
    size_t need = HDR + n;
    if (n > INBOX_MSG_MAX || q->cap - q->used < need || make_room(q, need)) {
        q->dropped++;
        return -1;
    }
    put_u32(q->ring + q->tail, (uint32_t)n);
    memcpy(q->ring + q->tail + HDR, msg, n);
    q->tail = (q->tail + need) % q->cap;
    q->used += need;
    q->queued++;
    q->peak = q->used > q->peak ? q->used : q->peak;
    return 0;
}

int inbox_pop(inbox *q, void *out, size_t *len)
{
    if (!q->used)
        return 0;
    if (q->cap - q->head < HDR || get_u32(q->ring + q->head) == WRAP) {
        q->used -= q->cap - q->head;
        q->head = 0;
    }
    uint32_t n = get_u32(q->ring + q->head);
    memcpy(out, q->ring + q->head + HDR, n);
    q->head = (q->head + HDR + n) % q->cap;
    q->used -= HDR + n;
    if (!q->used)
        q->head = q->tail = 0;
    *len = n;
    return 1;
}

int inbox_waiting(const inbox *q) { return q->used != 0; }

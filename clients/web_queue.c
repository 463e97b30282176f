/* web_queue.c - bounded drop-oldest queues of shared messages. */
#include "web_queue.h"

#include <stdlib.h>
#include <string.h>

wq_msg *wq_msg_new(const void *p, size_t len)
{
    wq_msg *m = malloc(sizeof *m + len + 1);
    if (!m)
        return NULL;
    m->refs = 1;
    m->len = len;
    if (len)
        memcpy(m->data, p, len);
    m->data[len] = '\0';
    return m;
}

void wq_msg_unref(wq_msg *m)
{
    if (m && --m->refs == 0)
        free(m);
}

int wq_init(wq *q, size_t cap, size_t max_bytes)
{
    memset(q, 0, sizeof *q);
    q->ring = calloc(cap ? cap : 1, sizeof *q->ring);
    if (!q->ring)
        return -1;
    q->cap = cap ? cap : 1;
    q->max_bytes = max_bytes;
    return 0;
}

void wq_fini(wq *q)
{
    wq_item it;
    while (wq_pop(q, &it))
        wq_msg_unref(it.m);
    free(q->ring);
    memset(q, 0, sizeof *q);
}

static size_t item_bytes(const wq_item *it) { return it->m ? it->m->len : 0; }

int wq_fits(const wq *q, const wq_item *it)
{
    return q->count < q->cap && q->bytes + item_bytes(it) <= q->max_bytes;
}

size_t wq_push(wq *q, wq_item it)
{
    size_t dropped = 0;
    wq_item old;
    while (q->count && !wq_fits(q, &it) && wq_pop(q, &old)) {
        wq_msg_unref(old.m);
        dropped++;
    }
    q->dropped += dropped;
    if (!wq_fits(q, &it)) { /* larger than the whole queue: drop it */
        q->dropped++;
        return dropped + 1;
    }
    if (it.m)
        it.m->refs++;
    q->ring[(q->head + q->count) % q->cap] = it;
    q->count++;
    q->bytes += item_bytes(&it);
    return dropped;
}

int wq_pop(wq *q, wq_item *out)
{
    if (!q->count)
        return 0;
    *out = q->ring[q->head];
    q->head = (q->head + 1) % q->cap;
    q->count--;
    q->bytes -= item_bytes(out);
    return 1;
}

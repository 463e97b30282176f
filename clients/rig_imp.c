/* rig_imp.c - mesh impacts by period (see rig_imp.h). */
#include "rig_imp.h"

#include <stdlib.h>

void rig_imp_init(rig_imp *m)
{
    *m = (rig_imp){.last = -1};
}

void rig_imp_heard(rig_imp *m, int64_t p)
{
    m->last = p > m->last ? p : m->last;
}

void rig_imp_lose(rig_imp *m, int64_t p)
{
    if (m->nlost < RIG_IMP_LOST_MAX) {
        m->lost[m->nlost][0] = m->last;
        m->lost[m->nlost][1] = p;
    }
    m->nlost++;
}

int rig_imp_lost(const rig_imp *m, int64_t p0, int64_t p1)
{
    if (m->nlost > RIG_IMP_LOST_MAX)
        return 1;
    for (int i = 0; i < m->nlost; i++)
        if (m->lost[i][0] <= p1 && m->lost[i][1] >= p0)
            return 1;
    return 0;
}

int rig_imp_push(rig_imp *m, int64_t p)
{
    if (m->n == m->cap) {
        size_t cap = m->cap ? 2 * m->cap : 4096;
        int64_t *np = cap < (size_t)1 << 28 ? realloc(m->period, cap * sizeof *np) : NULL;
        if (!np)
            return -1;
        m->period = np, m->cap = cap;
    }
    m->period[m->n++] = p;
    m->sorted = 0;
    return 0;
}

static int cmp64(const void *a, const void *b)
{
    int64_t x = *(const int64_t *)a, y = *(const int64_t *)b;
    return (x > y) - (x < y);
}

long rig_imp_count(rig_imp *m, int64_t p0, int64_t p1)
{
    if (!m->sorted && m->n) /* none yet: period is NULL, which qsort may not take */
        qsort(m->period, m->n, sizeof *m->period, cmp64);
    m->sorted = 1;
    size_t lo = 0, hi = m->n;
    while (lo < hi) { /* the first impact at or after p0 */
        size_t mid = lo + (hi - lo) / 2;
        if (m->period[mid] < p0)
            lo = mid + 1;
        else
            hi = mid;
    }
    long n = 0;
    for (size_t i = lo; i < m->n && m->period[i] <= p1; i++)
        n++;
    return n;
}

void rig_imp_fini(rig_imp *m)
{
    free(m->period);
    rig_imp_init(m);
}

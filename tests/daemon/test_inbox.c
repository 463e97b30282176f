/* test_inbox.c - the command inbox against a model queue: random pushes
 * and pops of random sizes in a small ring (every wrap case), order and
 * bytes kept, full means refused and counted, never corrupted. */
#include "inbox.h"
#include "test.h"

#include <stdint.h>
#include <time.h>

enum { CAP = 8192, MAXQ = 4096 };

static void test_against_a_model(void)
{
    inbox q;
    ASSERT_EQ_INT(inbox_init(&q, CAP), 0);
    static unsigned char out[INBOX_MSG_MAX];
    static size_t len[MAXQ];
    static unsigned seedof[MAXQ];
    unsigned seed = test_seed("queue:");
    srand(seed);
    int head = 0, tail = 0, refused = 0;
    for (int step = 0; step < 200000; step++) {
        if (rand() % 100 < 55 && tail - head < MAXQ) {
            size_t n = (size_t)(rand() % 3 == 0 ? rand() % 3000 : rand() % 200);
            unsigned sd = (unsigned)rand();
            unsigned char msg[3000];
            for (size_t i = 0; i < n; i++)
                msg[i] = (unsigned char)(sd + i * 7);
            uint64_t dropped = q.dropped;
            if (inbox_push(&q, msg, n) == 0) {
                len[tail % MAXQ] = n, seedof[tail % MAXQ] = sd, tail++;
            } else {
                refused++;
                ASSERT_EQ_INT(q.dropped, dropped + 1);
            }
        } else if (head < tail) {
            size_t n = 99999;
            ASSERT_EQ_INT(inbox_pop(&q, out, &n), 1);
            ASSERT_EQ_INT(n, len[head % MAXQ]);
            for (size_t i = 0; i < n; i++)
                if (out[i] != (unsigned char)(seedof[head % MAXQ] + i * 7)) {
                    TEST_FAIL_("message %d byte %zu differs", head, i);
                    break;
                }
            head++;
        } else {
            size_t n;
            ASSERT_EQ_INT(inbox_pop(&q, out, &n), 0);
            ASSERT_EQ_INT(inbox_waiting(&q), 0);
        }
        ASSERT_TRUE(q.used <= CAP);
    }
    ASSERT_TRUE(refused > 0); /* the ring did fill up */
    printf("  %d refused for lack of room, peak %zu of %d bytes\n", refused, q.peak, CAP);
    ASSERT_EQ_INT(inbox_push(&q, out, INBOX_MSG_MAX + 1), -1); /* too large */
    inbox_fini(&q);
}

TEST_MAIN(TEST(test_against_a_model))

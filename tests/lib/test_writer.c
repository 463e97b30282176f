/* test_writer.c - the writer thread (lib/wg_writer.c): records reach their
 * fds whole and in order; a reader that takes nothing never blocks the
 * caller, the queue holds at most its cap (an empty queue takes a record of
 * any size), drops are counted and told once by a note ahead of the next
 * record that fits; wg_writer_stop gives up in the time it is given and the
 * thread then frees itself once its write returns; a reader gone is an
 * error kept for that fd only, not a crash (SIGPIPE ignored, as the daemon
 * and the clients do). */
#include "test.h"
#include "wormgear/wg_writer.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <sys/ioctl.h>
#include <unistd.h>

static double mono_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

/* Wait (5 s at most) on wg_writer_fd until the queue is written out. */
static int wait_idle(wg_writer *w)
{
    struct pollfd p = {.fd = wg_writer_fd(w), .events = POLLIN};
    for (double end = mono_s() + 5; !wg_writer_idle(w);)
        if (mono_s() > end || poll(&p, 1, 100) < 0)
            return 0;
    return 1;
}

/* Read exactly n bytes from fd into buf (5 s at most): the count read. */
static size_t read_n(int fd, char *buf, size_t n)
{
    size_t got = 0;
    struct pollfd p = {.fd = fd, .events = POLLIN};
    for (double end = mono_s() + 5; got < n && mono_s() < end;) {
        if (poll(&p, 1, 100) <= 0)
            continue;
        ssize_t r = read(fd, buf + got, n - got);
        if (r <= 0)
            break;
        got += (size_t)r;
    }
    return got;
}

/* 1 once the pipe read at fd holds 64 KiB (its default capacity), 5 s at most. */
static int pipe_full(int fd)
{
    int n = 0;
    for (double end = mono_s() + 5; mono_s() < end; usleep(1000))
        if (ioctl(fd, FIONREAD, &n) == 0 && n >= 65536)
            return 1;
    return 0;
}

static void test_records_in_order(void)
{
    int a[2], b[2];
    ASSERT_TRUE(pipe(a) == 0 && pipe(b) == 0);
    wg_writer *w = wg_writer_start(4096);
    ASSERT_TRUE(w != NULL);
    ASSERT_EQ_INT(wg_writer_idle(w), 1);
    struct pollfd pf = {.fd = wg_writer_fd(w), .events = POLLIN};
    ASSERT_EQ_INT(wg_writer_put(w, a[1], "one|", 4), 0);
    ASSERT_EQ_INT(poll(&pf, 1, 5000), 1); /* readable once written out */
    ASSERT_EQ_INT(wg_writer_idle(w), 1);
    ASSERT_EQ_INT(poll(&pf, 1, 0), 0); /* and read by wg_writer_idle: no select loop spins */
    ASSERT_EQ_INT(wg_writer_put(w, b[1], "two|", 4), 0);
    ASSERT_EQ_INT(wg_writer_put(w, a[1], "three|", 6), 0);
    ASSERT_TRUE(wait_idle(w));
    ASSERT_EQ_INT(wg_writer_put(w, b[1], "four|", 5), 0);
    ASSERT_EQ_INT(wg_writer_stop(w, 5), 0);
    char got[64] = {0};
    ASSERT_EQ_INT(read_n(a[0], got, 10), 10);
    ASSERT_STR(got, "one|three|");
    memset(got, 0, sizeof got);
    ASSERT_EQ_INT(read_n(b[0], got, 9), 9);
    ASSERT_STR(got, "two|four|");
    close(a[0]), close(a[1]), close(b[0]), close(b[1]);
}

/* A pipe no one reads: puts return at once, the queue holds its cap and
 * no more (drops counted), the note tells them once ahead of the next
 * record that fits after the reader came back. */
static void test_bounded_and_told(void)
{
    int p[2];
    ASSERT_TRUE(pipe(p) == 0);
    enum { BIG = 1 << 20 }; /* 16 times a pipe's buffer */
    char *big = malloc(BIG), *got = malloc(BIG + 256);
    ASSERT_TRUE(big && got);
    memset(big, 'x', BIG);
    wg_writer *w = wg_writer_start(100);
    ASSERT_TRUE(w != NULL);
    ASSERT_EQ_INT(wg_writer_note(w, p[1], "[%lu dropped]"), 0);
    double t0 = mono_s();
    ASSERT_EQ_INT(wg_writer_put(w, p[1], big, BIG), 0); /* an empty queue takes any size */
    char a[60], c[30], d[20];
    memset(a, 'a', sizeof a), memset(c, 'c', sizeof c), memset(d, 'd', sizeof d);
    ASSERT_TRUE(pipe_full(p[0])); /* the writer has taken the big one and is blocked */
    ASSERT_EQ_INT(wg_writer_put(w, p[1], a, sizeof a), 0);
    ASSERT_EQ_INT(wg_writer_put(w, p[1], a, sizeof a), ENOBUFS); /* 120 > 100 */
    ASSERT_EQ_INT(wg_writer_put(w, p[1], c, sizeof c), 0);       /* 90 */
    ASSERT_EQ_INT(wg_writer_put(w, p[1], d, sizeof d), ENOBUFS); /* 110 */
    ASSERT_EQ_INT(wg_writer_put(w, p[1], big, BIG), ENOBUFS);    /* not empty: the cap holds */
    ASSERT_TRUE(mono_s() - t0 < 0.5);
    ASSERT_EQ_INT(wg_writer_dropped(w), 3);
    ASSERT_EQ_INT(wg_writer_idle(w), 0);
    size_t n = read_n(p[0], got, BIG + 90);
    ASSERT_EQ_INT(n, BIG + 90);
    ASSERT_TRUE(wait_idle(w));
    ASSERT_EQ_INT(wg_writer_put(w, p[1], "z", 1), 0);
    ASSERT_EQ_INT(wg_writer_put(w, p[1], "y", 1), 0); /* told once */
    ASSERT_EQ_INT(wg_writer_stop(w, 5), 0);
    memset(got, 0, BIG + 256);
    ASSERT_EQ_INT(read_n(p[0], got, 13), 13);
    ASSERT_STR(got, "[3 dropped]zy");
    free(big), free(got);
    close(p[0]), close(p[1]);
}

/* stop gives up in its time on a writer blocked in write(); once the
 * reader drains the pipe the thread ends and closes its own fds. */
static void test_stop_gives_up(void)
{
    int p[2];
    ASSERT_TRUE(pipe(p) == 0);
    enum { BIG = 1 << 20 };
    char *big = malloc(BIG);
    ASSERT_TRUE(big != NULL);
    memset(big, 'x', BIG);
    wg_writer *w = wg_writer_start(1 << 16);
    ASSERT_TRUE(w != NULL);
    int wfd = wg_writer_fd(w);
    ASSERT_EQ_INT(wg_writer_put(w, p[1], big, BIG), 0);
    ASSERT_TRUE(pipe_full(p[0]));
    ASSERT_EQ_INT(wg_writer_put(w, p[1], "bye", 3), 0); /* queued behind it, never written */
    double t0 = mono_s();
    ASSERT_EQ_INT(wg_writer_stop(w, 0.3), -1);
    double took = mono_s() - t0;
    printf("  stop gave up after %.2f s\n", took);
    ASSERT_TRUE(took >= 0.29 && took < 2.0);
    char buf[65536];
    size_t got = 0;
    ssize_t r;
    while (got < BIG && (r = read(p[0], buf, sizeof buf)) > 0)
        got += (size_t)r;
    ASSERT_EQ_INT(got, BIG);
    t0 = mono_s();
    while (fcntl(wfd, F_GETFD) != -1 && mono_s() - t0 < 5)
        usleep(10000);
    ASSERT_TRUE(fcntl(wfd, F_GETFD) == -1 && errno == EBADF);
    free(big);
    close(p[0]), close(p[1]);
}

/* A reader gone: EPIPE, kept for that fd (later records refused with it,
 * not counted as drops); another fd still written. */
static void test_reader_gone(void)
{
    signal(SIGPIPE, SIG_IGN);
    int a[2], b[2];
    ASSERT_TRUE(pipe(a) == 0 && pipe(b) == 0);
    close(a[0]);
    wg_writer *w = wg_writer_start(4096);
    ASSERT_TRUE(w != NULL);
    ASSERT_EQ_INT(wg_writer_note(w, b[1], "%lu dropped"), 0);
    ASSERT_EQ_INT(wg_writer_put(w, a[1], "lost", 4), 0);
    ASSERT_TRUE(wait_idle(w));
    ASSERT_EQ_INT(wg_writer_error(w, a[1]), EPIPE);
    ASSERT_EQ_INT(wg_writer_error(w, b[1]), 0);
    ASSERT_EQ_INT(wg_writer_put(w, a[1], "more", 4), EPIPE);
    ASSERT_EQ_INT(wg_writer_put(w, b[1], "ok", 2), 0);
    ASSERT_EQ_INT(wg_writer_dropped(w), 0);
    ASSERT_EQ_INT(wg_writer_stop(w, 5), 0);
    char got[16] = {0};
    ASSERT_EQ_INT(read_n(b[0], got, 2), 2);
    ASSERT_STR(got, "ok");
    close(a[1]), close(b[0]), close(b[1]);
}

TEST_MAIN(TEST(test_records_in_order), TEST(test_bounded_and_told), TEST(test_stop_gives_up),
          TEST(test_reader_gone))

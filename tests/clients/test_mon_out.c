/* test_mon_out.c - wgmon's frame writer (clients/mon_out.c): frames reach
 * the fd whole and in order, one in flight at a time; a reader that takes
 * nothing never blocks the caller, and mon_out_stop gives up on it in the
 * time it is given (the writer then ends and frees itself once its write
 * returns); a reader gone is an error, not a crash (SIGPIPE ignored, as
 * wgmon does). */
#include "cli.h"
#include "mon_out.h"
#include "test.h"

#include <errno.h>
#include <fcntl.h>
#include <poll.h>
#include <signal.h>
#include <unistd.h>

/* Wait (5 s at most) until the frame in flight is written. */
static int wait_idle(mon_out *o)
{
    struct pollfd p = {.fd = mon_out_fd(o), .events = POLLIN};
    for (double end = cli_mono_s() + 5; mon_out_busy(o);)
        if (cli_mono_s() > end || poll(&p, 1, 100) < 0)
            return 0;
    return 1;
}

static void test_frames_in_order(void)
{
    int p[2];
    ASSERT_TRUE(pipe(p) == 0);
    mon_out *o = mon_out_start(p[1]);
    ASSERT_TRUE(o != NULL);
    ASSERT_EQ_INT(mon_out_busy(o), 0);
    ASSERT_EQ_INT(mon_out_send(o, "frame1|", 7), 0);
    ASSERT_TRUE(wait_idle(o));
    ASSERT_EQ_INT(mon_out_send(o, "frame2|", 7), 0);
    ASSERT_EQ_INT(mon_out_stop(o, 5, "bye", 3), 0);
    char buf[64] = {0};
    ssize_t n = 0, r;
    while (n < 17 && (r = read(p[0], buf + n, sizeof buf - 1 - (size_t)n)) > 0)
        n += r;
    ASSERT_STR(buf, "frame1|frame2|bye");
    close(p[0]), close(p[1]);
}

/* A pipe no one reads: the caller is never blocked; a second frame is
 * refused while the first is in flight; stop gives up in its time; once
 * the reader drains the pipe the writer ends and closes its own fds. */
static void test_stalled_reader(void)
{
    int p[2];
    ASSERT_TRUE(pipe(p) == 0);
    enum { BIG = 1 << 20 }; /* 16 times a pipe's buffer */
    char *frame = malloc(BIG);
    ASSERT_TRUE(frame != NULL);
    memset(frame, 'x', BIG);
    mon_out *o = mon_out_start(p[1]);
    ASSERT_TRUE(o != NULL);
    int wfd = mon_out_fd(o);
    double t0 = cli_mono_s();
    ASSERT_EQ_INT(mon_out_send(o, frame, BIG), 0);
    ASSERT_TRUE(cli_mono_s() - t0 < 0.5); /* handed over, not written */
    usleep(200000);
    ASSERT_EQ_INT(mon_out_busy(o), 1);
    ASSERT_EQ_INT(mon_out_send(o, "more", 4), -1);
    t0 = cli_mono_s();
    ASSERT_EQ_INT(mon_out_stop(o, 0.3, "bye", 3), -1);
    double took = cli_mono_s() - t0;
    ASSERT_TRUE(took >= 0.29 && took < 2.0);
    /* drain: the writer finishes the frame, then ends and frees itself */
    char buf[65536];
    size_t got = 0;
    ssize_t r;
    while (got < BIG && (r = read(p[0], buf, sizeof buf)) > 0)
        got += (size_t)r;
    ASSERT_EQ_INT(got, BIG);
    t0 = cli_mono_s();
    while (fcntl(wfd, F_GETFD) != -1 && cli_mono_s() - t0 < 5)
        usleep(10000);
    ASSERT_TRUE(fcntl(wfd, F_GETFD) == -1 && errno == EBADF);
    free(frame);
    close(p[0]), close(p[1]);
}

static void test_reader_gone(void)
{
    signal(SIGPIPE, SIG_IGN);
    int p[2];
    ASSERT_TRUE(pipe(p) == 0);
    close(p[0]);
    mon_out *o = mon_out_start(p[1]);
    ASSERT_TRUE(o != NULL);
    ASSERT_EQ_INT(mon_out_send(o, "lost", 4), 0);
    ASSERT_TRUE(wait_idle(o));
    ASSERT_EQ_INT(mon_out_error(o), EPIPE);
    ASSERT_EQ_INT(mon_out_send(o, "more", 4), 0); /* taken, not written */
    ASSERT_TRUE(wait_idle(o));
    ASSERT_EQ_INT(mon_out_stop(o, 1, NULL, 0), 0);
    close(p[1]);
}

TEST_MAIN(TEST(test_frames_in_order), TEST(test_stalled_reader), TEST(test_reader_gone))

/* test_log.c - the log: text from the bus never makes a line of its own
 * (issue 10, defect 9): control bytes are escaped, in log_escape and in
 * what log_msg writes; repeats are rate-limited with a count. */
#include "log.h"
#include "test.h"

#include <fcntl.h>
#include <signal.h>
#include <stdlib.h>
#include <unistd.h>

static void test_escape(void)
{
    char out[256];
    ASSERT_STR(log_escape("a\n<3>FORGED", out, sizeof out), "a\\x0a<3>FORGED");
    ASSERT_STR(log_escape("tab\there\x1b[31m\x7f", out, sizeof out),
               "tab\\x09here\\x1b[31m\\x7f");
    ASSERT_STR(log_escape("rig@m\xc3\xbcller", out, sizeof out), "rig@m\xc3\xbcller");
    char small[8]; /* never past the end, always terminated */
    ASSERT_STR(log_escape("\n\n\n\n", small, sizeof small), "\\x0a");
}

/* What log_msg writes to stderr: one line per call, the newline escaped. */
static void test_one_line_per_message(void)
{
    char path[] = "/tmp/wgd-log-XXXXXX";
    int fd = mkstemp(path), keep = dup(2);
    ASSERT_TRUE(fd >= 0 && keep >= 0);
    dup2(fd, 2);
    log_ctx l;
    log_init(&l, 0);
    log_msg(&l, LOG_WARNING, "refused save from %s: name '%s'", "rig", "a\n<3>FORGED line");
    log_fini(&l);
    fflush(stderr);
    dup2(keep, 2);
    close(keep);
    FILE *f = fopen(path, "r");
    char line[512];
    int lines = 0, forged = 0;
    while (f && fgets(line, sizeof line, f))
        lines++, forged += !strncmp(line, "<3>FORGED", 9) || !strncmp(line, "FORGED", 6);
    if (f)
        fclose(f);
    close(fd);
    unlink(path);
    ASSERT_EQ_INT(lines, 1);
    ASSERT_EQ_INT(forged, 0);
}

/* Redirect stderr into a temporary file; capture_end reads it back. */
static int capture_begin(char *path, int *keep)
{
    strcpy(path, "/tmp/wgd-log-XXXXXX");
    int fd = mkstemp(path);
    *keep = dup(2);
    dup2(fd, 2);
    return fd;
}

static int capture_end(char *path, int fd, int keep, char *out, size_t n)
{
    fflush(stderr);
    dup2(keep, 2);
    close(keep);
    FILE *f = fopen(path, "r");
    size_t got = f ? fread(out, 1, n - 1, f) : 0;
    out[got] = 0;
    if (f)
        fclose(f);
    close(fd);
    unlink(path);
    int lines = 0;
    for (char *p = out; *p; p++)
        lines += *p == '\n';
    return lines;
}

/* Accepted changes are never rate-limited; repeats and refusals are. */
static void test_changes_never_lost(void)
{
    char path[] = "/tmp/wgd-log-XXXXXX", out[16384];
    int keep, fd = capture_begin(path, &keep);
    log_ctx l;
    log_init(&l, 0);
    char what[64];
    for (int i = 0; i < 20; i++) {
        snprintf(what, sizeof what, "set: omega = %d", i);
        log_change(&l, LOG_INFO, what, "%s", what);
    }
    int n = capture_end(path, fd, keep, out, sizeof out);
    ASSERT_EQ_INT(n, 20);
    ASSERT_CONTAINS(out, "set: omega = 19");
    fd = capture_begin(path, &keep);
    for (int i = 0; i < 20; i++)
        log_change(&l, LOG_INFO, "set: omega = 1", "set from rig (seq %d)", i);
    for (int i = 0; i < 20; i++)
        log_msg(&l, LOG_WARNING, "refused set from rig (seq %d)", i);
    log_fini(&l);
    n = capture_end(path, fd, keep, out, sizeof out);
    /* the first of the repeats is a change (the last was omega = 19): 1 + 5
     * repeats, 5 refusals, two lines counting the rest */
    ASSERT_EQ_INT(n, 1 + LOG_BURST + LOG_BURST + 2);
    /* each says which kind: the last line printed from its call site */
    ASSERT_CONTAINS(out, "14 similar messages suppressed (rate limit), like: set from rig (seq 5)");
    ASSERT_CONTAINS(out, "15 similar messages suppressed (rate limit), like: refused set from "
                    "rig (seq 4)");
}

/* "<N>" prefixes only under journald or when asked. */
static void test_prefixes(void)
{
    char path[] = "/tmp/wgd-log-XXXXXX", out[4096];
    int keep, fd = capture_begin(path, &keep);
    log_ctx l;
    unsetenv("JOURNAL_STREAM");
    log_init(&l, 0); /* stderr is a file here: still no prefix */
    log_msg(&l, LOG_WARNING, "plain");
    log_configure(&l, 0, 1);
    log_msg(&l, LOG_WARNING, "asked");
    setenv("JOURNAL_STREAM", "8:12345", 1);
    log_configure(&l, 0, 0);
    log_msg(&l, LOG_ERR, "journal");
    unsetenv("JOURNAL_STREAM");
    capture_end(path, fd, keep, out, sizeof out);
    ASSERT_STR(out, "wormgeard: warning: plain\n<4>asked\n<3>journal\n");
}

static double mono_s(void) { return (double)log_now_ns() * 1e-9; }

/* The writer thread: stdout a pipe no one reads. 3000 status lines are
 * taken at once (the loop never blocks), those the queue cannot hold
 * dropped whole; once the pipe is drained, the next log line is preceded
 * by how many were not written; what arrives is whole lines, in order. */
static void test_writer_never_blocks(void)
{
    char path[] = "/tmp/wgd-log-XXXXXX", out[16384];
    int keep, fd = capture_begin(path, &keep);
    int p[2], keep1 = dup(1);
    ASSERT_TRUE(pipe(p) == 0 && keep1 >= 0);
    fflush(stdout);
    dup2(p[1], 1);
    log_ctx l;
    log_init(&l, 0);
    ASSERT_EQ_INT(log_start(&l), 0);
    char line[120];
    double t0 = mono_s();
    for (int i = 0; i < 3000; i++) {
        snprintf(line, sizeof line, "status %04d %080d", i, 0);
        ASSERT_EQ_INT(log_stdout(&l, line), 0);
    }
    double took = mono_s() - t0;
    /* drain what the pipe got, until it has been quiet for 0.3 s */
    fcntl(p[0], F_SETFL, O_NONBLOCK);
    static char got[1 << 20];
    size_t n = 0;
    for (double quiet = mono_s(); mono_s() - quiet < 0.3;) {
        ssize_t r = read(p[0], got + n, sizeof got - 1 - n);
        if (r > 0)
            n += (size_t)r, quiet = mono_s();
        else
            usleep(10000);
    }
    got[n] = 0;
    log_msg(&l, LOG_WARNING, "after the stall");
    log_fini(&l);
    fflush(stdout);
    dup2(keep1, 1);
    close(keep1), close(p[0]), close(p[1]);
    capture_end(path, fd, keep, out, sizeof out);
    printf("  3000 lines taken in %.3f s; %zu bytes reached the pipe\n", took, n);
    ASSERT_TRUE(took < 1.0);
    int lines = 0, prev = -1, order = 1;
    for (char *s = got; *s; lines++) {
        int k = -1;
        ASSERT_TRUE(sscanf(s, "status %d ", &k) == 1 && strlen(s) >= 93 && s[92] == '\n');
        order &= k > prev;
        prev = k;
        char *nl = strchr(s, '\n');
        if (!nl)
            break;
        s = nl + 1;
    }
    ASSERT_TRUE(order);
    ASSERT_TRUE(lines > 100 && lines < 3000); /* a pipe and a queue: some, not all */
    /* every line dropped is counted, once (a count goes out whenever the
     * queue has room for it and the next line) */
    int lost = 0, k;
    for (char *s = strstr(out, "warning: "); s; s = strstr(s + 1, "warning: "))
        if (sscanf(s, "warning: %d lines not written", &k) == 1)
            lost += k;
    ASSERT_EQ_INT(lost, 3000 - lines);
    ASSERT_CONTAINS(out, "not written: stdout or stderr took nothing (a stopped terminal, a pipe "
                         "no one reads)\nwormgeard: warning: after the stall\n");
}

/* A stderr that never takes anything: log_fini gives up after its 2 s. */
static void test_fini_gives_up(void)
{
    signal(SIGPIPE, SIG_IGN);
    int p[2], keep2 = dup(2);
    ASSERT_TRUE(pipe(p) == 0 && keep2 >= 0);
    dup2(p[1], 2);
    log_ctx l;
    log_init(&l, 0);
    ASSERT_EQ_INT(log_start(&l), 0);
    char what[128];
    for (int i = 0; i < 4000; i++) { /* twice the queue: the pipe full, the queue too */
        snprintf(what, sizeof what, "set: omega = %d %060d", i, 0);
        log_change(&l, LOG_INFO, what, "%s", what);
        if (i == 2000)
            usleep(200000);
    }
    double t0 = mono_s();
    log_fini(&l);
    double took = mono_s() - t0;
    dup2(keep2, 2);
    close(keep2), close(p[0]), close(p[1]); /* the writer's write fails: it ends */
    usleep(200000);
    printf("  log_fini gave up after %.2f s\n", took);
    ASSERT_TRUE(took >= 1.9 && took < 4.0);
}

TEST_MAIN(TEST(test_escape), TEST(test_one_line_per_message), TEST(test_changes_never_lost),
          TEST(test_prefixes), TEST(test_writer_never_blocks), TEST(test_fini_gives_up))

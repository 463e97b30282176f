/* test_log.c - the log: text from the bus never makes a line of its own
 * (issue 10, defect 9): control bytes are escaped, in log_escape and in
 * what log_msg writes; repeats are rate-limited with a count. */
#include "log.h"
#include "test.h"

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

TEST_MAIN(TEST(test_escape), TEST(test_one_line_per_message))

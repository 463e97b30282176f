/* test_file.c - wg_file: every reader of a named file (scenes, snapshots,
 * key files, the daemon's config, logs, CSV files read back) opens it
 * through wg_file_open, so what it refuses and how it says so is pinned
 * here once: a directory, a FIFO (without blocking), a device, a link when
 * links are not followed, a file over the limit, one that grows past it
 * while it is read, one that is not there. And wg_file_write_all, which the
 * daemon's snapshots and log and wgmon's frames write with: all of it
 * through a pipe's short writes and a signal, or the errno that stopped it. */
#include "test.h"
#include "wormgear/wg_file.h"

#include <errno.h>
#include <fcntl.h>
#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <unistd.h>

static char dir[64];

static void put(const char *path, const char *text)
{
    FILE *f = fopen(path, "w");
    ASSERT_TRUE(f && fputs(text, f) >= 0 && fclose(f) == 0);
}

static void setup(void)
{
    snprintf(dir, sizeof dir, "/tmp/wg_test_file_XXXXXX");
    ASSERT_TRUE(mkdtemp(dir) != NULL);
    alarm(20); /* a FIFO opened for reading would block: fail, do not hang */
}

static void teardown(void)
{
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf %s", dir);
    ASSERT_EQ_INT(system(cmd), 0);
}

/* A regular file is read whole, up to the limit and not a byte past it. */
static void test_regular(void)
{
    setup();
    char path[128], buf[17], why[400];
    snprintf(path, sizeof path, "%s/a.txt", dir);
    put(path, "0123456789abcdef"); /* 16 bytes */
    ASSERT_EQ_INT((int)wg_file_read(path, "config file", 0, buf, 16, why, sizeof why), 16);
    ASSERT_TRUE(memcmp(buf, "0123456789abcdef", 16) == 0);
    ASSERT_EQ_INT((int)wg_file_read(path, "config file", 0, buf, 15, why, sizeof why), -1);
    char want[200];
    snprintf(want, sizeof want, "config file %s is 16 bytes (limit 15)", path);
    ASSERT_STR(why, want);
    /* a stream, no limit, and what fstat said of it */
    struct stat st;
    FILE *f = wg_file_fopen(path, "log", 0, -1, &st, why, sizeof why);
    ASSERT_TRUE(f != NULL);
    ASSERT_EQ_INT((int)st.st_size, 16);
    ASSERT_TRUE(S_ISREG(st.st_mode));
    if (f) {
        char line[32] = "";
        ASSERT_TRUE(fgets(line, sizeof line, f) != NULL);
        ASSERT_STR(line, "0123456789abcdef");
        fclose(f);
    }
    teardown();
}

/* Not regular files: each refused before it is opened, in its own words;
 * a FIFO without waiting for a writer. */
static void test_not_regular(void)
{
    setup();
    char fifo[128], sub[128], why[400], want[200];
    snprintf(fifo, sizeof fifo, "%s/fifo", dir);
    snprintf(sub, sizeof sub, "%s/sub", dir);
    ASSERT_EQ_INT(mkfifo(fifo, 0600), 0);
    ASSERT_EQ_INT(mkdir(sub, 0700), 0);
    ASSERT_EQ_INT(wg_file_open(fifo, "scene file", 0, -1, NULL, why, sizeof why), -1);
    snprintf(want, sizeof want, "scene file %s is a FIFO, not a regular file", fifo);
    ASSERT_STR(why, want);
    ASSERT_TRUE(wg_file_fopen(sub, NULL, 0, -1, NULL, why, sizeof why) == NULL);
    snprintf(want, sizeof want, "%s is a directory, not a regular file", sub);
    ASSERT_STR(why, want);
    ASSERT_EQ_INT(wg_file_open("/dev/zero", "", 0, 100, NULL, why, sizeof why), -1);
    ASSERT_STR(why, "/dev/zero is a character device, not a regular file");
    teardown();
}

/* A link is followed unless WG_FILE_NOFOLLOW says otherwise. */
static void test_links(void)
{
    setup();
    char path[128], link[128], buf[8], why[400], want[200];
    snprintf(path, sizeof path, "%s/target", dir);
    snprintf(link, sizeof link, "%s/link", dir);
    put(path, "key\n");
    ASSERT_EQ_INT(symlink(path, link), 0);
    ASSERT_EQ_INT((int)wg_file_read(link, NULL, 0, buf, 7, why, sizeof why), 4);
    ASSERT_EQ_INT((int)wg_file_read(link, "key file", WG_FILE_NOFOLLOW, buf, 7, why, sizeof why),
                  -1);
    snprintf(want, sizeof want, "key file %s is a symbolic link (not followed), not a regular file",
             link);
    ASSERT_STR(why, want);
    teardown();
}

/* Not there: the reason. */
static void test_missing(void)
{
    setup();
    char path[128], why[400], want[200];
    snprintf(path, sizeof path, "%s/no-dir/x", dir);
    ASSERT_EQ_INT(wg_file_open(path, "config file", 0, -1, NULL, why, sizeof why), -1);
    snprintf(want, sizeof want, "cannot open config file %s: No such file or directory", path);
    ASSERT_STR(why, want);
    ASSERT_EQ_INT(wg_file_open(path, NULL, WG_FILE_NOFOLLOW, -1, NULL, why, sizeof why), -1);
    snprintf(want, sizeof want, "cannot open %s: No such file or directory", path);
    ASSERT_STR(why, want);
    teardown();
}

/* A file whose size said it was within the limit but that holds more when
 * read (grown in between; /proc files say 0 bytes) is refused, not cut. */
static void test_grew(void)
{
    char buf[17], why[400];
    ASSERT_EQ_INT((int)wg_file_read("/proc/self/status", "snapshot", 0, buf, 16, why, sizeof why),
                  -1);
    ASSERT_STR(why, "snapshot /proc/self/status grew past 16 bytes while it was read");
}

static void on_usr1(int sig) { (void)sig; }

/* 1 MiB through a pipe (64 KiB at a time) to a child that checks every
 * byte, interrupted by a signal without SA_RESTART while it is blocked:
 * the pipe full first, so that the write is interrupted before it wrote
 * anything (EINTR), then short writes. */
static void test_write_all(void)
{
    enum { N = 1 << 20 };
    static unsigned char buf[N];
    for (int i = 0; i < N; i++)
        buf[i] = (unsigned char)(i * 31 + 7);
    struct sigaction sa = {.sa_handler = on_usr1}, old; /* no SA_RESTART */
    sigaction(SIGUSR1, &sa, &old);
    int p[2];
    ASSERT_TRUE(pipe(p) == 0);
    pid_t kid = fork();
    if (kid == 0) {
        close(p[1]);
        usleep(100000); /* the parent blocks on a full pipe: interrupt it */
        kill(getppid(), SIGUSR1);
        usleep(100000); /* before reading: it wrote nothing when interrupted */
        size_t got = 0, bad = 0;
        unsigned char b[4096];
        for (ssize_t r; (r = read(p[0], b, sizeof b)) > 0; got += (size_t)r)
            for (ssize_t i = 0; i < r; i++)
                bad += b[i] != (unsigned char)((got + (size_t)i) * 31 + 7);
        _exit(got == N && !bad ? 0 : 1);
    }
    close(p[0]);
    fcntl(p[1], F_SETFL, O_NONBLOCK);
    size_t m = 0;
    for (ssize_t w; (w = write(p[1], buf + m, N - m)) > 0;)
        m += (size_t)w;
    fcntl(p[1], F_SETFL, 0);
    ASSERT_TRUE(m > 0 && m < N);
    ASSERT_EQ_INT(wg_file_write_all(p[1], buf + m, N - m), 0);
    close(p[1]);
    int st = -1;
    waitpid(kid, &st, 0);
    ASSERT_TRUE(WIFEXITED(st) && WEXITSTATUS(st) == 0);
    sigaction(SIGUSR1, &old, NULL);

    void (*was)(int) = signal(SIGPIPE, SIG_IGN);
    ASSERT_TRUE(pipe(p) == 0);
    close(p[0]);
    ASSERT_EQ_INT(wg_file_write_all(p[1], buf, 10), EPIPE);
    close(p[1]);
    signal(SIGPIPE, was);
    ASSERT_EQ_INT(wg_file_write_all(-1, buf, 10), EBADF);
    ASSERT_EQ_INT(wg_file_write_all(-1, buf, 0), 0); /* nothing to write */
}

TEST_MAIN(TEST(test_regular), TEST(test_not_regular), TEST(test_links), TEST(test_missing),
          TEST(test_grew), TEST(test_write_all))

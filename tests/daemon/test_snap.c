/* test_snap.c - save and restore through the command path: bit-exact
 * continuation (also mid-ramp), snapshot-name, N-mismatch and corrupted-file
 * refusals that change nothing; every truncation and single-byte flip of a
 * saved file refused; FIFOs, symbolic links, directories and oversized
 * files refused at once, their content never quoted; a save killed at any
 * moment leaves the old file or the new one, and its temporary file is
 * removed at the next start. */
#include "fixture.h"
#include "snap.h"

#include <signal.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>

typedef struct shot {
    double y[WG_NSTATE_MAX], tau, tau_c;
    uint32_t k;
    uint64_t steps, period;
    wg_params p;
} shot;

static shot take(const wgd *d)
{
    shot s;
    memset(&s, 0, sizeof s);
    memcpy(s.y, d->sim.y, sizeof s.y);
    s.tau = d->sim.tau, s.tau_c = d->sim.tau_c, s.k = d->sim.k;
    s.steps = d->sim.steps, s.period = d->sim.period, s.p = d->sim.p;
    return s;
}

static void bitexact_case(int with_ramp)
{
    wgd *d = setup(128);
    ASSERT_EQ_INT(set1(d, "omega", 1.35), WG_OK); /* an impacting regime */
    run(d, 128 * 50 + 37);
    if (with_ramp)
        ASSERT_EQ_INT(ramp(d, "omega", 0, 0, 1.6, 2000, "tau"), WG_OK);
    run(d, 1001);
    ASSERT_EQ_INT(simple(d, "save", "bx"), WG_OK);
    run(d, 128 * 40);
    shot a = take(d);
    ASSERT_EQ_INT(simple(d, "restore", "bx"), WG_OK);
    ASSERT_STR(F.params_reason, "restore");
    run(d, 128 * 40);
    shot b = take(d);
    ASSERT_TRUE(memcmp(&a, &b, sizeof a) == 0);
    ASSERT_NEAR(b.tau, a.tau, 0);
    ASSERT_NEAR(b.y[0], a.y[0], 0);
    teardown(d);
}

static void test_save_restore_bitexact(void) { bitexact_case(0); }
static void test_save_restore_bitexact_ramp(void) { bitexact_case(1); }

static void test_save_restore_refusals(void)
{
    wgd *d = setup(128);
    const char *bad[] = {"../etc/passwd", "a/b", "..", ".hidden", "", "x y"};
    for (unsigned i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        ASSERT_EQ_INT(simple(d, "save", bad[i]), WG_EINVAL);
        ASSERT_EQ_INT(simple(d, "restore", bad[i]), WG_EINVAL);
    }
    ASSERT_EQ_INT(simple(d, "restore", "never-saved"), WG_EIO);
    /* a refused name is quoted printable only (issue 10, defect 9) */
    ASSERT_EQ_INT(simple(d, "save", "a\n<3>FORGED\x1b[31m"), WG_EINVAL);
    for (const char *m = F.message; *m; m++)
        ASSERT_TRUE((unsigned char)*m >= 0x20 && (unsigned char)*m < 0x7f);
    ASSERT_CONTAINS(F.message, "'a?<3>FORGED?[31m'");
    /* a snapshot of another N: ESTATE, nothing changed */
    snap s;
    char path[600], why[600];
    snap_take(&s, &d->sim, "table3");
    s.w.steps_per_period = 256;
    ASSERT_EQ_INT(snap_write(&s, fx_statedir(), "n256", path, sizeof path, why, sizeof why),
                  WG_OK);
    shot a = take(d);
    ASSERT_EQ_INT(simple(d, "restore", "n256"), WG_ESTATE);
    ASSERT_CONTAINS(F.message, "N = 256");
    shot b = take(d);
    ASSERT_TRUE(memcmp(&a, &b, sizeof a) == 0);
    /* a line appended: refused, naming the file, quoting nothing */
    FILE *f = fopen(path, "a");
    fprintf(f, "param omega = 99\n");
    fclose(f);
    ASSERT_EQ_INT(simple(d, "restore", "n256"), WG_EINVAL);
    ASSERT_CONTAINS(F.message, "n256.wgstate: the last line is not its checksum");
    teardown(d);
}

/* ---- corrupt and special files ---------------------------------------------- */

static const char *state_path(const char *name, char *buf, size_t len)
{
    snprintf(buf, len, "%s/%s.wgstate", fx_statedir(), name);
    return buf;
}

static size_t slurp(const char *path, char *buf, size_t cap)
{
    FILE *f = fopen(path, "rb");
    ASSERT_TRUE(f != NULL);
    size_t n = f ? fread(buf, 1, cap, f) : 0;
    if (f)
        fclose(f);
    return n;
}

static void spit(const char *path, const char *buf, size_t n)
{
    FILE *f = fopen(path, "wb");
    ASSERT_TRUE(f != NULL);
    if (f) {
        ASSERT_EQ_INT(fwrite(buf, 1, n, f), n);
        fclose(f);
    }
}

static int ends_with_quotes(const char *s)
{
    size_t n = strlen(s);
    return n >= 2 && s[n - 1] == '\'' && s[n - 2] == '\'';
}

/* Restore a damaged copy: 1 if refused with the state unchanged and a
 * message that quotes nothing; an accepted one is undone. */
static int refused(wgd *d, const char *bytes, size_t n, const shot *a)
{
    char path[700];
    spit(state_path("t", path, sizeof path), bytes, n);
    if (simple(d, "restore", "t") == WG_OK) {
        ASSERT_EQ_INT(simple(d, "restore", "good"), WG_OK);
        return 0;
    }
    shot b = take(d);
    if (memcmp(a, &b, sizeof b) != 0 || ends_with_quotes(F.message))
        TEST_FAIL_("refused, but state changed or message '%s'", F.message);
    return 1;
}

static void test_corrupt_files_refused(void)
{
    wgd *d = setup(128);
    ASSERT_EQ_INT(set1(d, "omega", 1.35), WG_OK);
    run(d, 128 * 20 + 37);
    ASSERT_EQ_INT(ramp(d, "omega", 0, 0, 1.6, 2000, "tau"), WG_OK);
    run(d, 1001);
    ASSERT_EQ_INT(simple(d, "save", "good"), WG_OK);
    static char good[70000], bad[70000];
    char path[700];
    size_t len = slurp(state_path("good", path, sizeof path), good, sizeof good);
    ASSERT_EQ_INT(simple(d, "restore", "good"), WG_OK);
    shot a = take(d);
    unsigned seed = test_seed("truncations and flips:");
    srand(seed);
    size_t ntrunc = 0, nflip = 0;
    for (size_t n = 0; n < len; n++)
        ntrunc += refused(d, good, n, &a);
    for (size_t i = 0; i < len; i++) {
        memcpy(bad, good, len);
        bad[i] = (char)(bad[i] ^ (1 + rand() % 255));
        nflip += refused(d, bad, len, &a);
    }
    printf("  %zu of %zu truncations and %zu of %zu single-byte flips (seed %u) refused\n",
           ntrunc, len, nflip, len, seed);
    ASSERT_EQ_INT(ntrunc, len);
    ASSERT_EQ_INT(nflip, len);
    unlink(state_path("t", path, sizeof path));
    teardown(d);
}

static void on_alarm(int sig)
{
    (void)sig;
    static const char msg[] = "restore blocked for 5 s\n";
    ssize_t w = write(2, msg, sizeof msg - 1);
    _exit(w > 0 ? 1 : 2);
}

static void special_case(wgd *d, const char *name, const char *says, const shot *a)
{
    signal(SIGALRM, on_alarm);
    alarm(5);
    int64_t t0 = log_now_ns();
    int rc = simple(d, "restore", name);
    double s = (double)(log_now_ns() - t0) * 1e-9;
    alarm(0);
    shot b = take(d);
    if (rc != WG_EIO || !strstr(F.message, says) || strstr(F.message, "root:") || s > 1.0 ||
        memcmp(a, &b, sizeof b) != 0)
        TEST_FAIL_("restore %s: rc %d in %.3f s, '%s' (want EIO, '%s', state unchanged)", name,
                   rc, s, F.message, says);
}

static void test_special_files_refused(void)
{
    wgd *d = setup(128);
    run(d, 1000);
    shot a = take(d);
    char p[700];
    ASSERT_EQ_INT(symlink("/etc/passwd", state_path("pw", p, sizeof p)), 0);
    ASSERT_EQ_INT(mkdir(state_path("dir", p, sizeof p), 0700), 0);
    FILE *f = fopen(state_path("big", p, sizeof p), "w");
    for (int i = 0; f && i < 2097152 / 16; i++)
        fputs("param omega = 1\n", f);
    if (f)
        fclose(f);
    ASSERT_EQ_INT(mkfifo(state_path("fifo", p, sizeof p), 0600), 0);
    special_case(d, "pw", "is a symbolic link", &a);
    special_case(d, "dir", "is a directory", &a);
    special_case(d, "big", "is 2097152 bytes (limit 8192)", &a);
    special_case(d, "fifo", "is a FIFO, not a regular file", &a);
    unlink(state_path("pw", p, sizeof p));
    rmdir(state_path("dir", p, sizeof p));
    unlink(state_path("big", p, sizeof p));
    unlink(state_path("fifo", p, sizeof p));
    teardown(d);
}

/* ---- killed saves and their temporary files ---------------------------------------- */

static const char *tmp_path(const char *name, long pid, char *buf, size_t len)
{
    snprintf(buf, len, "%s/%s.wgstate.tmp.%ld", fx_statedir(), name, pid);
    return buf;
}

static void touch(const char *path)
{
    FILE *f = fopen(path, "w");
    ASSERT_TRUE(f != NULL);
    if (f)
        fclose(f);
}

static long dead_pid(void)
{
    pid_t c = fork();
    if (c == 0)
        _exit(0);
    waitpid(c, NULL, 0);
    return (long)c;
}

static void test_stale_temp_files_removed(void)
{
    char p[700], why[400];
    long dead = dead_pid();
    touch(tmp_path("a", dead, p, sizeof p));             /* its writer is gone */
    touch(tmp_path("b", (long)getpid(), p, sizeof p));   /* ours, before any save */
    touch(tmp_path("c", 1, p, sizeof p));                /* a live process's: kept */
    ASSERT_EQ_INT(mkdir(tmp_path("d", dead, p, sizeof p), 0700), 0); /* not a file */
    snprintf(p, sizeof p, "%s/e.wgstate.tmp.x%ld", fx_statedir(), dead); /* not a pid */
    touch(p);
    int n = -1;
    ASSERT_EQ_INT(snap_init(fx_statedir(), &n, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(n, 2);
    ASSERT_TRUE(access(tmp_path("a", dead, p, sizeof p), F_OK) != 0);
    ASSERT_TRUE(access(tmp_path("b", (long)getpid(), p, sizeof p), F_OK) != 0);
    ASSERT_EQ_INT(unlink(tmp_path("c", 1, p, sizeof p)), 0);
    ASSERT_EQ_INT(rmdir(tmp_path("d", dead, p, sizeof p)), 0);
    snprintf(p, sizeof p, "%s/e.wgstate.tmp.x%ld", fx_statedir(), dead);
    ASSERT_EQ_INT(unlink(p), 0);
    snprintf(p, sizeof p, "%s/not-there", fx_statedir());
    ASSERT_EQ_INT(snap_init(p, &n, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(n, 0);
}

/* The state directory is judged at start (a bad one failed only at the
 * first save): an existing directory we can write, or a missing one whose
 * parent can hold it (made when asked, reported when not); a file, or a
 * missing parent, refused saying what is allowed. */
static void test_state_dir_check(void)
{
    char p[700], q[720], why[400];
    int state = -1;
    ASSERT_EQ_INT(snap_dir_check(fx_statedir(), 1, &state, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(state, SNAP_DIR_OK);
    snprintf(p, sizeof p, "%s/new", fx_statedir());
    ASSERT_EQ_INT(snap_dir_check(p, 0, &state, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(state, SNAP_DIR_ABSENT);
    ASSERT_TRUE(access(p, F_OK) != 0); /* --check-config makes nothing */
    ASSERT_EQ_INT(snap_dir_check(p, 1, &state, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(state, SNAP_DIR_MADE);
    ASSERT_EQ_INT(access(p, W_OK | X_OK), 0);
    ASSERT_EQ_INT(rmdir(p), 0);
    snprintf(q, sizeof q, "%s/none/sub", fx_statedir()); /* its parent is missing */
    ASSERT_EQ_INT(snap_dir_check(q, 1, &state, why, sizeof why), WG_EIO);
    ASSERT_CONTAINS(why, "/none/sub does not exist, and cannot be made in");
    ASSERT_CONTAINS(why, "/none: No such file or directory (state_dir must be a directory");
    touch(p); /* a file */
    ASSERT_EQ_INT(snap_dir_check(p, 1, &state, why, sizeof why), WG_EIO);
    ASSERT_CONTAINS(why, "/new is not a directory (state_dir must be a directory this process "
                         "can write, or one it can make)");
    snprintf(q, sizeof q, "%s/sub", p); /* in a file */
    ASSERT_EQ_INT(snap_dir_check(q, 1, &state, why, sizeof why), WG_EIO);
    ASSERT_CONTAINS(why, "Not a directory");
    ASSERT_EQ_INT(unlink(p), 0);
}

/* A child saves two states in turn, forever; it is killed at a random
 * moment, again and again. The file is always one of the two, whole. */
static void test_kill_during_save(void)
{
    wgd *d = setup(128);
    run(d, 1000);
    static snap s[2];
    static char text[2][WG_SNAPSHOT_MAX], got[WG_SNAPSHOT_MAX + 1];
    char path[700], why[400];
    int len[2];
    for (int i = 0; i < 2; i++) {
        snap_take(&s[i], &d->sim, "table3");
        len[i] = wg_snapshot_format(&s[i].w, "table3", text[i], WG_SNAPSHOT_MAX, why, sizeof why);
        run(d, 1);
    }
    ASSERT_EQ_INT(snap_write(&s[0], fx_statedir(), "k", path, sizeof path, why, sizeof why), 0);
    unsigned seed = test_seed("kills mid-save:");
    srand(seed);
    int kills = 100, found[3] = {0, 0, 0}, left = 0, n = 0;
    for (int i = 0; i < kills; i++) {
        pid_t c = fork();
        for (unsigned j = 1; c == 0; j++)
            snap_write(&s[j & 1], fx_statedir(), "k", path, sizeof path, why, sizeof why);
        usleep((useconds_t)(rand() % 8000));
        kill(c, SIGKILL);
        waitpid(c, NULL, 0);
        size_t m = slurp(path, got, sizeof got);
        int which = m == (size_t)len[0] && !memcmp(got, text[0], m)   ? 0
                    : m == (size_t)len[1] && !memcmp(got, text[1], m) ? 1 : 2;
        found[which]++;
    }
    left = fx_temp_files();
    ASSERT_EQ_INT(snap_init(fx_statedir(), &n, why, sizeof why), WG_OK);
    printf("  %d kills mid-save (seed %u): the file was one state %d times, the other %d, "
           "neither %d; %d temporary files left, %d removed at start\n", kills, seed,
           found[0], found[1], found[2], left, n);
    ASSERT_EQ_INT(found[2], 0);
    ASSERT_EQ_INT(n, left);
    ASSERT_EQ_INT(fx_temp_files(), 0);
    unlink(path);
    teardown(d);
}

TEST_MAIN(TEST(test_save_restore_bitexact), TEST(test_save_restore_bitexact_ramp),
          TEST(test_save_restore_refusals), TEST(test_corrupt_files_refused),
          TEST(test_special_files_refused), TEST(test_stale_temp_files_removed),
          TEST(test_kill_during_save), TEST(test_state_dir_check))

/* test_snap.c - save and restore through the command path: bit-exact
 * continuation (also mid-ramp), snapshot-name, N-mismatch and corrupted-file
 * refusals that change nothing; every truncation and single-byte flip of a
 * saved file refused; FIFOs, symbolic links, directories and oversized
 * files refused at once, their content never quoted. */
#include "fixture.h"
#include "snap.h"

#include <signal.h>
#include <sys/stat.h>
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
    unsigned seed = (unsigned)time(NULL);
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

TEST_MAIN(TEST(test_save_restore_bitexact), TEST(test_save_restore_bitexact_ramp),
          TEST(test_save_restore_refusals), TEST(test_corrupt_files_refused),
          TEST(test_special_files_refused))

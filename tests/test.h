/* test.h - the tiny test harness shared by every wormgear test.
 *
 * A test file defines functions `static void test_x(void)`, lists them in
 * TEST_LIST, and ends with TEST_MAIN(). Each ASSERT prints both values and
 * the line when it fails and marks the current test failed; the run exits 1
 * if any test failed. `prog NAME` runs only test NAME.
 *
 * Every test ends by proving its teardown left nothing behind (as libuv's
 * tests prove the loop is empty): the process must hold exactly the file
 * descriptors it held before the test ran. A file adds checks of its own
 * (temporary files gone, fixtures torn down) by defining
 * TEST_TEARDOWN_CHECK() before including this header. */
#ifndef WG_TEST_H
#define WG_TEST_H

#include <dirent.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <time.h>

static int test_failed_ = 0, test_cur_failed_ = 0;

#define TEST_FAIL_(...)                                                                   \
    do {                                                                                  \
        fprintf(stderr, "%s:%d: ", __FILE__, __LINE__);                                   \
        fprintf(stderr, __VA_ARGS__);                                                     \
        fputc('\n', stderr);                                                              \
        test_cur_failed_ = 1;                                                             \
    } while (0)

#define ASSERT_TRUE(c)                                                                    \
    do {                                                                                  \
        if (!(c))                                                                         \
            TEST_FAIL_("assertion failed: %s", #c);                                       \
    } while (0)

#define ASSERT_EQ_INT(a, b)                                                               \
    do {                                                                                  \
        long long a_ = (long long)(a), b_ = (long long)(b);                               \
        if (a_ != b_)                                                                     \
            TEST_FAIL_("%s == %s: %lld != %lld", #a, #b, a_, b_);                         \
    } while (0)

#define ASSERT_NEAR(a, b, tol)                                                            \
    do {                                                                                  \
        double a_ = (a), b_ = (b), t_ = (tol);                                            \
        if (!(fabs(a_ - b_) <= t_))                                                       \
            TEST_FAIL_("%s ~ %s: %.17g vs %.17g (diff %.3g > tol %.3g)", #a, #b, a_, b_,  \
                       fabs(a_ - b_), t_);                                                \
    } while (0)

#define ASSERT_STR(a, b)                                                                  \
    do {                                                                                  \
        const char *a_ = (a), *b_ = (b);                                                  \
        if (!a_ || !b_ || strcmp(a_, b_) != 0)                                            \
            TEST_FAIL_("%s == %s: '%s' != '%s'", #a, #b, a_ ? a_ : "(null)",              \
                       b_ ? b_ : "(null)");                                               \
    } while (0)

#define ASSERT_CONTAINS(hay, needle)                                                      \
    do {                                                                                  \
        const char *h_ = (hay), *n_ = (needle);                                           \
        if (!h_ || !strstr(h_, n_))                                                       \
            TEST_FAIL_("'%s' does not contain '%s'", h_ ? h_ : "(null)", n_);             \
    } while (0)

/* The seed of a randomised test: a new one each run (the time), printed
 * with what it seeds; WG_TEST_SEED=N in the environment runs N again. */
static inline unsigned test_seed(const char *what)
{
    const char *env = getenv("WG_TEST_SEED");
    unsigned seed = env && *env ? (unsigned)strtoul(env, NULL, 10) : (unsigned)time(NULL);
    printf("  %s seed %u (rerun with WG_TEST_SEED=%u)\n", what, seed, seed);
    return seed;
}

/* Open file descriptors of this process (-1 if /proc is not there). */
static int test_open_fds_(void)
{
    DIR *d = opendir("/proc/self/fd");
    if (!d)
        return -1;
    int n = 0;
    while (readdir(d))
        n++;
    closedir(d);
    return n;
}

#ifndef TEST_TEARDOWN_CHECK
#define TEST_TEARDOWN_CHECK() ((void)0)
#endif

/* After each test: nothing left open, and the file's own check. */
#define TEST_AFTER_(fds0)                                                                 \
    do {                                                                                  \
        int fds1_ = test_open_fds_();                                                     \
        if (fds1_ != (fds0))                                                              \
            TEST_FAIL_("teardown: %d file descriptors open after the test, %d before",    \
                       fds1_, (fds0));                                                    \
        TEST_TEARDOWN_CHECK();                                                            \
    } while (0)

typedef struct test_entry_ {
    const char *name;
    void (*fn)(void);
} test_entry_;

#define TEST(fn) {#fn, fn}

#define TEST_MAIN(...)                                                                    \
    int main(int argc, char **argv)                                                       \
    {                                                                                     \
        static const test_entry_ tests_[] = {__VA_ARGS__};                                \
        int ran = 0;                                                                      \
        for (unsigned i = 0; i < sizeof tests_ / sizeof tests_[0]; i++) {                 \
            if (argc > 1 && strcmp(argv[1], tests_[i].name) != 0)                         \
                continue;                                                                 \
            test_cur_failed_ = 0;                                                         \
            int fds0_ = test_open_fds_();                                                 \
            tests_[i].fn();                                                               \
            TEST_AFTER_(fds0_);                                                           \
            printf("%-40s %s\n", tests_[i].name, test_cur_failed_ ? "FAIL" : "ok");       \
            test_failed_ |= test_cur_failed_;                                             \
            ran++;                                                                        \
        }                                                                                 \
        if (!ran) {                                                                       \
            fprintf(stderr, "no test named %s\n", argc > 1 ? argv[1] : "");               \
            return 2;                                                                     \
        }                                                                                 \
        return test_failed_ ? 1 : 0;                                                      \
    }

#endif

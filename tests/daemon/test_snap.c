/* test_snap.c - save and restore through the command path: bit-exact
 * continuation (also mid-ramp), snapshot-name, N-mismatch and corrupted-file
 * refusals that change nothing. */
#include "fixture.h"
#include "snap.h"

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
    /* a corrupted file: refused with file:line */
    FILE *f = fopen(path, "a");
    fprintf(f, "param omega = 99\n");
    fclose(f);
    ASSERT_EQ_INT(simple(d, "restore", "n256"), WG_ERANGE);
    ASSERT_CONTAINS(F.message, "n256.wgstate:");
    teardown(d);
}

TEST_MAIN(TEST(test_save_restore_bitexact), TEST(test_save_restore_bitexact_ramp), TEST(test_save_restore_refusals))

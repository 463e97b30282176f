/* Determinism: the same scene and the same sequence of parameter changes
 * and ramps give bit-identical Poincare sections and events -- run twice in
 * one process, in a fresh process (exec, different address layout), with
 * the steps cut into random chunks, and with or without a per-step sink.
 * The run starts in table3's chaotic band (omega 1.45) and the hash covers
 * every bit of every section and event, so one differing bit shows (checked:
 * xi_p one ulp higher gives another hash). */
#include "stress.h"

#include <time.h>
#include <unistd.h>

enum { N = 128 };

typedef struct hasher {
    uint64_t h;
    uint64_t nsec, nev, nstep;
    double last_xn;
} hasher;

static void h_sec(void *ctx, const wg_section *s)
{
    hasher *x = ctx;
    x->h = stress_fnv(x->h, &s->tau, sizeof s->tau);
    x->h = stress_fnv(x->h, &s->omega, sizeof s->omega);
    x->h = stress_fnv(x->h, s->y, 14 * sizeof s->y[0]);
    x->h = stress_fnv(x->h, &s->out.xn, 3 * sizeof(double));
    x->h = stress_fnv(x->h, &s->stats.min_xn, 2 * sizeof(double));
    x->h = stress_fnv(x->h, &s->stats.motion, 2 * sizeof(int));
    x->last_xn = s->out.xn;
    x->nsec++;
}

static void h_ev(void *ctx, const wg_event *e)
{
    hasher *x = ctx;
    x->h = stress_fnv(x->h, &e->tau, sizeof e->tau);
    x->h = stress_fnv(x->h, &e->velocity, sizeof e->velocity);
    x->h = stress_fnv(x->h, &e->contact, sizeof e->contact);
    x->h = stress_fnv(x->h, &e->kind, sizeof e->kind);
    x->nev++;
}

static void h_step(void *ctx, const wg_sim *s)
{
    (void)s;
    ((hasher *)ctx)->nstep++;
}

/* Run n steps, in random chunks when seed != 0. */
static void run(wg_sim *s, uint64_t n, const wg_sink *sink, unsigned *seed)
{
    while (n > 0) {
        uint64_t c = n;
        if (*seed) {
            *seed = *seed * 1103515245u + 12345u;
            c = 1 + (*seed >> 8) % 700;
            c = c < n ? c : n;
        }
        ASSERT_EQ_INT(wg_sim_run(s, c, sink, NULL), WG_OK);
        n -= c;
    }
}

/* The scenario: chaotic band, a damping change, an omega ramp, a step
 * change of k_a and e_m, a load ramp, a stepper-visible kernel change
 * (b_j = 0). Returns the hash of every section and event. */
static uint64_t scenario_ulp(int stepper, unsigned seed, int per_step, int ulp, hasher *out)
{
    wg_params p = stress_scene("table3");
    p.v[WG_P_OMEGA] = 1.45;
    if (ulp)
        p.v[WG_P_XI_P] = nextafter(p.v[WG_P_XI_P], 1.0);
    wg_sim s;
    ASSERT_EQ_INT(test_sim_init(&s, &p, stepper, N), WG_OK);
    hasher x = {STRESS_FNV0, 0, 0, 0, 0};
    wg_sink sink = {&x, per_step ? h_step : NULL, h_sec, h_ev};
    char why[300];
    run(&s, N * 100, &sink, &seed);
    wg_params q = s.p;
    q.v[WG_P_XI_P] = 0.1;
    ASSERT_EQ_INT(wg_sim_set_params(&s, &q, why, sizeof why), WG_OK);
    run(&s, N * 50 + 17, &sink, &seed);
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_OMEGA, NULL, 1.5, 150.0, why, sizeof why), WG_OK);
    run(&s, N * 60, &sink, &seed);
    q = s.p;
    q.v[WG_P_K_A] = 0.4;
    q.v[WG_P_E_M] = 0.3;
    ASSERT_EQ_INT(wg_sim_set_params(&s, &q, why, sizeof why), WG_OK);
    run(&s, N * 40, &sink, &seed);
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_F_E, NULL, 0.2, 80.0, why, sizeof why), WG_OK);
    run(&s, N * 40, &sink, &seed);
    q = s.p;
    q.v[WG_P_B_J] = 0.0;
    ASSERT_EQ_INT(wg_sim_set_params(&s, &q, why, sizeof why), WG_OK);
    run(&s, N * 40, &sink, &seed);
    x.h = stress_fnv(x.h, s.y, 14 * sizeof s.y[0]);
    if (out)
        *out = x;
    wg_sim_fini(&s);
    return x.h;
}

static uint64_t scenario(int stepper, unsigned seed, int per_step, hasher *out)
{
    return scenario_ulp(stepper, seed, per_step, 0, out);
}

/* Run by the parent in a fresh process: prints the hashes. */
static void test_child_hash(void)
{
    printf("hash %016llx %016llx\n", (unsigned long long)scenario(WG_STEPPER_RK4, 0, 0, NULL),
           (unsigned long long)scenario(WG_STEPPER_RK4_EVENT, 0, 0, NULL));
}

static void test_bit_identical(void)
{
    unsigned seed = test_seed("chunk") | 1u;
    uint64_t h[2];
    for (int st = 0; st < 2; st++) {
        hasher a, b;
        h[st] = scenario(st, 0, 0, &a);
        uint64_t again = scenario(st, 0, 0, NULL);
        uint64_t chunked = scenario(st, seed + 2u * (unsigned)st, 0, NULL);
        uint64_t stepped = scenario(st, 0, 1, &b);
        printf("  %-9s %llu sections, %llu events, last x_n %.6f: hash %016llx; again %s, "
               "random chunks %s, per-step sink %s\n", wg_stepper_name(st),
               (unsigned long long)a.nsec, (unsigned long long)a.nev, a.last_xn,
               (unsigned long long)h[st], again == h[st] ? "same" : "DIFFERENT",
               chunked == h[st] ? "same" : "DIFFERENT", stepped == h[st] ? "same" : "DIFFERENT");
        ASSERT_TRUE(again == h[st]);
        ASSERT_TRUE(chunked == h[st]);
        ASSERT_TRUE(stepped == h[st]);
        ASSERT_EQ_INT(b.nstep, N * 330 + 17);
        ASSERT_TRUE(a.nev > 1000 && a.nsec == 330);
    }
    ASSERT_TRUE(h[0] != h[1]); /* the two steppers differ: the hash sees the trajectory */
    /* a fresh process */
    char exe[512], cmd[600];
    ssize_t len = readlink("/proc/self/exe", exe, sizeof exe - 1);
    ASSERT_TRUE(len > 0);
    exe[len > 0 ? len : 0] = 0;
    snprintf(cmd, sizeof cmd, "'%s' test_child_hash", exe);
    FILE *f = popen(cmd, "r");
    ASSERT_TRUE(f != NULL);
    unsigned long long c0 = 0, c1 = 0;
    char line[256];
    int got = 0;
    while (f && fgets(line, sizeof line, f))
        got += sscanf(line, "hash %llx %llx", &c0, &c1) == 2;
    ASSERT_EQ_INT(f ? pclose(f) : -1, 0);
    printf("  fresh process: %016llx %016llx (%s)\n", c0, c1,
           c0 == h[0] && c1 == h[1] ? "same" : "DIFFERENT");
    ASSERT_EQ_INT(got, 1);
    ASSERT_TRUE(c0 == h[0] && c1 == h[1]);
    /* sensitivity: one ulp more mesh damping gives another trajectory */
    hasher u;
    uint64_t hu = scenario_ulp(WG_STEPPER_RK4_EVENT, 0, 0, 1, &u);
    printf("  xi_p one ulp higher: hash %016llx, last x_n %.6f\n", (unsigned long long)hu,
           u.last_xn);
    ASSERT_TRUE(hu != h[1]);
}

TEST_MAIN(TEST(test_bit_identical), TEST(test_child_hash))

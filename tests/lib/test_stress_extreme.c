/* Extreme parameters within the table's ranges: every run either stays
 * bounded, or stops with a clean WG_ENONFINITE fault (finite last state,
 * step counters consistent). Never a NaN in any output a sink receives. */
#include "stress.h"

typedef struct watch {
    uint64_t nsec, nev, bad;
    double maxabs;
} watch;

static void on_sec(void *ctx, const wg_section *s)
{
    watch *w = ctx;
    const wg_outputs *o = &s->out;
    int ok = stress_finite(s->y, 14) && isfinite(s->tau) && isfinite(o->xn) &&
             isfinite(o->dxn) && isfinite(o->F) && stress_finite(o->fb, 6) &&
             isfinite(s->stats.min_xn) && isfinite(s->stats.max_xn);
    w->bad += !ok;
    w->maxabs = fmax(w->maxabs, stress_maxabs(s->y, 14));
    w->nsec++;
}

static void on_ev(void *ctx, const wg_event *e)
{
    watch *w = ctx;
    w->bad += !(isfinite(e->tau) && isfinite(e->velocity));
    w->nev++;
}

typedef struct xcase {
    const char *what, *scene;
    double omega;
    int set[7];     /* parameter ids, -1 terminated */
    double val[7];
    int periods;
    int expect;     /* 0 bounded, 1 clean fault, -1 either */
} xcase;

#define P_(...) {__VA_ARGS__, -1}
static const xcase cases[] = {
    {"xi_p = 0 (no mesh damping)", "table3", 1.0, P_(WG_P_XI_P), {0}, 400, 0},
    {"xi_p = 0, chaotic band", "table3", 1.45, P_(WG_P_XI_P), {0}, 400, 0},
    {"k_a = 0.95 (max)", "table3", 0.7, P_(WG_P_K_A), {0.95}, 400, 0},
    {"k_a = 0.95, parametric 2:1", "table3", 2.0, P_(WG_P_K_A), {0.95}, 400, 0},
    {"f_e = 10 (max): rattle", "table3", 1.0, P_(WG_P_F_E), {10}, 400, 0},
    {"e_m = 10 (max)", "table3", 1.0, P_(WG_P_E_M), {10}, 400, 0},
    {"omega = 0.01 (min)", "table3", 0.01, P_(WG_P_OMEGA), {0.01}, 6, 0},
    {"omega = 10 (max)", "table3", 10.0, P_(WG_P_OMEGA), {10}, 800, 0},
    {"omega = 10, f_e = 10", "table3", 10.0, P_(WG_P_F_E), {10}, 800, 0},
    {"b = b_j = 0 (no backlash, no clearance)", "table3", 1.0, P_(WG_P_B, WG_P_B_J), {0, 0}, 400, 0},
    {"b_j = 1000 (huge clearance)", "table3", 1.0, P_(WG_P_B_J), {1000}, 400, 0},
    {"b = 100 (huge backlash)", "table3", 1.0, P_(WG_P_B), {100}, 400, 0},
    {"bearings k = 1e4 (max): stiff, large N_min", "table3", 1.0,
     P_(WG_P_K1X, WG_P_K1Y, WG_P_K1Z, WG_P_K2X, WG_P_K2Y, WG_P_K2Z), {1e4, 1e4, 1e4, 1e4, 1e4, 1e4},
     100, 0},
    {"bearings k = 1e-3 (min): nearly free", "table3", 1.0,
     P_(WG_P_K1X, WG_P_K1Y, WG_P_K1Z, WG_P_K2X, WG_P_K2Y, WG_P_K2Z),
     {1e-3, 1e-3, 1e-3, 1e-3, 1e-3, 1e-3}, 400, 0},
    /* a physical parametric instability (see test_physical_fault_converged) */
    {"all at once: xi_p 0, k_a .95, f_e 10, e_m 10", "table3", 1.45,
     P_(WG_P_XI_P, WG_P_K_A, WG_P_F_E, WG_P_E_M), {0, 0.95, 10, 10}, 400, 1},
    {"lowfreq, xi_p 0, k_a .95", "lowfreq", 0.5, P_(WG_P_XI_P, WG_P_K_A), {0, 0.95}, 400, -1},
    {"realistic, f_e 10, omega 10", "realistic", 10.0, P_(WG_P_F_E), {10}, 800, 0},
    /* undamped Mathieu oscillator at its principal parametric resonance:
     * the amplitude grows like exp(k_a tau / 4) -- must end in a clean fault */
    {"torsional undamped, k_a .95, omega 2", "torsional", 2.0,
     P_(WG_P_XI_P, WG_P_XI_G, WG_P_K_A, WG_P_B, WG_P_E_M), {0, 0, 0.95, 0, 0}, 4000, 1},
    {"same with backlash b = 1", "torsional", 2.0, P_(WG_P_XI_P, WG_P_XI_G, WG_P_K_A),
     {0, 0, 0.95}, 4000, -1},
};

static void test_extreme_parameters(void)
{
    printf("  %-44s %-9s %5s  %-11s %9s %8s %s\n", "case", "stepper", "N", "result", "periods",
           "max|y|", "events");
    for (unsigned i = 0; i < sizeof cases / sizeof cases[0]; i++) {
        const xcase *c = &cases[i];
        wg_params p = stress_scene(c->scene);
        p.v[WG_P_OMEGA] = c->omega;
        for (int j = 0; c->set[j] >= 0; j++)
            p.v[c->set[j]] = c->val[j];
        char why[300];
        ASSERT_EQ_INT(wg_params_check(&p, why, sizeof why), WG_OK); /* within the table */
        int nmin = wg_min_steps(wg_rk4_hmax(WG_MODEL_CONSISTENT, &p), c->omega);
        int N = nmin > 128 ? nmin : 128;
        for (int st = 0; st < 2; st++) {
            wg_sim s;
            ASSERT_EQ_INT(test_sim_init(&s, &p, st, N), WG_OK);
            watch w = {0, 0, 0, 0};
            wg_sink sink = {&w, NULL, on_sec, on_ev};
            uint64_t done = 0, want = (uint64_t)N * (uint64_t)c->periods;
            int rc = wg_sim_run(&s, want, &sink, &done);
            printf("  %-44s %-9s %5d  %-11s %9.1f %8.3g %llu\n", c->what, wg_stepper_name(st), N,
                   rc == WG_OK ? "bounded" : wg_status_name(rc), (double)done / N,
                   fmax(w.maxabs, stress_maxabs(s.y, 14)), (unsigned long long)w.nev);
            ASSERT_TRUE(rc == WG_OK || rc == WG_ENONFINITE);
            ASSERT_EQ_INT(w.bad, 0);              /* no NaN ever reached a sink */
            ASSERT_TRUE(stress_finite(s.y, 14));  /* the kept state is a good one */
            ASSERT_EQ_INT(s.steps, done);
            ASSERT_EQ_INT(w.nsec, done / N);
            if (rc == WG_OK) {
                ASSERT_EQ_INT(done, want);
                double sum = 0;
                for (int k = 0; k < 14; k++)
                    sum += fabs(s.y[k]);
                ASSERT_TRUE(sum < 1e9);
            } else {
                ASSERT_TRUE(done < want);
                /* the fault is sticky until the state is replaced: the
                 * same call fails again at once, applying nothing */
                double y[16];
                memcpy(y, s.y, sizeof y);
                uint64_t d2 = 99;
                ASSERT_EQ_INT(wg_sim_run(&s, 10, &sink, &d2), WG_ENONFINITE);
                ASSERT_EQ_INT(d2, 0);
                ASSERT_TRUE(memcmp(y, s.y, sizeof y) == 0);
            }
            if (c->expect == 0)
                ASSERT_EQ_INT(rc, WG_OK);
            if (c->expect == 1)
                ASSERT_EQ_INT(rc, WG_ENONFINITE);
            wg_sim_fini(&s);
        }
    }
}

/* The "all at once" fault is the model's own parametric instability, not
 * RK4's: the run stops at the same time for N = 128 and 1024, and mesh
 * damping at the scene's 0.08 removes it. */
static void test_physical_fault_converged(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = 1.45;
    p.v[WG_P_XI_P] = 0;
    p.v[WG_P_K_A] = 0.95;
    p.v[WG_P_F_E] = p.v[WG_P_E_M] = 10;
    double at[2];
    for (int r = 0; r < 2; r++) {
        int N = r ? 1024 : 128;
        wg_sim s;
        ASSERT_EQ_INT(test_sim_init(&s, &p, WG_STEPPER_RK4_EVENT, N), WG_OK);
        uint64_t done = 0;
        ASSERT_EQ_INT(wg_sim_run(&s, (uint64_t)N * 400, NULL, &done), WG_ENONFINITE);
        at[r] = s.tau;
        wg_sim_fini(&s);
    }
    printf("  fault at tau %.2f (N 128) and %.2f (N 1024)\n", at[0], at[1]);
    ASSERT_NEAR(at[0], at[1], 0.01 * at[1]);
    p.v[WG_P_XI_P] = 0.08;
    wg_sim s;
    ASSERT_EQ_INT(test_sim_init(&s, &p, WG_STEPPER_RK4_EVENT, 128), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(&s, 128 * 400, NULL, NULL), WG_OK);
    wg_sim_fini(&s);
}

TEST_MAIN(TEST(test_extreme_parameters), TEST(test_physical_fault_converged))

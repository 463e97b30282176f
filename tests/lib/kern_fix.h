/* kern_fix.h - the setup the kernel tests share (test_model: each kernel
 * against the reference step; test_dispatch: each instruction set against
 * the baseline; test_pair: paired runs against single ones): a state with
 * every contact engaged somewhere interesting, the parameters on which the
 * flags f are exactly the kernel wg_sim selects, a sim built on them with
 * its state, and an rk4-event sim on a chosen instruction set. */
#ifndef WG_TEST_KERN_FIX_H
#define WG_TEST_KERN_FIX_H

#include "test.h"
#include "internal.h"

#include <stdlib.h>
#include "wormgear/wg_sim.h"
#include "wormgear/wg_status.h"

static inline void some_state(double *y)
{
    static const double v[14] = {1.3, -0.2, -1.7, 0.4, 1.05, -2.2, 1.9,
                                 0.11, -0.3, 0.25, -0.07, 0.5, -0.41, 0.33};
    memcpy(y, v, sizeof v);
}

static inline double maxdiff(const double *a, const double *b, int n)
{
    double d = 0;
    for (int i = 0; i < n; i++)
        d = fmax(d, fabs(a[i] - b[i]));
    return d;
}

/* Flags no kernel has: b_j does not matter on the torsional path. */
static inline int kfix_skip(unsigned f) { return !(f & KF_BEAR) && (f & KF_BJ); }

/* Parameters on which the flags f are exactly the kernel wg_sim selects. */
static inline void params_for(unsigned f, wg_params *p)
{
    wg_params_default(p);
    if (!(f & KF_EM))
        p->v[WG_P_E_M] = 0;
    if (!(f & KF_KA))
        p->v[WG_P_K_A] = 0;
    if (!(f & KF_MB))
        p->v[WG_P_B] = 0;
    if (!(f & KF_BJ))
        p->v[WG_P_B_J] = 0;
    if (!(f & KF_BEAR))
        p->v[WG_P_MU1] = p->v[WG_P_MU2] = 0;
}

/* A sim (N = 128) on params_for(f), checked to have selected kernel f, and
 * some_state in y0 with the bearings at rest on the torsional path. */
static inline void kfix_setup(unsigned f, wg_params *p, wg_sim *s, double y0[16])
{
    params_for(f, p);
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, (f & KF_LOCK) ? 1 : 0, 128};
    char why[300];
    ASSERT_EQ_INT(wg_sim_init(s, p, &cfg, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(s->core->kflags, f);
    for (int i = 0; i < 16; i++)
        y0[i] = 0;
    some_state(y0);
    if (!(f & KF_BEAR))
        for (int i = 0; i < 6; i++)
            y0[i] = y0[7 + i] = 0;
}

/* An rk4-event sim of p with N steps per period on instruction set isa
 * (by WG_ISA, as a user would choose it). */
static inline void kfix_sim_on(wg_sim *s, const wg_params *p, int N, int isa)
{
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, N};
    char why[300];
    if (setenv("WG_ISA", kernel_isa_name(isa), 1) != 0)
        abort();
    ASSERT_EQ_INT(wg_sim_init(s, p, &cfg, why, sizeof why), WG_OK);
    unsetenv("WG_ISA");
    ASSERT_EQ_INT(s->core->isa, isa);
}

#endif

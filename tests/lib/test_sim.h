/* test_sim.h - wg_sim set-up shared by the unit and stress tests. */
#ifndef WG_TEST_SIM_H
#define WG_TEST_SIM_H

#include "test.h"
#include "wormgear/wg_sim.h"
#include "wormgear/wg_status.h"

/* wg_sim_init of the consistent form; prints the reason when it fails. */
static inline int test_sim_init(wg_sim *s, const wg_params *p, int stepper, int N)
{
    char why[400];
    wg_sim_config cfg = {WG_MODEL_CONSISTENT, stepper, N};
    int rc = wg_sim_init(s, p, &cfg, why, sizeof why);
    if (rc)
        fprintf(stderr, "wg_sim_init(N=%d): %s\n", N, why);
    return rc;
}

/* A sim that must initialise (the current test fails otherwise). */
static inline wg_sim test_sim_make(const wg_params *p, int stepper, int N)
{
    wg_sim s;
    ASSERT_EQ_INT(test_sim_init(&s, p, stepper, N), WG_OK);
    return s;
}

#endif

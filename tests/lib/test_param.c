/* Parameter table: lookup, parsing, ranges, cross-checks, status names. */
#include "test.h"
#include "wormgear/wg_param.h"
#include "wormgear/wg_status.h"

#include <stdio.h>

static void test_every_row_is_consistent(void)
{
    wg_params p;
    wg_params_default(&p);
    for (int i = 0; i < WG_NPARAM; i++) {
        const wg_param_info *r = wg_param_info_get(i);
        ASSERT_TRUE(r && r->name && r->unit && r->help);
        ASSERT_TRUE(r->min < r->max);
        ASSERT_TRUE(r->def >= r->min && r->def <= r->max);
        ASSERT_EQ_INT(wg_param_lookup(r->name), i);
    }
    ASSERT_EQ_INT(wg_params_check(&p, NULL, 0), WG_OK);
    ASSERT_TRUE(wg_param_info_get(WG_NPARAM) == NULL);
    ASSERT_EQ_INT(wg_param_lookup("nope"), -1);
}

static void test_direction_cosines_unit(void)
{
    wg_params p;
    wg_params_default(&p);
    double a1 = p.v[WG_P_A1], a2 = p.v[WG_P_A2], a3 = p.v[WG_P_A3];
    ASSERT_NEAR(a1 * a1 + a2 * a2 + a3 * a3, 1.0, 1e-14);
    /* from alpha_n = 20 deg, beta = atan(3 * 4 / 44) */
    double an = 20.0 * M_PI / 180.0, beta = atan(12.0 / 44.0);
    ASSERT_NEAR(a1, cos(an) * sin(beta), 1e-15);
    ASSERT_NEAR(a2, sin(an), 1e-15);
    ASSERT_NEAR(a3, cos(an) * cos(beta), 1e-15);
    char why[200];
    p.v[WG_P_A1] = 0.5;
    ASSERT_EQ_INT(wg_params_check(&p, why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "a1^2 + a2^2 + a3^2");
}

static void test_parse_and_assign(void)
{
    wg_params p;
    wg_params_default(&p);
    char why[200];
    ASSERT_EQ_INT(wg_param_assign(&p, "omega=1.3", why, sizeof why), WG_OK);
    ASSERT_NEAR(p.v[WG_P_OMEGA], 1.3, 0);
    ASSERT_EQ_INT(wg_param_assign(&p, "omega=99", why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "omega = 99 out of range [0.01, 10]");
    ASSERT_NEAR(p.v[WG_P_OMEGA], 1.3, 0); /* unchanged on error */
    ASSERT_EQ_INT(wg_param_assign(&p, "omega=1.2x", why, sizeof why), WG_EINVAL);
    ASSERT_CONTAINS(why, "not a number");
    ASSERT_EQ_INT(wg_param_assign(&p, "omega=nan", why, sizeof why), WG_ERANGE);
    ASSERT_EQ_INT(wg_param_assign(&p, "omega=inf", why, sizeof why), WG_ERANGE);
    ASSERT_EQ_INT(wg_param_assign(&p, "omega=", why, sizeof why), WG_EINVAL);
    ASSERT_EQ_INT(wg_param_assign(&p, "omegax=1", why, sizeof why), WG_EUNKNOWN);
    ASSERT_CONTAINS(why, "unknown parameter 'omegax'");
    ASSERT_EQ_INT(wg_param_assign(&p, "omega", why, sizeof why), WG_EINVAL);
    ASSERT_EQ_INT(wg_param_assign(&p, "k_a=0.95", why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_param_assign(&p, "k_a=0.96", why, sizeof why), WG_ERANGE);
}

static void test_status_names(void)
{
    ASSERT_STR(wg_status_name(WG_OK), "OK");
    ASSERT_STR(wg_status_name(WG_ERANGE), "ERANGE");
    ASSERT_STR(wg_status_name(WG_EDECODE), "EDECODE");
    ASSERT_STR(wg_status_name(12345), "EUNKNOWNCODE");
    ASSERT_TRUE(strlen(wg_status_str(WG_ESTABILITY)) > 5);
}

/* A range as help texts show it is accepted as shown: each bound, copied
 * back, is in range (before: %g's "[-6.28319, 6.28319]" for phi1, and
 * set phi1=6.28319 was refused), and at most 1e-5 (relative) inside. */
static void test_range_shown_is_accepted(void)
{
    for (int i = 0; i < WG_NPARAM; i++) {
        const wg_param_info *r = wg_param_info_get(i);
        char buf[64], why[200];
        double lo, hi;
        wg_range_shown(r->min, r->max, buf, sizeof buf);
        ASSERT_EQ_INT(sscanf(buf, "[%lf, %lf]", &lo, &hi), 2);
        ASSERT_EQ_INT(wg_param_check(i, lo, why, sizeof why), WG_OK);
        ASSERT_EQ_INT(wg_param_check(i, hi, why, sizeof why), WG_OK);
        ASSERT_TRUE(lo - r->min <= 1e-5 * (1 + fabs(r->min)));
        ASSERT_TRUE(r->max - hi <= 1e-5 * (1 + fabs(r->max)));
    }
    char buf[64];
    ASSERT_STR(wg_range_shown(-2 * M_PI, 2 * M_PI, buf, sizeof buf), "[-6.28318, 6.28318]");
    ASSERT_STR(wg_range_shown(0, 0.95, buf, sizeof buf), "[0, 0.95]");
}

TEST_MAIN(TEST(test_every_row_is_consistent), TEST(test_direction_cosines_unit),
          TEST(test_parse_and_assign), TEST(test_status_names),
          TEST(test_range_shown_is_accepted))

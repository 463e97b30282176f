/* theta1, theta2: the derived rotation angles of MODEL.md s2 (wg_angles,
 * wg_sim_angles) and the body rows of the parameter table they use. */
#include "test.h"
#include "wormgear/wg_model.h"
#include "wormgear/wg_param.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_sim.h"
#include "wormgear/wg_status.h"

#include <string.h>

#define TWO_PI 6.283185307179586
enum { N = 128 };

/* a - b as an angle in (-pi, pi]. */
static double adiff(double a, double b)
{
    double d = fmod(a - b, TWO_PI);
    return d > M_PI ? d - TWO_PI : d <= -M_PI ? d + TWO_PI : d;
}

static wg_sim start(const wg_params *p, int model)
{
    wg_sim s;
    char why[300];
    wg_sim_config cfg = {model, WG_STEPPER_DEFAULT, N};
    memset(&s, 0, sizeof s);
    if (wg_sim_init(&s, p, &cfg, why, sizeof why) != WG_OK)
        TEST_FAIL_("init: %s", why);
    return s;
}

/* The elastic parts e = theta - rigid (rigid: mesh phase over the teeth). */
static void elastic(const wg_params *p, uint64_t period, double psi, const double th[2],
                    double e[2])
{
    double z1 = p->v[WG_P_Z1], z2 = p->v[WG_P_Z2];
    e[0] = adiff(th[0], (TWO_PI * (double)(period % (uint64_t)z1) + psi) / z1);
    e[1] = adiff(th[1], (TWO_PI * (double)(period % (uint64_t)z2) + psi) / z2);
}

/* The elastic split: kinematics a1 rho1 e1 - a3 rho2 e2 = s, and the mesh
 * force's equal and opposite lever-arm impulses I1 e1 / (a1 R1) =
 * -I2 e2 / (a3 R2), i.e. j1 rho1 e1 / a1 = -j2 rho2 e2 / a3. */
static void check_split(const wg_params *p, double s, const double e[2], double tol)
{
    double a1 = p->v[WG_P_A1], a3 = p->v[WG_P_A3];
    double r1 = p->v[WG_P_RHO1], r2 = p->v[WG_P_RHO2];
    ASSERT_NEAR(a1 * r1 * e[0] - a3 * r2 * e[1], s, tol * (1 + fabs(s)));
    ASSERT_NEAR(p->v[WG_P_J1] * r1 * e[0] / a1, -p->v[WG_P_J2] * r2 * e[1] / a3,
                tol * (1 + fabs(s)));
}

static void test_start_and_split(void)
{
    wg_params p;
    wg_params_default(&p);
    wg_sim s = start(&p, WG_MODEL_CONSISTENT);
    double th[2], e[2];
    wg_sim_angles(&s, th);
    elastic(&p, 0, 0.0, th, e);
    /* under the mean load the worm leads (s > 0) and the wheel lags */
    ASSERT_TRUE(s.y[6] > 0 && e[0] > 0 && e[1] < 0);
    check_split(&p, s.y[6], e, 1e-12);
    printf("  equilibrium s = %.6g: theta1 %+.6g rad, theta2 %+.6g rad (worm leads, wheel "
           "lags)\n", s.y[6], e[0], e[1]);
    /* other body data: the split follows it, the motion does not */
    wg_params q = p;
    q.v[WG_P_J1] = 3.0, q.v[WG_P_J2] = 0.05, q.v[WG_P_RHO1] = 57, q.v[WG_P_Z2] = 61;
    wg_sim t = start(&q, WG_MODEL_CONSISTENT);
    ASSERT_EQ_INT(wg_sim_run(&s, N * 20 + 17, NULL, NULL), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(&t, N * 20 + 17, NULL, NULL), WG_OK);
    ASSERT_TRUE(memcmp(s.y, t.y, sizeof s.y) == 0);
    wg_sim_angles(&t, th);
    elastic(&q, t.period, wg_sim_psi(&t), th, e);
    check_split(&q, t.y[6], e, 1e-12);
    wg_sim_fini(&s);
    wg_sim_fini(&t);
}

/* Rigid rotation: over a run the unwrapped angles advance by the mesh phase
 * over the teeth, so theta1 turns z2/z1 times as fast as theta2 and each
 * returns after z periods; every section agrees with the step's angles. */
typedef struct secs {
    const wg_params *p;
    int n;
    double worst;
    double prev[2], jump; /* on_step: the angles of the last step, largest change */
    long steps;
} secs;

static void on_step(void *ctx, const wg_sim *s)
{
    secs *c = ctx;
    double th[2];
    wg_sim_angles(s, th);
    if (c->steps++)
        for (int j = 0; j < 2; j++)
            c->jump = fmax(c->jump, fabs(adiff(th[j], c->prev[j])));
    memcpy(c->prev, th, sizeof th);
}

static void on_section(void *ctx, const wg_section *sec)
{
    secs *c = ctx;
    double th[2], e[2];
    wg_angles(WG_MODEL_CONSISTENT, c->p, sec->stats.period + 1, 0.0, sec->y, th);
    elastic(c->p, sec->stats.period + 1, 0.0, th, e);
    check_split(c->p, sec->y[6], e, 1e-12);
    c->worst = fmax(c->worst, fabs(e[0]) + fabs(e[1]));
    c->n++;
}

static void test_rigid_rotation(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = 0.7; /* impacting: s swings */
    wg_sim s = start(&p, WG_MODEL_CONSISTENT);
    double prev[2], th[2], turn[2] = {0, 0}, el0[2], el[2];
    wg_sim_angles(&s, prev);
    elastic(&p, 0, 0.0, prev, el0);
    secs c = {&p, 0, 0, {0, 0}, 0, 0};
    wg_sink sink = {&c, on_step, on_section, NULL};
    uint64_t steps = (uint64_t)N * 37 * 3; /* 3 wheel turns, 37 worm turns */
    for (uint64_t i = 0; i < steps; i++) {
        ASSERT_EQ_INT(wg_sim_run(&s, 1, &sink, NULL), WG_OK);
        wg_sim_angles(&s, th);
        ASSERT_TRUE(th[0] >= 0 && th[0] < TWO_PI && th[1] >= 0 && th[1] < TWO_PI);
        for (int j = 0; j < 2; j++) {
            turn[j] += adiff(th[j], prev[j]);
            prev[j] = th[j];
        }
    }
    elastic(&p, s.period, wg_sim_psi(&s), th, el);
    /* rigid part: 111 periods of mesh phase over z1 = 3 and z2 = 37 */
    double rig1 = turn[0] - (el[0] - el0[0]), rig2 = turn[1] - (el[1] - el0[1]);
    ASSERT_NEAR(rig1, TWO_PI * 111 / 3, 1e-9);
    ASSERT_NEAR(rig2, TWO_PI * 111 / 37, 1e-9);
    ASSERT_EQ_INT(c.n, 111);
    /* seen from on_step too, every step turns the worm by about 2 pi / (z1 N) */
    ASSERT_TRUE(c.jump < 2 * TWO_PI / (3 * N));
    printf("  111 mesh periods: worm %.9f turns, wheel %.9f turns (ratio %.9f = z2/z1), %d "
           "sections consistent, elastic parts up to %.3g rad\n",
           rig1 / TWO_PI, rig2 / TWO_PI, rig1 / rig2, c.n, c.worst);
    wg_sim_fini(&s);
}

/* Days of running: a period count of 1e12 and more stays exact (only its
 * residue modulo z enters), every angle in [0, 2 pi). */
static void test_long_runs(void)
{
    wg_params p;
    wg_params_default(&p);
    double y[WG_NSTATE_MAX] = {0}, th[2];
    const uint64_t big[] = {1000000000000ull, 18446744073709551615ull, 3 * 37 * 1000003ull};
    for (int i = 0; i < 3; i++) {
        wg_angles(WG_MODEL_CONSISTENT, &p, big[i], 1.0, y, th);
        ASSERT_NEAR(th[0], (TWO_PI * (double)(big[i] % 3) + 1.0) / 3, 1e-15);
        ASSERT_NEAR(th[1], (TWO_PI * (double)(big[i] % 37) + 1.0) / 37, 1e-15);
    }
    /* rows the table would refuse (a caller's own wg_params) never divide by
     * zero: a count below 1 or not a number is taken as 1 */
    wg_params q = p;
    q.v[WG_P_Z1] = 0, q.v[WG_P_Z2] = NAN;
    wg_angles(WG_MODEL_CONSISTENT, &q, 12345, 1.0, y, th);
    ASSERT_TRUE(th[0] == 1.0 && th[1] == 1.0);
    /* a huge elastic part still wraps into [0, 2 pi) */
    y[6] = -1e6;
    for (double psi = 0; psi < TWO_PI; psi += 0.1) {
        wg_angles(WG_MODEL_CONSISTENT, &p, 5, psi, y, th);
        ASSERT_TRUE(th[0] >= 0 && th[0] < TWO_PI && th[1] >= 0 && th[1] < TWO_PI);
    }
}

/* The physical scene carries the same body: the same angles as table3. */
static void test_physical_scene(void)
{
    wg_scene a, b;
    char why[300];
    ASSERT_EQ_INT(wg_scene_open(&a, "table3", why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_scene_open(&b, "table3-physical", why, sizeof why), WG_OK);
    ASSERT_TRUE(b.p.v[WG_P_Z1] == 3 && b.p.v[WG_P_Z2] == 37);
    ASSERT_NEAR(b.p.v[WG_P_RHO1], 220, 1e-9);
    ASSERT_NEAR(b.p.v[WG_P_RHO2], 740, 1e-9);
    for (int id = WG_P_J1; id <= WG_P_J2; id++)
        ASSERT_NEAR(b.p.v[id] / a.p.v[id], 1.0, 2e-4);
    wg_sim sa = start(&a.p, WG_MODEL_CONSISTENT), sb = start(&b.p, WG_MODEL_CONSISTENT);
    double worst = 0, ta[2], tb[2];
    for (int i = 0; i < 40; i++) {
        ASSERT_EQ_INT(wg_sim_run(&sa, N + 3, NULL, NULL), WG_OK);
        ASSERT_EQ_INT(wg_sim_run(&sb, N + 3, NULL, NULL), WG_OK);
        wg_sim_angles(&sa, ta);
        wg_sim_angles(&sb, tb);
        worst = fmax(worst, fmax(fabs(adiff(ta[0], tb[0])), fabs(adiff(ta[1], tb[1]))));
    }
    ASSERT_TRUE(worst < 1e-6);
    printf("  table3 and table3-physical: angles agree to %.2g rad over 40 periods\n", worst);
    wg_sim_fini(&sa);
    wg_sim_fini(&sb);
}

/* The printed form's th1, th2 (lengths along the line of action). */
static void test_printed(void)
{
    wg_params p;
    wg_params_default(&p);
    double y[WG_NSTATE_MAX] = {0}, th[2];
    y[6] = 0.44, y[7] = 0.22;
    wg_angles(WG_MODEL_PRINTED, &p, 0, 0.0, y, th);
    ASSERT_NEAR(th[0], 0.44 / 220, 1e-15);
    ASSERT_NEAR(th[1], TWO_PI - 0.22 / 740, 1e-15);
}

static void test_body_rows(void)
{
    char why[200];
    wg_params p;
    wg_params_default(&p);
    for (int id = WG_NPARAM_DYN; id < WG_NPARAM; id++) {
        const wg_param_info *r = wg_param_info_get(id);
        ASSERT_TRUE((r->flags & WG_PF_BODY) && !(r->flags & WG_PF_RAMP));
    }
    for (int id = 0; id < WG_NPARAM_DYN; id++)
        ASSERT_TRUE(!(wg_param_info_get(id)->flags & WG_PF_BODY));
    ASSERT_EQ_INT(wg_param_assign(&p, "z1=2.5", why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "z1 = 2.5 must be a whole number in [1, 12]");
    ASSERT_EQ_INT(wg_param_assign(&p, "z2=3", why, sizeof why), WG_ERANGE);
    ASSERT_CONTAINS(why, "z2 = 3 out of range [4, 1000]");
    ASSERT_EQ_INT(wg_param_assign(&p, "z2=1e300", why, sizeof why), WG_ERANGE);
    ASSERT_EQ_INT(wg_param_assign(&p, "j1=0", why, sizeof why), WG_ERANGE);
    ASSERT_EQ_INT(wg_param_assign(&p, "z2=41", why, sizeof why), WG_OK);
    ASSERT_TRUE(p.v[WG_P_Z2] == 41);
    /* table3's body data: the defaults give the m_e of MODEL.md s3 (D = 1) */
    double a1 = p.v[WG_P_A1], a3 = p.v[WG_P_A3];
    ASSERT_NEAR(a1 * a1 / p.v[WG_P_J1] + a3 * a3 / p.v[WG_P_J2], 1.0, 1e-4);
}

TEST_MAIN(TEST(test_start_and_split), TEST(test_rigid_rotation), TEST(test_long_runs),
          TEST(test_physical_scene), TEST(test_printed), TEST(test_body_rows))

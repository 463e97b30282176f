/* The transitions table on a synthetic sweep whose transitions are known:
 * grazing at 0.2, a jump with hysteresis [0.40, 0.55], period doublings at
 * 0.605 and 0.705, chaos 0.75-0.85 with a period-3 window, period-2 after,
 * return to period-1 at 0.905. */
#include "test.h"
#include "wormgear/wg_sweep.h"

enum { NP = 101 };

/* The attractor at grid index i on branch 'big' (1) or 'small' (0). */
static wg_point synth(int i, int big)
{
    double v = i / 100.0;
    wg_point p = {0};
    p.value = v;
    p.regime = WG_REGIME_PERIODIC;
    p.period = 1;
    p.converged = 1;
    p.min_xn = 1.2 - v;               /* crosses b = 1 at v = 0.2 */
    p.max_xn = big ? 2.0 + v : 1.5 + v;
    p.motion = p.min_xn > 1.0 ? WG_MOTION_NO_IMPACT : WG_MOTION_SINGLE;
    if (i >= 61)
        p.period = 2;
    if (i >= 71)
        p.period = 4;
    if (i >= 75 && i <= 85) {
        p.regime = WG_REGIME_CHAOTIC;
        p.period = 0;
    }
    if (i == 80) {
        p.regime = WG_REGIME_PERIODIC;
        p.period = 3;
    }
    if (i > 85 && i <= 90)
        p.period = 2;
    if (i > 90)
        p.period = 1;
    if (i >= 95)
        p.motion = WG_MOTION_DOUBLE, p.min_xn = -1.2;
    return p;
}

static void make(wg_point *up, wg_point *down)
{
    for (int i = 0; i < NP; i++) {
        up[i] = synth(i, i > 55);                 /* up stays small up to 0.55 */
        down[NP - 1 - i] = synth(i, i >= 40);     /* down stays big down to 0.40 */
    }
}

static const wg_transition *find(const wg_transition *t, int n, int kind, int dir, int k)
{
    for (int i = 0; i < n; i++)
        if (t[i].kind == kind && t[i].dir == dir && k-- == 0)
            return &t[i];
    return NULL;
}

static int count(const wg_transition *t, int n, int kind, int dir)
{
    int c = 0;
    for (int i = 0; i < n; i++)
        c += t[i].kind == kind && t[i].dir == dir;
    return c;
}

static void test_synthetic_table(void)
{
    static wg_point up[NP], down[NP];
    wg_transition t[64];
    make(up, down);
    int n = wg_transitions(up, NP, down, NP, 1.0, t, 64);
    ASSERT_TRUE(n > 0);
    const wg_transition *g = find(t, n, WG_TR_GRAZING, +1, 0);
    ASSERT_TRUE(g != NULL);
    if (g) {
        ASSERT_NEAR(g->at, 0.2, 1e-9);
        ASSERT_EQ_INT(g->from, WG_MOTION_NO_IMPACT);
        ASSERT_EQ_INT(g->to, WG_MOTION_SINGLE);
    }
    ASSERT_EQ_INT(count(t, n, WG_TR_GRAZING, +1), 1);
    ASSERT_EQ_INT(count(t, n, WG_TR_GRAZING, -1), 1);
    const wg_transition *j = find(t, n, WG_TR_JUMP, 0, 0);
    ASSERT_EQ_INT(count(t, n, WG_TR_JUMP, 0), 1);
    if (j) {
        ASSERT_NEAR(j->lo, 0.55, 1e-12); /* up sweep jumps in (0.55, 0.56) */
        ASSERT_NEAR(j->hi, 0.56, 1e-12);
        ASSERT_NEAR(j->lo2, 0.39, 1e-12); /* down sweep jumps in (0.39, 0.40) */
        ASSERT_NEAR(j->hi2, 0.40, 1e-12);
    }
    const wg_transition *d1 = find(t, n, WG_TR_DOUBLING, +1, 0);
    const wg_transition *d2 = find(t, n, WG_TR_DOUBLING, +1, 1);
    ASSERT_TRUE(d1 && d2);
    if (d1 && d2) {
        ASSERT_NEAR(d1->at, 0.605, 1e-12);
        ASSERT_EQ_INT(d1->from, 1);
        ASSERT_EQ_INT(d1->to, 2);
        ASSERT_NEAR(d2->at, 0.705, 1e-12);
        ASSERT_EQ_INT(d2->to, 4);
    }
    ASSERT_EQ_INT(count(t, n, WG_TR_DOUBLING, -1), 2); /* seen from above too */
    const wg_transition *c = find(t, n, WG_TR_CHAOS, +1, 0);
    ASSERT_EQ_INT(count(t, n, WG_TR_CHAOS, +1), 1); /* the window stays inside */
    if (c) {
        ASSERT_NEAR(c->lo, 0.75, 1e-12);
        ASSERT_NEAR(c->hi, 0.85, 1e-12);
        ASSERT_EQ_INT(c->from, 10);
        ASSERT_EQ_INT(c->to, 1);
    }
    const wg_transition *r = find(t, n, WG_TR_RETURN_P1, +1, 0);
    ASSERT_EQ_INT(count(t, n, WG_TR_RETURN_P1, +1), 1);
    if (r) {
        ASSERT_NEAR(r->at, 0.905, 1e-12);
        ASSERT_EQ_INT(r->from, 2);
    }
    ASSERT_EQ_INT(count(t, n, WG_TR_BACKSIDE, +1), 1);
    for (int i = 1; i < n; i++) /* sorted */
        ASSERT_TRUE((t[i].kind == WG_TR_JUMP ? t[i].lo2 : t[i].at) >=
                    (t[i - 1].kind == WG_TR_JUMP ? t[i - 1].lo2 : t[i - 1].at));
}

static void test_partial_and_empty(void)
{
    static wg_point up[NP], down[NP];
    wg_transition t[64];
    make(up, down);
    ASSERT_EQ_INT(wg_transitions(up, 0, down, 0, 1.0, t, 64), 0);
    /* an interrupted down sweep: only its first 30 points (0.71..1.00) */
    int n = wg_transitions(up, NP, down, 30, 1.0, t, 64);
    ASSERT_EQ_INT(count(t, n, WG_TR_JUMP, 0), 0); /* no hysteresis without both */
    ASSERT_EQ_INT(count(t, n, WG_TR_GRAZING, -1), 0);
    ASSERT_EQ_INT(count(t, n, WG_TR_CHAOS, -1), 1);
    /* a short output buffer is filled, not overrun */
    ASSERT_EQ_INT(wg_transitions(up, NP, down, NP, 1.0, t, 3), 3);
}

/* A sweep of b itself (b = NAN): grazing is where min x_n crosses each
 * point's own b. Here min x_n = 0.25 + 0.5 v at b = v: it crosses b at
 * v = 0.5 alone, and never crosses a fixed b = 1 (the scene's, which the
 * table once used: it reported grazing where min x_n met 1). */
static void test_b_swept(void)
{
    static wg_point up[NP];
    for (int i = 0; i < NP; i++) {
        wg_point *p = &up[i];
        memset(p, 0, sizeof *p);
        p->value = i / 100.0;
        p->regime = WG_REGIME_PERIODIC;
        p->period = p->converged = 1;
        p->min_xn = 0.25 + 0.5 * p->value;
        p->max_xn = p->min_xn + 1.0;
        p->motion = p->min_xn > p->value ? WG_MOTION_NO_IMPACT : WG_MOTION_SINGLE;
    }
    wg_transition t[64];
    int n = wg_transitions(up, NP, NULL, 0, NAN, t, 64);
    ASSERT_EQ_INT(count(t, n, WG_TR_GRAZING, +1), 1);
    const wg_transition *g = find(t, n, WG_TR_GRAZING, +1, 0);
    ASSERT_TRUE(g != NULL);
    ASSERT_NEAR(g->at, 0.5, 1e-12); /* linear: interpolated exactly */
    n = wg_transitions(up, NP, NULL, 0, 1.0, t, 64); /* min x_n stays under b = 1 */
    ASSERT_EQ_INT(count(t, n, WG_TR_GRAZING, +1), 0);
}

TEST_MAIN(TEST(test_synthetic_table), TEST(test_partial_and_empty), TEST(test_b_swept))

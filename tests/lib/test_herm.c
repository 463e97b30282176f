/* The cubic Hermite of a coordinate over one step (lib/wg_herm.c), white
 * box: its rate, its crossings (herm_root: where rk4-event's split step
 * starts its Newton refinement and where a smooth contact's event is
 * interpolated), its extrema and the turn inside a step. Each result is
 * checked against the same cubic evaluated in long double: random cubics
 * (seeded, printed), cubics with up to three crossings, crossings with a
 * rate near zero (grazing) and crossings at an end. */
#include "test.h"
#include "internal.h"

#include <math.h>
#include <stdint.h>

static uint64_t rng_state;

/* The generator's state from a seed: splitmix64, so that every seed (even
 * or odd, small or large) starts its own sequence. */
static void rng_seed(unsigned seed)
{
    uint64_t z = (uint64_t)seed + 0x9e3779b97f4a7c15u;
    z = (z ^ (z >> 30)) * 0xbf58476d1ce4e5b9u;
    z = (z ^ (z >> 27)) * 0x94d049bb133111ebu;
    rng_state = (z ^ (z >> 31)) | 1u; /* xorshift's state must not be 0 */
}

static double urand(double lo, double hi)
{
    rng_state ^= rng_state << 13; /* xorshift64 */
    rng_state ^= rng_state >> 7;
    rng_state ^= rng_state << 17;
    return lo + (hi - lo) * (double)(rng_state >> 11) * 0x1p-53;
}

/* H(t) and H'(t) in long double, in the power basis. */
static long double hval(const herm *H, long double t)
{
    long double q0 = H->q0, q1 = H->q1, d0 = H->d0, d1 = H->d1;
    long double p2 = 3 * (q1 - q0) - 2 * d0 - d1, p3 = 2 * (q0 - q1) + d0 + d1;
    return ((p3 * t + p2) * t + d0) * t + q0;
}

static long double hder(const herm *H, long double t)
{
    long double q0 = H->q0, q1 = H->q1, d0 = H->d0, d1 = H->d1;
    long double p2 = 3 * (q1 - q0) - 2 * d0 - d1, p3 = 2 * (q0 - q1) + d0 + d1;
    return (3 * p3 * t + 2 * p2) * t + d0;
}

/* Is t a crossing of H = c to within the claim, ~1e-15 in t? H - c must
 * change sign (or vanish) on [t - e, t + e] within [0, 1], where e is
 * 2e-15 plus what rounding H to double near the root (4e-16 of its terms:
 * the Hermite data and the power basis's p2 and p3, which herm_root
 * evaluates, up to ~4x the data) moves the root by at H's rate there, and
 * at most 1e-7 (a turning point, where the rate vanishes, must not pass for
 * a root). *worst: the largest distance seen from t to the sign change. */
static int near_crossing(const herm *H, double c, double t, double *worst)
{
    if (!(t >= 0.0 && t <= 1.0))
        return 0;
    long double q0 = H->q0, q1 = H->q1, d0 = H->d0, d1 = H->d1;
    long double p2 = 3 * (q1 - q0) - 2 * d0 - d1, p3 = 2 * (q0 - q1) + d0 + d1;
    long double scale = fabsl(q0) + fabsl(q1) + fabsl(d0) + fabsl(d1) + fabs(c) + fabsl(p2) +
                        fabsl(p3);
    long double slope = fabsl(hder(H, t));
    long double e = 2e-15L + 4e-16L * scale / (slope > 1e-300L ? slope : 1e-300L);
    if (e > 1e-7L)
        e = 1e-7L;
    long double lo = t - e < 0 ? 0 : t - e, hi = t + e > 1 ? 1 : t + e;
    long double flo = hval(H, lo) - c, fhi = hval(H, hi) - c, fm = hval(H, t) - c;
    int ok = (flo <= 0 && fhi >= 0) || (flo >= 0 && fhi <= 0) || fm == 0;
    /* how far the sign change lies from t (bisection in long double) */
    if (ok && flo * fhi < 0) {
        for (int i = 0; i < 80; i++) {
            long double m = 0.5L * (lo + hi), fmid = hval(H, m) - c;
            if ((fmid < 0) == (flo < 0))
                lo = m, flo = fmid;
            else
                hi = m;
        }
        double d = (double)fabsl(0.5L * (lo + hi) - t);
        if (d > *worst)
            *worst = d;
    }
    return ok;
}

/* Random cubics whose ends lie on either side of c: every root found is a
 * crossing to ~1e-15 in t. */
static void test_root_random(void)
{
    rng_seed(test_seed("herm_root cubics"));
    int bad = 0, n = 0, multi = 0;
    double worst = 0.0;
    while (n < 200000) {
        herm H = {urand(-2, 2), urand(-2, 2), urand(-3, 3), urand(-3, 3)};
        double c = urand(-2, 2);
        if (!((H.q0 - c) * (H.q1 - c) < 0))
            continue;
        n++;
        int signs = 0; /* sign changes of H - c on 64 samples: 3 for three crossings */
        for (int i = 1; i <= 64; i++)
            signs += (hval(&H, (i - 1) / 64.0L) > c) != (hval(&H, i / 64.0L) > c);
        multi += signs > 1;
        double t = herm_root(&H, c);
        if (!near_crossing(&H, c, t, &worst) && bad++ < 5)
            TEST_FAIL_("q0 %.17g q1 %.17g d0 %.17g d1 %.17g c %.17g: root %.17g", H.q0, H.q1,
                       H.d0, H.d1, c, t);
    }
    printf("  %d cubics (%d with three crossings): %d roots off by more than the claim; the "
           "farthest %.2g in t from its crossing\n", n, multi, bad, worst);
    ASSERT_EQ_INT(bad, 0);
    ASSERT_TRUE(multi > 100); /* the cases are there (~0.3 %) */
}

/* The Hermite data of a cubic given in the power basis (c = 0). */
static herm from_poly(double p0, double p1, double p2, double p3)
{
    return (herm){p0, p0 + p1 + p2 + p3, p1, p1 + 2 * p2 + 3 * p3};
}

/* Known roots: lines, the threshold at either end, three crossings,
 * grazing crossings (H - c = (t - m)^3 + eps (t - m): the rate eps at the
 * root m, off the middle so that the chord does not land on it), and a
 * step of an impacting run. */
static void test_root_cases(void)
{
    double worst = 0.0;
    /* straight line: H = q0 + (q1 - q0) t */
    herm L = {-0.25, 0.75, 1.0, 1.0};
    ASSERT_NEAR(herm_root(&L, 0.0), 0.25, 1e-15);
    ASSERT_NEAR(herm_root(&L, 0.5), 0.75, 1e-15);
    /* descending */
    herm D = {1.0, -1.0, -2.0, -2.0};
    ASSERT_NEAR(herm_root(&D, 0.0), 0.5, 1e-15);
    /* the threshold at an end: from below and from above to exactly c at
     * t = 1 is 1 (false position alone moved the bracket's end off it) */
    herm E = {1.0, 2.0, 1.0, 1.0}, F = {2.0, 1.0, -1.0, -1.0};
    ASSERT_NEAR(herm_root(&E, 1.0), 0.0, 1e-15);
    ASSERT_TRUE(herm_root(&E, 2.0) == 1.0);
    ASSERT_TRUE(herm_root(&F, 1.0) == 1.0);
    /* three crossings, 20 (t - 0.2)(t - 0.5)(t - 0.9): any of them */
    herm T = from_poly(-1.8, 20 * 0.73, -20 * 1.6, 20.0);
    double t = herm_root(&T, 0.0);
    ASSERT_TRUE(near_crossing(&T, 0.0, t, &worst));
    ASSERT_TRUE(fabs(t - 0.2) < 1e-14 || fabs(t - 0.5) < 1e-14 || fabs(t - 0.9) < 1e-14);
    /* grazing: the rate at the crossing 1e-1 ... 1e-8 of the coordinate's */
    for (int k = 1; k <= 8; k++) {
        double eps = pow(10.0, -k), m = 0.3;
        herm G = from_poly(-m * m * m - eps * m, 3 * m * m + eps, -3 * m, 1.0);
        t = herm_root(&G, 0.0);
        ASSERT_TRUE(near_crossing(&G, 0.0, t, &worst));
        ASSERT_NEAR(t, m, 1e-15 + 1e-15 / eps);
    }
    /* a step of an impacting run, q from just inside the clearance to past
     * it: H - 1 = 1e-5 (t^2 + 3 t - 1), the root (sqrt(13) - 3) / 2; q0 and
     * q1 rounded to double (1e-16) move it by 1e-16 / H' = 3e-12 */
    herm S = {0.99999, 1.00003, 0.00003, 0.00005};
    t = herm_root(&S, 1.0);
    ASSERT_NEAR(t, 0.30277563773199464, 1e-11);
    ASSERT_TRUE(near_crossing(&S, 1.0, t, &worst));
    printf("  farthest from its crossing: %.2g in t\n", worst);
}

/* herm_der is H' (per unit t); herm_min and herm_max are the extrema on
 * [0, 1]; herm_turn lowers or raises them only when the rate changes sign. */
static void test_extrema(void)
{
    rng_seed(test_seed("herm extrema"));
    int bad = 0;
    for (int n = 0; n < 20000; n++) {
        herm H = {urand(-2, 2), urand(-2, 2), urand(-3, 3), urand(-3, 3)};
        double t = urand(0, 1);
        if (fabs(herm_der(&H, t) - (double)hder(&H, t)) > 1e-14 && bad++ < 5)
            TEST_FAIL_("herm_der at %.17g: %.17g, %.17Lg", t, herm_der(&H, t), hder(&H, t));
        long double mn = INFINITY, mx = -INFINITY;
        for (int i = 0; i <= 4000; i++) {
            long double v = hval(&H, i / 4000.0L);
            mn = v < mn ? v : mn;
            mx = v > mx ? v : mx;
        }
        /* the sampled extremum is within |H''| / 2 (1/8000)^2 of the true one,
         * |H''| <= 18 (|q0| + |q1| + |d0| + |d1|): 1.4e-7 of that sum */
        double tol = 1e-12 + 1.5e-7 * (fabs(H.q0) + fabs(H.q1) + fabs(H.d0) + fabs(H.d1));
        double hmn = herm_min(&H), hmx = herm_max(&H);
        if ((!(hmn <= (double)mn + 1e-14) || !(hmn >= (double)mn - tol) ||
             !(hmx >= (double)mx - 1e-14) || !(hmx <= (double)mx + tol)) &&
            bad++ < 5)
            TEST_FAIL_("herm_min/max %.17g %.17g, sampled %.17Lg %.17Lg", hmn, hmx, mn, mx);
    }
    ASSERT_EQ_INT(bad, 0);
    /* herm_turn: rate -1 to +1 over h = 0.1 from q = 0 to 0 has its minimum
     * -h / 4 at the middle; no turn leaves both alone */
    double mn = 0.0, mx = 0.0;
    herm_turn(0.0, 0.0, -1.0, 1.0, 0.1, &mn, &mx);
    ASSERT_NEAR(mn, -0.025, 1e-16);
    ASSERT_NEAR(mx, 0.0, 0.0);
    mn = mx = 0.0;
    herm_turn(0.0, 0.1, 1.0, 1.0, 0.1, &mn, &mx);
    ASSERT_TRUE(mn == 0.0 && mx == 0.0);
    herm_turn(0.0, 0.0, 1.0, -1.0, 0.1, &mn, &mx);
    ASSERT_NEAR(mx, 0.025, 1e-16);
}

TEST_MAIN(TEST(test_root_random), TEST(test_root_cases), TEST(test_extrema))

/* Snapshots: wg_sim_restore validates every field exactly as the live path
 * does (parameters through wg_sim_set_params's checks, k < N, a finite
 * state, tau and its compensation term, the counters, the ramp as
 * wg_sim_ramp would accept it, the period statistics) and leaves the sim
 * unchanged when it refuses. The file format (wg_snapshot.h): a round trip
 * is bit-exact; every truncation and every single-byte change of a
 * formatted snapshot is refused by parse + restore; hostile text for each
 * kind of field is refused with a message that names the line and the field
 * and quotes nothing of the text. */
#include "test.h"
#include "test_sim.h"
#include "wormgear/wg_sim.h"
#include "wormgear/wg_snapshot.h"
#include "wormgear/wg_status.h"

#include <sodium.h>
#include <stdint.h>
#include <time.h>

enum { N = 128 };

/* A sim in the middle of an omega ramp, on an impacting orbit. */
static wg_sim mid_ramp(void)
{
    wg_params p;
    wg_params_default(&p);
    p.v[WG_P_OMEGA] = 1.35;
    wg_sim s = test_sim_make(&p, WG_STEPPER_RK4_EVENT, N);
    char why[300];
    ASSERT_EQ_INT(wg_sim_run(&s, N * 20 + 37, NULL, NULL), WG_OK);
    ASSERT_EQ_INT(wg_sim_ramp(&s, WG_P_OMEGA, NULL, 1.6, 2000.0, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(&s, 1001, NULL, NULL), WG_OK);
    ASSERT_TRUE(s.ramp.active);
    return s;
}

/* ---- hostile values: one mutation of a valid snapshot each ---------------- */

typedef struct hostile {
    const char *what;
    void (*mutate)(wg_snapshot *w);
    int rc;           /* the code wg_sim_restore must return */
    const char *says; /* ... and a part of its message */
} hostile;

static void m_model(wg_snapshot *w) { w->model = WG_MODEL_PRINTED; }
static void m_stepper(wg_snapshot *w) { w->stepper = WG_STEPPER_RK4; }
static void m_n(wg_snapshot *w) { w->steps_per_period = 256; }
static void m_omega(wg_snapshot *w) { w->p.v[WG_P_OMEGA] = 12; }
static void m_cosines(wg_snapshot *w) { w->p.v[WG_P_A1] = 0.5; }
static void m_stiff(wg_snapshot *w) { w->p.v[WG_P_K1X] = 1e4; }
static void m_param_nan(wg_snapshot *w) { w->p.v[WG_P_XI_P] = NAN; }
static void m_y_nan(wg_snapshot *w) { w->y[3] = NAN; }
static void m_y_huge(wg_snapshot *w) { w->y[0] = 1e10; }
static void m_k_n(wg_snapshot *w) { w->k = N; }
static void m_k_max(wg_snapshot *w) { w->k = UINT32_MAX; }
static void m_tau_huge(wg_snapshot *w) { w->tau = 1e308; }
static void m_tau_neg(wg_snapshot *w) { w->tau = -1; }
static void m_tau_nan(wg_snapshot *w) { w->tau = NAN; }
static void m_tau_c(wg_snapshot *w) { w->tau_c = 1.0; }
static void m_tau_c_nan(wg_snapshot *w) { w->tau_c = NAN; }
static void m_period(wg_snapshot *w) { w->period = w->steps + 1; }
static void m_active(wg_snapshot *w) { w->ramp.active = 7; }
static void m_ramp_id(wg_snapshot *w) { w->ramp.id = 99; }
static void m_ramp_geom(wg_snapshot *w)
{
    w->ramp = (wg_ramp){1, WG_P_A1, w->p.v[WG_P_A1], 0.3, w->tau, 100.0};
}
static void m_ramp_to(wg_snapshot *w) { w->ramp.v1 = 1000; }
static void m_ramp_from(wg_snapshot *w) { w->ramp.v0 = NAN; }
static void m_ramp_dur0(wg_snapshot *w) { w->ramp.dur = 0; }
static void m_ramp_dur_huge(wg_snapshot *w) { w->ramp.dur = 1e16; }
static void m_ramp_tau0(wg_snapshot *w) { w->ramp.tau0 = w->tau + 1; }
static void m_ramp_tau0_nan(wg_snapshot *w) { w->ramp.tau0 = NAN; }
static void m_ramp_over(wg_snapshot *w) { w->ramp.tau0 = w->tau - w->ramp.dur - 1; }
static void m_ramp_value(wg_snapshot *w) { w->p.v[WG_P_OMEGA] = 1.5; }
static void m_ramp_unstable(wg_snapshot *w)
{
    w->ramp = (wg_ramp){1, WG_P_K1X, w->p.v[WG_P_K1X], 1e4, w->tau, 100.0};
}
static void m_motion(wg_snapshot *w) { w->cur.motion = 3; }
static void m_motion_last(wg_snapshot *w) { w->last.motion = -1; }
static void m_impacts(wg_snapshot *w) { w->cur.impacts = -1; }
static void m_impacts_max(wg_snapshot *w) { w->cur.impacts = INT32_MAX; }
static void m_bimpacts_max(wg_snapshot *w) { w->last.bimpacts[2] = INT32_MAX; }
static void m_minmax(wg_snapshot *w) { w->last.min_xn = w->last.max_xn + 1; }
static void m_min_nan(wg_snapshot *w) { w->cur.min_xn = NAN; }
static void m_cur_period(wg_snapshot *w) { w->cur.period = w->period + 1; }
static void m_steps_max(wg_snapshot *w) { w->steps = w->period = w->cur.period = UINT64_MAX; }

static const hostile cases[] = {
    {"another model", m_model, WG_ESTATE, "model printed"},
    {"another stepper", m_stepper, WG_ESTATE, "stepper rk4"},
    {"another N", m_n, WG_ESTATE, "N = 256"},
    {"omega = 12", m_omega, WG_ERANGE, "omega = 12 out of range [0.01, 10]"},
    {"a1 breaks the cosines", m_cosines, WG_ERANGE, "a1^2 + a2^2 + a3^2"},
    {"k1x = 1e4 at N = 128", m_stiff, WG_ESTABILITY, "need N >="},
    {"xi_p = nan", m_param_nan, WG_ERANGE, "xi_p = nan out of range"},
    {"y[3] = nan", m_y_nan, WG_EINVAL, "not finite"},
    {"y[0] = 1e10", m_y_huge, WG_EINVAL, "not finite"},
    {"k = N", m_k_n, WG_EINVAL, "k = 128 out of range [0, 128)"},
    {"k = 2^32 - 1", m_k_max, WG_EINVAL, "k = 4294967295 out of range"},
    {"tau = 1e308", m_tau_huge, WG_EINVAL, "tau = 1e+308 out of range [0, 1e+15]"},
    {"tau = -1", m_tau_neg, WG_EINVAL, "tau = -1 out of range"},
    {"tau = nan", m_tau_nan, WG_EINVAL, "tau = nan out of range"},
    {"tau_c = 1", m_tau_c, WG_EINVAL, "tau_c = 1"},
    {"tau_c = nan", m_tau_c_nan, WG_EINVAL, "tau_c = nan"},
    {"period > steps", m_period, WG_EINVAL, "period"},
    {"ramp active = 7", m_active, WG_EINVAL, "ramp active = 7, must be 0 or 1"},
    {"ramp of parameter 99", m_ramp_id, WG_EUNKNOWN, "parameter id 99 does not exist"},
    {"ramp of a1", m_ramp_geom, WG_EINVAL, "a1 cannot be ramped"},
    {"ramp of omega to 1000", m_ramp_to, WG_ERANGE, "ramp target: omega = 1000 out of range"},
    {"ramp from nan", m_ramp_from, WG_ERANGE, "ramp from: omega = nan out of range"},
    {"ramp duration 0", m_ramp_dur0, WG_ERANGE, "ramp duration 0 tau out of range"},
    {"ramp duration 1e16", m_ramp_dur_huge, WG_ERANGE, "ramp duration 1e+16 tau"},
    {"ramp started after tau", m_ramp_tau0, WG_EINVAL, "ramp tau0"},
    {"ramp tau0 = nan", m_ramp_tau0_nan, WG_EINVAL, "ramp tau0"},
    {"ramp already over", m_ramp_over, WG_EINVAL, "ramp tau0"},
    {"ramped value off the ramp", m_ramp_value, WG_EINVAL, "omega = 1.5 is not on the ramp"},
    {"ramp of k1x to 1e4", m_ramp_unstable, WG_ESTABILITY, "need N >="},
    {"cur.motion = 3", m_motion, WG_EINVAL, "cur.motion = 3"},
    {"last.motion = -1", m_motion_last, WG_EINVAL, "last.motion = -1"},
    {"cur.impacts = -1", m_impacts, WG_EINVAL, "cur.impacts = -1"},
    /* the next impact would overflow the count (UBSan: wg_sim_run.c) */
    {"cur.impacts = 2^31 - 1", m_impacts_max, WG_EINVAL,
     "cur.impacts = 2147483647, must be in [0, 1000000000]"},
    {"last.z1 impacts = 2^31 - 1", m_bimpacts_max, WG_EINVAL, "last.z1 bearing statistics"},
    {"last.min_xn > last.max_xn", m_minmax, WG_EINVAL, "last.min_xn"},
    {"cur.min_xn = nan", m_min_nan, WG_EINVAL, "cur.min_xn"},
    /* the counters wrapped to 0 at the next step */
    {"steps = period = 2^64 - 1", m_steps_max, WG_EINVAL,
     "steps = 18446744073709551615 out of range [0, 1000000000000000000]"},
    {"cur.period != period", m_cur_period, WG_EINVAL, "cur.period"},
};

/* The run's whole visible state, for "unchanged" checks. */
static int same_run(const wg_sim *a, const wg_snapshot *before, double hmax, double h)
{
    wg_snapshot now;
    wg_sim_snapshot(a, &now);
    return memcmp(&now, before, sizeof now) == 0 && a->hmax == hmax && a->h == h;
}

static size_t ends_with_quotes(const char *s)
{
    size_t n = strlen(s);
    return n >= 2 && s[n - 1] == '\'' && s[n - 2] == '\'';
}

static void test_restore_refuses_hostile_values(void)
{
    wg_sim src = mid_ramp(), dst = mid_ramp();
    ASSERT_EQ_INT(wg_sim_run(&dst, 333, NULL, NULL), WG_OK); /* a different moment */
    wg_snapshot good, before;
    wg_sim_snapshot(&src, &good);
    wg_sim_snapshot(&dst, &before);
    double hmax = dst.hmax, h = dst.h;
    char why[400];
    int refused = 0, n = (int)(sizeof cases / sizeof cases[0]);
    for (int i = 0; i < n; i++) {
        wg_snapshot w = good;
        cases[i].mutate(&w);
        why[0] = 0;
        int rc = wg_sim_restore(&dst, &w, why, sizeof why);
        if (rc != cases[i].rc || !strstr(why, cases[i].says) || ends_with_quotes(why))
            TEST_FAIL_("%s: rc %d (want %d), why '%s' (want '%s')", cases[i].what, rc,
                       cases[i].rc, why, cases[i].says);
        if (!same_run(&dst, &before, hmax, h))
            TEST_FAIL_("%s: the sim changed", cases[i].what);
        refused += rc != WG_OK;
    }
    printf("  %d of %d hostile snapshots refused, the sim unchanged\n", refused, n);
    ASSERT_EQ_INT(wg_sim_restore(&dst, &good, why, sizeof why), WG_OK);
    wg_sim_fini(&src);
    wg_sim_fini(&dst);
}

/* A ramp of another parameter than omega restores too, mid-ramp and at its
 * first step, and continues bit-exactly. */
static void test_restore_accepts_live_ramps(void)
{
    wg_sim a = mid_ramp(), b = mid_ramp();
    char why[300];
    ASSERT_EQ_INT(wg_sim_ramp(&a, WG_P_XI_P, NULL, 0.12, 50.0, why, sizeof why), WG_OK);
    for (int k = 0; k < 3; k++) {
        wg_snapshot w;
        wg_sim_snapshot(&a, &w);
        int rc = wg_sim_restore(&b, &w, why, sizeof why);
        if (rc)
            TEST_FAIL_("restore after %d runs: %s", k, why);
        ASSERT_EQ_INT(wg_sim_run(&a, 77, NULL, NULL), WG_OK);
        ASSERT_EQ_INT(wg_sim_run(&b, 77, NULL, NULL), WG_OK);
        ASSERT_TRUE(memcmp(a.y, b.y, sizeof a.y) == 0 && a.tau == b.tau);
        ASSERT_TRUE(a.p.v[WG_P_XI_P] == b.p.v[WG_P_XI_P] && a.ramp.active == b.ramp.active);
    }
    wg_sim_fini(&a);
    wg_sim_fini(&b);
}

/* ---- the file format ------------------------------------------------------------ */

/* Field by field, reals bit by bit (the struct has padding). */
static int same_snapshot(const wg_snapshot *a, const wg_snapshot *b)
{
    return a->model == b->model && a->stepper == b->stepper &&
           a->steps_per_period == b->steps_per_period && !memcmp(&a->p, &b->p, sizeof a->p) &&
           !memcmp(a->y, b->y, sizeof a->y) && a->k == b->k &&
           !memcmp(&a->tau, &b->tau, sizeof a->tau) &&
           !memcmp(&a->tau_c, &b->tau_c, sizeof a->tau_c) && a->period == b->period &&
           a->steps == b->steps && !memcmp(&a->ramp, &b->ramp, sizeof a->ramp) &&
           !memcmp(&a->cur, &b->cur, sizeof a->cur) && !memcmp(&a->last, &b->last, sizeof a->last);
}

static int format(const wg_sim *s, char *buf)
{
    wg_snapshot w;
    char why[300];
    wg_sim_snapshot(s, &w);
    int n = wg_snapshot_format(&w, "table3", buf, WG_SNAPSHOT_MAX, why, sizeof why);
    if (n < 0)
        TEST_FAIL_("format: %s", why);
    return n;
}

static void round_trip(wg_sim *a, wg_sim *b, const char *what)
{
    char text[WG_SNAPSHOT_MAX], again[WG_SNAPSHOT_MAX], scene[WG_SNAPSHOT_SCENE_MAX], why[300];
    wg_snapshot w, back;
    wg_sim_snapshot(a, &w);
    if (!w.ramp.active) /* "ramp = none": an ended ramp's old fields are not state */
        memset(&w.ramp, 0, sizeof w.ramp);
    int n = format(a, text);
    ASSERT_EQ_INT(wg_snapshot_parse(text, (size_t)n, &back, scene, sizeof scene, why,
                                    sizeof why), WG_OK);
    ASSERT_STR(scene, "table3");
    if (!same_snapshot(&w, &back))
        TEST_FAIL_("%s: the snapshot read back differs", what);
    ASSERT_EQ_INT(wg_snapshot_format(&back, scene, again, sizeof again, why, sizeof why), n);
    ASSERT_TRUE(memcmp(text, again, (size_t)n) == 0);
    ASSERT_EQ_INT(wg_sim_restore(b, &back, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(a, N * 40 + 5, NULL, NULL), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(b, N * 40 + 5, NULL, NULL), WG_OK);
    if (memcmp(a->y, b->y, sizeof a->y) || a->tau != b->tau || a->tau_c != b->tau_c ||
        a->steps != b->steps || a->period != b->period || a->p.v[WG_P_OMEGA] != b->p.v[WG_P_OMEGA])
        TEST_FAIL_("%s: the restored run is not bit-exact", what);
    printf("  %s: %d bytes, read back and continued bit-exactly\n", what, n);
}

static void test_format_round_trip(void)
{
    wg_sim a = mid_ramp(), b = mid_ramp();
    ASSERT_EQ_INT(wg_sim_run(&b, 999, NULL, NULL), WG_OK);
    round_trip(&a, &b, "mid-ramp");
    ASSERT_EQ_INT(wg_sim_run(&a, 70000, NULL, NULL), WG_OK); /* past the ramp's end */
    ASSERT_EQ_INT(wg_sim_run(&b, 70000, NULL, NULL), WG_OK);
    ASSERT_TRUE(!a.ramp.active && !b.ramp.active && !memcmp(a.y, b.y, sizeof a.y));
    round_trip(&a, &b, "no ramp");
    wg_sim_fini(&a);
    wg_sim_fini(&b);
    wg_params p;
    wg_params_default(&p);
    wg_sim_config cfg = {WG_MODEL_PRINTED, WG_STEPPER_RK4, N};
    char why[300];
    ASSERT_EQ_INT(wg_sim_init(&a, &p, &cfg, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_sim_init(&b, &p, &cfg, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(&a, N * 3 + 1, NULL, NULL), WG_OK);
    round_trip(&a, &b, "printed model (16 states)");
    wg_sim_fini(&a);
    wg_sim_fini(&b);
}

/* What would not read back is not written. */
static void test_format_refuses(void)
{
    wg_sim a = mid_ramp();
    wg_snapshot w;
    char buf[WG_SNAPSHOT_MAX], why[300];
    wg_sim_snapshot(&a, &w);
    w.y[3] = NAN;
    ASSERT_EQ_INT(wg_snapshot_format(&w, "table3", buf, sizeof buf, why, sizeof why), WG_EINVAL);
    ASSERT_CONTAINS(why, "cannot save this state: line 44: y 3 must be a finite hex float");
    wg_sim_snapshot(&a, &w);
    w.stepper = WG_STEPPER_DEFAULT;
    ASSERT_EQ_INT(wg_snapshot_format(&w, "table3", buf, sizeof buf, why, sizeof why), WG_EINVAL);
    ASSERT_CONTAINS(why, "stepper must be rk4 or rk4-event");
    wg_sim_snapshot(&a, &w);
    ASSERT_EQ_INT(wg_snapshot_format(&w, "table3", buf, 1000, why, sizeof why), WG_ERANGE);
    ASSERT_TRUE(wg_snapshot_format(&w, "t\x01\xc3\xa9", buf, sizeof buf, why, sizeof why) > 0);
    ASSERT_CONTAINS(buf, "\nscene = t???\n");
    wg_sim_fini(&a);
}

/* 1 if text is refused, by the parser or by the restore; either way dst
 * and the parser's outputs unchanged. */
static int refused(wg_sim *dst, const wg_snapshot *before, const char *text, size_t n,
                   char *why, size_t whylen)
{
    static wg_snapshot out, sentinel;
    static char scene[WG_SNAPSHOT_SCENE_MAX];
    memset(&out, 0x5a, sizeof out);
    memset(&sentinel, 0x5a, sizeof sentinel);
    memset(scene, 0x5a, sizeof scene);
    why[0] = 0;
    int rc = wg_snapshot_parse(text, n, &out, scene, sizeof scene, why, whylen);
    if (rc && (memcmp(&out, &sentinel, sizeof out) != 0 || scene[0] != 0x5a))
        TEST_FAIL_("parse refused (%s) but wrote its outputs", why);
    if (!rc)
        rc = wg_sim_restore(dst, &out, why, whylen);
    if (rc && !same_run(dst, before, dst->hmax, dst->h))
        TEST_FAIL_("refused (%s) but the sim changed", why);
    return rc != WG_OK;
}

static void test_every_truncation_and_flip_refused(void)
{
    wg_sim src = mid_ramp(), dst = mid_ramp();
    ASSERT_EQ_INT(wg_sim_run(&dst, 333, NULL, NULL), WG_OK);
    static char text[WG_SNAPSHOT_MAX], bad[WG_SNAPSHOT_MAX];
    char why[400];
    size_t n = (size_t)format(&src, text), ntr = 0, nfl = 0, nonempty = 0;
    wg_snapshot before;
    wg_sim_snapshot(&dst, &before);
    clock_t t0 = clock();
    for (size_t len = 0; len < n; len++) {
        memcpy(bad, text, len);
        ntr += refused(&dst, &before, bad, len, why, sizeof why);
    }
    memcpy(bad, text, n);
    for (size_t i = 0; i < n; i++) {
        for (int x = 1; x < 256; x++) {
            bad[i] = (char)(text[i] ^ x);
            nfl += refused(&dst, &before, bad, n, why, sizeof why);
            nonempty += why[0] != 0 && !ends_with_quotes(why);
        }
        bad[i] = text[i];
    }
    printf("  %zu of %zu truncations and %zu of %zu single-byte changes (every position, "
           "every other value) refused, the sim unchanged, %.1f s\n", ntr, n, nfl, n * 255,
           (double)(clock() - t0) / CLOCKS_PER_SEC);
    ASSERT_EQ_INT(ntr, n);
    ASSERT_EQ_INT(nfl, n * 255);
    ASSERT_EQ_INT(nonempty, n * 255);
    wg_sim_fini(&src);
    wg_sim_fini(&dst);
}

/* ---- hostile text, re-signed so that the checksum passes --------------------- */

/* Replace the line that starts with `line_start` by `with` ("" deletes it;
 * it may hold several lines) and sign the result again. Returns its length. */
static size_t edit(const char *text, const char *line_start, const char *with, char *out)
{
    const char *at = strstr(text, line_start), *sum = strstr(text, "blake2b-256 = ");
    ASSERT_TRUE(at != NULL && sum != NULL);
    if (!at || !sum)
        return 0;
    const char *nl = strchr(at, '\n') + 1;
    size_t n = (size_t)(at - text);
    memcpy(out, text, n);
    n += (size_t)sprintf(out + n, "%s", with);
    memcpy(out + n, nl, (size_t)(sum - nl));
    n += (size_t)(sum - nl);
    unsigned char h[32];
    char hex[65];
    ASSERT_TRUE(sodium_init() >= 0);
    crypto_generichash(h, sizeof h, (const unsigned char *)out, n, NULL, 0);
    sodium_bin2hex(hex, sizeof hex, h, sizeof h);
    n += (size_t)sprintf(out + n, "blake2b-256 = %s\n", hex);
    return n;
}

typedef struct textcase {
    const char *line, *with; /* the line (its start) and what replaces it */
    const char *says;        /* a part of the refusal */
} textcase;

static const textcase texts[] = {
    {"k = ", "k = 4294967296\n", "line 55: k must be an integer in [0, 4294967295]"},
    {"k = ", "k = 00\n", "k must be an integer"},
    {"k = ", "k = +1\n", "k must be an integer"},
    {"k = ", "k = -1\n", "k must be an integer"},
    {"k = ", "k =  1\n", "k must be an integer"},
    {"steps = ", "steps = 18446744073709551616\n", "steps must be an integer"},
    {"tau_c = ", "", "line 57: expected 'tau_c = <a finite hex float as %a writes it>'"},
    {"tau = ", "tau = 0x1p+0\ntau = 0x1p+0\n", "line 57: expected 'tau_c = "},
    {"tau = ", "tau = 12.5\n", "tau must be a finite hex float"},
    {"tau = ", "tau = 0X1P+0\n", "tau must be a finite hex float"},
    {"tau = ", "tau = 0x1p+0 \n", "tau must be a finite hex float"},
    {"tau = ", "tau = 0x1p+0\r\n", "tau must be a finite hex float"},
    {"tau = ", "tau = nan\n", "tau must be a finite hex float"},
    {"tau = ", "tau = inf\n", "tau must be a finite hex float"},
    {"tau = ", "tau = 0x1.1ccf385ebc8ap+1023\n", "tau = 1e+308 out of range [0, 1e+15]"},
    {"tau = ", "tau = 0x1p+0\0\n", "tau must be"},
    {"k = ", "k = 1\nbogus = 1\n", "line 56: expected 'tau = "},
    {"param xi_p = ", "", "line 7: expected 'param xi_p = "},
    {"param omega = ", "param omega = 0x1.8p+3\n", "omega = 12 out of range [0.01, 10]"},
    {"ramp = ", "ramp = a1\n", "a1 cannot be ramped"},
    {"param z2 = ", "param z2 = 0x1.f48p+10\n", "z2 = 2002 out of range [4, 1000]"},
    {"param z1 = ", "param z1 = 0x1.4p+1\n", "z1 = 2.5 must be a whole number in [1, 12]"},
    {"param j1 = ", "param j1 = 0x0p+0\n", "j1 = 0 out of range [1e-06, 1000000]"},
    {"param j2 = ", "", "line 40: expected 'param j2 = "},
    {"ramp = ", "ramp = bogus\n", "ramp must be none or a parameter name"},
    {"cur.x2.vmax = ", "cur.x2.vmax = -0x1p+0\n", "cur.x2 bearing statistics"},
    {"last.z1.impacts = ", "last.z1.impacts = -1\n", "last.z1.impacts must be an integer"},
    {"cur.y2.impacts = ", "", "expected 'cur.y2.impacts = "},
    {"ramp.to = ", "ramp.to = 0x1.f4p+9\n", "ramp target: omega = 1000 out of range"},
    {"model = ", "model = printed\n", "expected 'y 14 = "},
    {"stepper = ", "stepper = default\n", "stepper must be rk4 or rk4-event"},
    {"steps_per_period = ", "steps_per_period = 256\n", "N = 256"},
    {"cur.motion = ", "cur.motion = triple\n", "cur.motion must be no_impact"},
    {"scene = ", "scene = a\tb\n", "scene must be 1-63 printable ASCII characters"},
    {"scene = ", "scene = \n", "scene must be 1-63"},
    {"last.impacts = ", "last.impacts = 0\nextra = 1\n", "expected the checksum line"},
    {"# wormgeard", "# wormgeard snapshot, format 1\n", "a format 1 snapshot"},
    {"# wormgeard", "# wormgeard snapshot, format 4\n", "unknown format"},
    {"# wormgeard", "root:x:0:0:root:/root:/bin/bash\n", "not a wormgeard snapshot"},
};

static void test_hostile_text_refused(void)
{
    wg_sim src = mid_ramp(), dst = mid_ramp();
    static char text[WG_SNAPSHOT_MAX], bad[2 * WG_SNAPSHOT_MAX];
    char why[400];
    format(&src, text);
    wg_snapshot before;
    wg_sim_snapshot(&dst, &before);
    int n = (int)(sizeof texts / sizeof texts[0]), nref = 0;
    for (int i = 0; i < n; i++) {
        size_t len = edit(text, texts[i].line, texts[i].with, bad);
        int r = refused(&dst, &before, bad, len, why, sizeof why);
        if (!r || !strstr(why, texts[i].says) || ends_with_quotes(why) ||
            strstr(why, "bogus") || strstr(why, "root:") || strstr(why, "4294967296"))
            TEST_FAIL_("'%s' -> '%.20s...': %s '%s' (want '%s')", texts[i].line, texts[i].with,
                       r ? "refused" : "ACCEPTED", why, texts[i].says);
        nref += r;
    }
    printf("  %d of %d hostile texts refused, the line and field named, nothing quoted\n",
           nref, n);
    ASSERT_EQ_INT(wg_snapshot_parse("", 0, &before, bad, 64, why, sizeof why), WG_EINVAL);
    ASSERT_CONTAINS(why, "empty");
    wg_sim_fini(&src);
    wg_sim_fini(&dst);
}

/* A format 2 file (before the body rows joined the table) still reads: its
 * body rows are the table's defaults, and it restores bit-exactly. */
static void test_format2_reads(void)
{
    wg_sim a = mid_ramp(), b = mid_ramp();
    static char text[WG_SNAPSHOT_MAX], two[WG_SNAPSHOT_MAX], tmp[WG_SNAPSHOT_MAX];
    char scene[WG_SNAPSHOT_SCENE_MAX], why[300];
    ASSERT_EQ_INT(wg_sim_run(&b, 777, NULL, NULL), WG_OK);
    format(&a, text);
    static const char *const body[] = {"param z1 = ", "param z2 = ", "param rho1 = ",
                                       "param rho2 = ", "param j1 = ", "param j2 = "};
    strcpy(two, text);
    for (int i = 0; i < 6; i++) {
        edit(two, body[i], "", tmp);
        strcpy(two, tmp);
    }
    /* and no per-bearing period statistics */
    static const char *const axis[] = {"x1", "y1", "z1", "x2", "y2", "z2"};
    for (int c = 0; c < 2; c++)
        for (int j = 0; j < 6; j++)
            for (int k = 0; k < 2; k++) {
                char key[32];
                snprintf(key, sizeof key, "%s.%s.%s = ", c ? "last" : "cur", axis[j],
                         k ? "vmax" : "impacts");
                edit(two, key, "", tmp);
                strcpy(two, tmp);
            }
    size_t len = edit(two, "# wormgeard", "# wormgeard snapshot, format 2\n", tmp);
    wg_snapshot w;
    ASSERT_EQ_INT(wg_snapshot_parse(tmp, len, &w, scene, sizeof scene, why, sizeof why), WG_OK);
    wg_params def;
    wg_params_default(&def);
    for (int i = WG_NPARAM_DYN; i < WG_NPARAM; i++)
        ASSERT_TRUE(w.p.v[i] == def.v[i]);
    ASSERT_TRUE(w.p.v[WG_P_OMEGA] == a.p.v[WG_P_OMEGA]);
    ASSERT_EQ_INT(wg_sim_restore(&b, &w, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(&a, N * 10, NULL, NULL), WG_OK);
    ASSERT_EQ_INT(wg_sim_run(&b, N * 10, NULL, NULL), WG_OK);
    ASSERT_TRUE(memcmp(a.y, b.y, sizeof a.y) == 0 && a.tau == b.tau);
    /* a format 3 header on the format 2 body is refused at the first body row */
    len = edit(two, "# wormgeard", "# wormgeard snapshot, format 3\n", tmp);
    ASSERT_EQ_INT(wg_snapshot_parse(tmp, len, &w, scene, sizeof scene, why, sizeof why),
                  WG_EINVAL);
    ASSERT_CONTAINS(why, "expected 'param z1 = ");
    printf("  format 2 (%zu bytes, no body rows) read with the table's body data, restored "
           "bit-exactly\n", strlen(two));
    wg_sim_fini(&a);
    wg_sim_fini(&b);
}

TEST_MAIN(TEST(test_restore_refuses_hostile_values), TEST(test_restore_accepts_live_ramps),
          TEST(test_format_round_trip), TEST(test_format_refuses), TEST(test_format2_reads), TEST(test_every_truncation_and_flip_refused),
          TEST(test_hostile_text_refused))

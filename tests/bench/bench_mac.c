/* bench_mac - what signing costs the daemon (and a client with a key, which
 * checks the same bytes): wg_mac_seal on encoded messages of each type at
 * the sizes the daemon publishes, and the share of one core that signing
 * takes at physical real time (wgd_bench's scene: table3, omega 2.5, a
 * 5 kHz mesh, STATE 2000 samples/s; every stream batched every 20 ms).
 * Not a test: it prints figures.  usage: bench_mac [REPEATS] */
#include "bench_args.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_scope_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "wormgear/wg_key.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static unsigned char buf[65536], mac[WG_MAC_BYTES];
static double d[400];
static double *rows[200];
static int32_t bi[6], *bir[200];
static double bv[6], *bvr[200];
static int64_t per[200];
static int8_t mot[200];
static int32_t imp[200];

static double now_s(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return (double)t.tv_sec + 1e-9 * (double)t.tv_nsec;
}

static int state(int n)
{
    wormgear_state_t m = {.n = n, .tau = d, .t_s = d, .omega = d, .xn = d, .dxn = d,
                          .force = d, .fb_x1 = d, .fb_y1 = d, .fb_z1 = d, .fb_x2 = d,
                          .fb_y2 = d, .fb_z2 = d, .theta1 = d, .theta2 = d,
                          .mac_len = WG_MAC_BYTES, .mac = mac};
    return wormgear_state_t_encode(buf, 0, sizeof buf, &m);
}

static int poincare(int n)
{
    for (int i = 0; i < 200; i++)
        rows[i] = d, bir[i] = bi, bvr[i] = bv;
    wormgear_poincare_t m = {.nstate = 14, .n = n, .period = per, .tau = d, .t_s = d,
                             .omega = d, .xn = d, .dxn = d, .force = d, .min_xn = d,
                             .max_xn = d, .motion = mot, .impacts = imp, .y = rows,
                             .nbearing = 6, .bearing_impacts = bir, .bearing_vmax = bvr,
                             .mac_len = WG_MAC_BYTES, .mac = mac};
    return wormgear_poincare_t_encode(buf, 0, sizeof buf, &m);
}

static int scope(int n)
{
    (void)n;
    wormgear_scope_t m = {.mac_len = WG_MAC_BYTES, .mac = mac};
    return wormgear_scope_t_encode(buf, 0, sizeof buf, &m);
}

/* Microseconds per wg_mac_seal of the message enc(n) encodes (the best of
 * reps rounds of 2000). */
static double cost_us(int (*enc)(int), int n, int reps, int *bytes)
{
    unsigned char key[WG_KEY_BYTES] = {1, 2, 3};
    *bytes = enc(n);
    double best = 1e30;
    for (int r = 0; r < reps; r++) {
        double t0 = now_s();
        for (int i = 0; i < 2000; i++) {
            buf[8] = (unsigned char)i; /* the bytes differ each time */
            wg_mac_seal(key, buf, (size_t)*bytes);
        }
        double us = (now_s() - t0) / 2000 * 1e6;
        best = us < best ? us : best;
    }
    return best;
}

int main(int argc, char **argv)
{
    double nrep = 5;
    bench_arg args[] = {{"REPEATS", "rounds of 2000 signatures, the best one kept, 1 to 1000 "
                         "(default 5)", 1, 1000, &nrep, NULL, 0}};
    int rc = bench_args("bench_mac", "What signing a message costs (wg_mac_seal, "
                        "HMAC-SHA-512-256) at the sizes the daemon publishes.", "", argc, argv,
                        args, 1, NULL);
    if (rc >= 0)
        return rc;
    int reps = (int)nrep;
    struct { const char *what; int (*enc)(int); int n; double per_s; } m[] = {
        {"STATE, 40 samples (physical real time)", state, 40, 50},
        {"STATE, 400 samples (the largest)", state, 400, 0},
        {"POINCARE, 100 sections (physical real time)", poincare, 100, 50},
        {"POINCARE, 200 sections (the largest)", poincare, 200, 0},
        {"SCOPE", scope, 0, 50}};
    double share = 0;
    printf("wg_mac_seal (HMAC-SHA-512-256, libsodium), best of %d rounds of 2000\n", reps);
    for (unsigned i = 0; i < sizeof m / sizeof m[0]; i++) {
        int bytes;
        double us = cost_us(m[i].enc, m[i].n, reps, &bytes);
        share += us * 1e-6 * m[i].per_s;
        printf("  %-46s %6d bytes  %8.2f us", m[i].what, bytes, us);
        if (m[i].per_s > 0)
            printf("  x %g/s", m[i].per_s);
        printf("\n");
    }
    printf("signing at physical real time (the rows with a rate): %.3f%% of one core\n",
           share * 100);
    return 0;
}

/* wgenc - test helper: encode one message of every wormgear type with the C
 * bindings into DIR/<type>.bin, and each C fingerprint into DIR/<type>.hash
 * (16 hex digits). The values are the ones java/DecodeTest.java expects.
 * usage: wgenc DIR */
#include "lcmtypes/wormgear_ack_t.h"
#include "lcmtypes/wormgear_cmd_t.h"
#include "lcmtypes/wormgear_contact_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "lcmtypes/wormgear_tick_t.h"
#include "lcmtypes/wormgear_scope_t.h"

#include <stdio.h>
#include <stdlib.h>

static const char *g_dir; /* set once in main, read-only after */

static int save(const char *type, const void *buf, int n, int64_t hash)
{
    char path[512];
    snprintf(path, sizeof path, "%s/%s.bin", g_dir, type);
    FILE *f = fopen(path, "wb");
    int bad = !f || fwrite(buf, 1, (size_t)n, f) != (size_t)n;
    if (f)
        bad |= fclose(f) != 0;
    snprintf(path, sizeof path, "%s/%s.hash", g_dir, type);
    f = fopen(path, "w");
    bad |= !f || fprintf(f, "%016llx\n", (unsigned long long)hash) < 0;
    if (f)
        bad |= fclose(f) != 0;
    if (bad)
        fprintf(stderr, "wgenc: cannot write %s\n", path);
    return bad;
}

#define ENC(T, name, msg)                                                                  \
    do {                                                                                   \
        int n_ = T##_encoded_size(msg);                                                    \
        char *b_ = malloc((size_t)n_);                                                     \
        rc |= !b_ || T##_encode(b_, 0, n_, msg) != n_ ||                                   \
              save(name, b_, n_, __##T##_get_hash());                                      \
        free(b_);                                                                          \
    } while (0)

int main(int argc, char **argv)
{
    if (argc != 2)
        return fprintf(stderr, "usage: wgenc DIR\n"), 2;
    g_dir = argv[1];
    int rc = 0;
    double a[3] = {1.0 / 7, 1.0 / 7 + 1, 1.0 / 7 + 2}, yv[2][14];
    double *y[2] = {yv[0], yv[1]};
    for (int i = 0; i < 2; i++)
        for (int k = 0; k < 14; k++)
            yv[i][k] = i + k / 3.0;
    wormgear_state_t st = {1, 42, 7, 10, 3, a, a, a, a, a, a, a, a, a, a, a, a, a, a, 0, NULL};
    ENC(wormgear_state_t, "state_t", &st);
    int64_t per[2] = {5, 6};
    int8_t mot[2] = {1, 2}, kind[2] = {1, 2};
    int32_t imp[2] = {1, 2};
    int32_t bi[2][6] = {{0}, {0, 0, 0, 3, 0, 1}}, *bir[2] = {bi[0], bi[1]};
    double bv[2][6] = {{0}, {0, 0, 0, 0.5, 0, 0.25}}, *bvr[2] = {bv[0], bv[1]};
    wormgear_poincare_t pc = {1, 43, 14, 2, per, a, a, a, a, a, a, a, a, mot, imp, y, 6, bir, bvr, 0, NULL};
    ENC(wormgear_poincare_t, "poincare_t", &pc);
    wormgear_contact_t ct = {1, 44, 10, 2, a, a, a, per, mot, kind, 0, NULL};
    ENC(wormgear_contact_t, "contact_t", &ct);
    wormgear_status_t ss = {.utime = 1, .seq = 45, .scene = "table3", .mode = "realtime",
                            .rate = 1, .run = "running", .health = "ok", .fault = "",
                            .omega = 0.7, .motion = "single_sided", .regime = "period-1",
                            .tick_refusal = ""};
    ENC(wormgear_status_t, "status_t", &ss);
    char *names[2] = {"omega", "xi_p"}, *units[2] = {"1", "1"};
    double v[2] = {1.3, 0.08};
    int8_t ramp[2] = {1, 1};
    wormgear_params_t pa = {.seq = 46, .reason = "get", .cmd_client = "c", .cmd_seq = 1,
                            .scene = "table3", .model = "consistent", .stepper = "rk4-event",
                            .steps_per_period = 128, .n = 2, .name = names, .unit = units,
                            .value = v, .min = v, .max = v, .def = v, .rampable = ramp,
                            .ramp_param = ""};
    ENC(wormgear_params_t, "params_t", &pa);
    wormgear_cmd_t cmd = {.seq = 47, .client = "c", .op = "set", .nparams = 1, .names = names,
                          .values = v, .unit = "", .name = ""};
    ENC(wormgear_cmd_t, "cmd_t", &cmd);
    wormgear_ack_t ack = {.seq = 48, .client = "c", .cmd_seq = 47, .op = "set", .code = "ERANGE",
                          .message = "omega = 99 out of range [0.01, 10]", .status = -2};
    ENC(wormgear_ack_t, "ack_t", &ack);
    wormgear_tick_t tk = {1, 49, 5, (char *)"rig-1@host", 0, NULL};
    ENC(wormgear_tick_t, "tick_t", &tk);
    wormgear_scope_t sc = {.utime = 1, .seq = 50, .t_s = 0.25, .tau = 7975.25, .omega = 1.2,
                           .xn = 1.2154, .dxn = -0.03, .force = 0.41};
    ENC(wormgear_scope_t, "scope_t", &sc);
    return rc;
}

/* test_msg.c - the check the clients (and, for CMD, the daemon) run on a
 * message's bytes before LCM's generated decoder (lcmtypes/msg_check.c,
 * through clients/bus_msg.h). For every type: a message encoded
 * by the generated encoder is walked to its exact encoded size (so the
 * layouts there cannot drift from lcmtypes/), every shorter prefix is
 * refused, and each array count and string length set to what a hostile
 * sender would (2^31 - 1, -1, one too many) is refused, as is a string
 * without its NUL; random mutants that pass decode within their bytes.
 * A count of 2^31 - 1 in a CONTACT message crashed wgweb,
 * wgmon, wgrig and wglog inside the generated decoder. A length over
 * MSG_MAX_BYTES (LCM's 4294967295 for a datagram it misread) is refused
 * before a byte is read. */
#include "test.h"

#include "bus_msg.h"
#include "lcmtypes/wormgear_ack_t.h"
#include "lcmtypes/wormgear_cmd_t.h"
#include "lcmtypes/wormgear_contact_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_scope_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "lcmtypes/wormgear_tick_t.h"
#include "wormgear/wg_model.h"

#include <stdint.h>
#include <stdlib.h>

enum { N = 3, NSTATE = 14, NB = 6, MAXB = 65536 };

static double d[N * NSTATE];
static int64_t l[N];
static int32_t i32[N * NB];
static int8_t i8[N];
static char *names[N] = {"omega", "xi_p", "k_a"};
static unsigned char mac[32];

/* One encoded message per type: its bytes and length. */
typedef struct enc {
    unsigned char buf[MAXB];
    int len;
} enc;

#define ENCODE(T, msg, e)                                                                  \
    do {                                                                                   \
        (e)->len = T##_encoded_size(msg);                                                  \
        ASSERT_TRUE((e)->len > 0 && (e)->len <= MAXB);                                     \
        ASSERT_EQ_INT(T##_encode((e)->buf, 0, (e)->len, msg), (e)->len);                   \
    } while (0)

static void encode(int type, enc *e)
{
    switch (type) {
    case BUS_ACK: {
        wormgear_ack_t m = {.client = "c-1@h", .op = "set", .code = "OK", .message = "fine",
                            .mac_len = 32, .mac = mac}; /* a signing daemon's */
        ENCODE(wormgear_ack_t, &m, e);
        break;
    }
    case BUS_STATE: {
        wormgear_state_t m = {.n = N, .tau = d, .t_s = d, .omega = d, .xn = d, .dxn = d,
                              .force = d, .fb_x1 = d, .fb_y1 = d, .fb_z1 = d, .fb_x2 = d,
                              .fb_y2 = d, .fb_z2 = d, .theta1 = d, .theta2 = d};
        ENCODE(wormgear_state_t, &m, e);
        break;
    }
    case BUS_POINCARE: {
        double *y[N] = {d, d + NSTATE, d + 2 * NSTATE};
        int32_t *bi[N] = {i32, i32 + NB, i32 + 2 * NB};
        double *bv[N] = {d, d + NB, d + 2 * NB};
        wormgear_poincare_t m = {.nstate = NSTATE, .n = N, .period = l, .tau = d, .t_s = d,
                                 .omega = d, .xn = d, .dxn = d, .force = d, .min_xn = d,
                                 .max_xn = d, .motion = i8, .impacts = i32, .y = y,
                                 .nbearing = NB, .bearing_impacts = bi, .bearing_vmax = bv};
        ENCODE(wormgear_poincare_t, &m, e);
        break;
    }
    case BUS_CONTACT: {
        wormgear_contact_t m = {.n = N, .tau = d, .t_s = d, .velocity = d, .period = l,
                                .contact = i8, .kind = i8};
        ENCODE(wormgear_contact_t, &m, e);
        break;
    }
    case BUS_STATUS: {
        wormgear_status_t m = {.scene = "table3", .mode = "realtime", .run = "running",
                               .health = "ok", .fault = "", .motion = "no_impact",
                               .nbearing = NB, .bearing_impacts_per_period = d,
                               .bearing_impact_vmax = d, .regime = "P1",
                               .tick_refusal = ""};
        ENCODE(wormgear_status_t, &m, e);
        break;
    }
    case BUS_PARAMS: {
        wormgear_params_t m = {.reason = "get", .cmd_client = "c", .scene = "table3",
                               .model = "consistent", .stepper = "rk4-event", .n = N,
                               .name = names, .unit = names, .value = d, .min = d, .max = d,
                               .def = d, .rampable = i8, .ramp_param = ""};
        ENCODE(wormgear_params_t, &m, e);
        break;
    }
    case BUS_CMD: {
        wormgear_cmd_t m = {.client = "c", .op = "set", .nparams = N, .names = names,
                            .values = d, .unit = "s", .name = "", .mac_len = 32, .mac = mac};
        ENCODE(wormgear_cmd_t, &m, e);
        break;
    }
    case BUS_TICK: {
        /* scalars 0: a 4-byte window holding 2..32 is a count */
        wormgear_tick_t m = {.client = "c", .mac_len = 32, .mac = mac};
        ENCODE(wormgear_tick_t, &m, e);
        break;
    }
    case BUS_SCOPE: {
        wormgear_scope_t m = {.xn = 0.0};
        ENCODE(wormgear_scope_t, &m, e);
        break;
    }
    }
}

static void put32(unsigned char *p, int32_t v)
{
    uint32_t u = (uint32_t)v;
    p[0] = (unsigned char)(u >> 24), p[1] = (unsigned char)(u >> 16);
    p[2] = (unsigned char)(u >> 8), p[3] = (unsigned char)u;
}

static int32_t get32(const unsigned char *p)
{
    return (int32_t)((uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3]);
}

/* The walk ends at the encoder's last byte; nothing shorter passes. */
static void test_layouts_match_the_encoder(void)
{
    static enc e;
    for (int t = 0; t < BUS_NTYPE; t++) {
        encode(t, &e);
        if (bus_msg_size(t, e.buf, e.len) != e.len)
            TEST_FAIL_("type %d: walked %ld bytes, encoded %d", t, bus_msg_size(t, e.buf, e.len),
                       e.len);
        for (int k = 0; k < e.len; k++)
            if (bus_msg_ok(t, e.buf, k)) {
                TEST_FAIL_("type %d: a prefix of %d of %d bytes passed", t, k, e.len);
                break;
            }
    }
}

/* Every 4 bytes that hold a count or a string length (the values the
 * encoder wrote there: N, NSTATE, NB, 32, a string's length) set to a
 * hostile value: refused. Found by position: where the original value is
 * one of those, changing it must not leave a message that passes and
 * still claims more than there is. */
static void test_hostile_counts_refused(void)
{
    static enc e;
    static const int32_t bad[] = {INT32_MAX, -1, INT32_MIN, 1 << 28, 1 << 20};
    int tried = 0;
    for (int t = 0; t < BUS_NTYPE; t++) {
        encode(t, &e);
        for (int p = 8; p + 4 <= e.len; p++) {
            int32_t v = get32(e.buf + p);
            if (v != N && v != NSTATE && v != NB && v != 32 && !(v >= 2 && v <= 12))
                continue; /* not a count or a short string's length */
            for (unsigned b = 0; b < sizeof bad / sizeof bad[0]; b++) {
                put32(e.buf + p, bad[b]);
                long got = bus_msg_size(t, e.buf, e.len);
                if (got >= 0 && got > e.len)
                    TEST_FAIL_("type %d: walked past the end (%ld > %d)", t, got, e.len);
                if (got == e.len && bad[b] != v)
                    TEST_FAIL_("type %d: %d at byte %d passed as a whole message", t, bad[b], p);
                tried++;
            }
            put32(e.buf + p, v);
        }
    }
    ASSERT_TRUE(tried > 100);
    /* the crash of the probe: CONTACT's n = 2^31 - 1 */
    encode(BUS_CONTACT, &e);
    put32(e.buf + 8 + 8 + 8 + 4, INT32_MAX);
    ASSERT_TRUE(!bus_msg_ok(BUS_CONTACT, e.buf, e.len));
    msg_walk w; /* the walk says which field and why */
    ASSERT_EQ_INT((int)msg_check(BUS_CONTACT, e.buf, e.len, &w), -1);
    ASSERT_STR(w.field, "tau"); /* the first array the count makes run past the end */
    ASSERT_STR(w.what, "truncated");
    ASSERT_EQ_INT((int)w.at, 8 + 8 + 8 + 4 + 4);
    ASSERT_EQ_INT((int)w.count[0], INT32_MAX);
    /* POINCARE with no rows and nstate 2^31 - 1 needs no state bytes: refused by
     * its limit (wglog export wrote a header of 2^31 columns), as is nbearing 7 */
    ASSERT_EQ_INT(MSG_NSTATE_MAX, WG_NSTATE_MAX);
    ASSERT_EQ_INT(MSG_NBEARING_MAX, WG_NBEARING);
    {
        wormgear_poincare_t m = {.nstate = INT32_MAX, .n = 0, .nbearing = 6};
        ENCODE(wormgear_poincare_t, &m, &e);
        ASSERT_EQ_INT((int)msg_check(BUS_POINCARE, e.buf, e.len, &w), -1);
        ASSERT_STR(w.field, "nstate");
        ASSERT_STR(w.what, "2147483647, allowed 0 to 16");
        m.nstate = 14, m.nbearing = 7;
        ENCODE(wormgear_poincare_t, &m, &e);
        ASSERT_EQ_INT((int)msg_check(BUS_POINCARE, e.buf, e.len, &w), -1);
        ASSERT_STR(w.field, "nbearing");
    }
    /* a command over the protocol's limits is refused wherever it is read */
    encode(BUS_CMD, &e);
    ASSERT_TRUE(bus_msg_ok(BUS_CMD, e.buf, e.len));
    put32(e.buf + 8 + 8 + 8 + 6 + 8, MSG_CMD_MAX_PARAMS + 1); /* nparams after "c", "set" */
    ASSERT_EQ_INT((int)msg_check(BUS_CMD, e.buf, e.len, &w), -1);
    ASSERT_STR(w.field, "nparams");
    ASSERT_STR(w.what, "65, allowed 0 to 64");
}

/* A string's last byte must be its NUL (the decoder copies the bytes and
 * the clients read them as C strings). */
static void test_string_without_nul_refused(void)
{
    static enc e;
    encode(BUS_ACK, &e);
    ASSERT_TRUE(bus_msg_ok(BUS_ACK, e.buf, e.len));
    e.buf[8 + 8 + 8 + 4 + 5] = 'x'; /* client "c-1@h": its NUL */
    ASSERT_TRUE(!bus_msg_ok(BUS_ACK, e.buf, e.len));
    e.buf[8 + 8 + 8 + 4 + 5] = 0;
    e.buf[8 + 8 + 8 + 4 + 2] = 0; /* "c-\0@h": not one C string */
    msg_walk w;
    ASSERT_TRUE(msg_check(BUS_ACK, e.buf, e.len, &w) < 0);
    ASSERT_STR(w.field, "client");
    ASSERT_STR(w.what, "a NUL byte inside the string");
    ASSERT_TRUE(!bus_msg_ok(BUS_ACK, NULL, 100));
    ASSERT_TRUE(!bus_msg_ok(-1, e.buf, e.len));
    ASSERT_TRUE(!bus_msg_ok(BUS_NTYPE, e.buf, e.len));
}

/* A message of 4294967295 bytes, which is what LCM 1.3.1 reports for a
 * short datagram whose channel name has no NUL: refused before a byte is
 * read. Walked, a string length left in its buffer from an earlier message
 * (here 2^30) carried the walk, and its NUL test, a gigabyte past the bytes
 * there are. Every type; the bytes are a heap copy of exactly the message,
 * so under AddressSanitizer any read past them fails the run. */
static void test_misread_length_refused(void)
{
    static enc e;
    for (int type = 0; type < BUS_NTYPE; type++) {
        encode(type, &e);
        unsigned char *b = malloc(e.len);
        ASSERT_TRUE(b != NULL);
        memcpy(b, e.buf, e.len);
        if (type == BUS_ACK)
            put32(b + 8 + 8 + 8, 1 << 30); /* the client string's length */
        msg_walk w;
        ASSERT_EQ_INT((int)msg_check(type, b, 4294967295L, &w), -1);
        ASSERT_STR(w.what, "a message of 4294967295 bytes, the limit is 16777216");
        ASSERT_TRUE(!bus_msg_ok(type, b, 4294967295L));
        ASSERT_EQ_INT((int)msg_check(type, b, MSG_MAX_BYTES + 1L, &w), -1);
        free(b);
    }
}

/* Decode with the generated decoder as the clients do once the check
 * passed (under AddressSanitizer a read past len fails the run). */
#define TRY(T, e, n)                                                                       \
    do {                                                                                   \
        T m_;                                                                              \
        if (T##_decode((e)->buf, 0, (n), &m_) >= 0)                                        \
            T##_decode_cleanup(&m_);                                                       \
    } while (0)

static void decode_as(int type, const enc *e, int n)
{
    switch (type) {
    case BUS_ACK: TRY(wormgear_ack_t, e, n); break;
    case BUS_STATE: TRY(wormgear_state_t, e, n); break;
    case BUS_POINCARE: TRY(wormgear_poincare_t, e, n); break;
    case BUS_CONTACT: TRY(wormgear_contact_t, e, n); break;
    case BUS_STATUS: TRY(wormgear_status_t, e, n); break;
    case BUS_PARAMS: TRY(wormgear_params_t, e, n); break;
    case BUS_CMD: TRY(wormgear_cmd_t, e, n); break;
    case BUS_TICK: TRY(wormgear_tick_t, e, n); break;
    case BUS_SCOPE: TRY(wormgear_scope_t, e, n); break;
    }
}

/* What a sender on the group could send: each type's message with 1 to 4
 * bytes after the fingerprint set at random and cut at a random length,
 * 2000 times a type (a fixed seed). Whatever the check passes, the
 * generated decoder reads within the bytes (ASan run); and some mutants
 * pass, so the decoder is reached. */
static void test_random_mutants(void)
{
    static enc e, m;
    uint32_t x = 12345u;
    long passed = 0;
    for (int t = 0; t < BUS_NTYPE; t++) {
        encode(t, &e);
        for (int k = 0; k < 2000; k++) {
            m = e;
            int flips = 1 + (int)((x = x * 1664525u + 1013904223u) >> 30);
            for (int f = 0; f < flips; f++) {
                x = x * 1664525u + 1013904223u;
                int at = 8 + (int)(x % (uint32_t)(e.len - 8));
                x = x * 1664525u + 1013904223u;
                m.buf[at] = (unsigned char)(x >> 24);
            }
            x = x * 1664525u + 1013904223u;
            int n = (x >> 28) ? e.len : 8 + (int)(x % (uint32_t)(e.len - 7));
            long got = bus_msg_size(t, m.buf, n);
            ASSERT_TRUE(got <= n);
            if (got >= 0) {
                passed++;
                decode_as(t, &m, n);
            }
        }
    }
    ASSERT_TRUE(passed > 1000);
}

TEST_MAIN(TEST(test_layouts_match_the_encoder), TEST(test_hostile_counts_refused),
          TEST(test_random_mutants), TEST(test_misread_length_refused),
          TEST(test_string_without_nul_refused))

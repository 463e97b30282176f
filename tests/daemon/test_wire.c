/* test_wire.c - raw bytes on the command channel: the wire check in front
 * of the generated decoder, undecodable and truncated messages answered
 * (client and seq recovered), 1000 corrupted commands with one ACK each. */
#include "fixture.h"
#include "wire.h"

static int encode_full(unsigned char *buf, int max)
{
    char *n[3] = {"omega", "xi_p", "k_a"};
    double v[3] = {1.1, 0.09, 0.3};
    wormgear_cmd_t c = {.seq = 7, .client = "wire", .op = "set", .nparams = 3, .names = n,
                        .values = v, .has_from = 1, .from = 2, .duration = 3, .unit = "s",
                        .nsteps = 9, .name = "x", .rate = 1};
    return wormgear_cmd_t_encode(buf, 0, max, &c);
}

static void test_wire_check(void)
{
    unsigned char buf[1024];
    char why[160];
    int len = encode_full(buf, sizeof buf);
    ASSERT_EQ_INT(wire_cmd_check(buf, (size_t)len, why, sizeof why), WG_OK);
    for (int cut = 0; cut < len; cut++) /* every strict prefix is refused */
        ASSERT_EQ_INT(wire_cmd_check(buf, (size_t)cut, why, sizeof why), WG_EDECODE);
    /* nparams (after fingerprint, utime, seq, client, op) set huge / negative */
    size_t at = 24 + 4 + 5 + 4 + 4;
    unsigned char bad[1024];
    memcpy(bad, buf, (size_t)len);
    bad[at] = 0x7f, bad[at + 1] = bad[at + 2] = bad[at + 3] = 0xff;
    ASSERT_EQ_INT(wire_cmd_check(bad, (size_t)len, why, sizeof why), WG_EDECODE);
    ASSERT_CONTAINS(why, "nparams");
    bad[at] = 0xff;
    ASSERT_EQ_INT(wire_cmd_check(bad, (size_t)len, why, sizeof why), WG_EDECODE);
    memcpy(bad, buf, (size_t)len);
    bad[24] = 0x80; /* client length negative */
    ASSERT_EQ_INT(wire_cmd_check(bad, (size_t)len, why, sizeof why), WG_EDECODE);
    ASSERT_CONTAINS(why, "string length");
    memcpy(bad, buf, (size_t)len);
    bad[28 + 4] = 'X'; /* the client's NUL */
    ASSERT_EQ_INT(wire_cmd_check(bad, (size_t)len, why, sizeof why), WG_EDECODE);
    ASSERT_CONTAINS(why, "NUL");
    char client[65];
    int64_t seq;
    wire_cmd_header(buf, 40, client, sizeof client, &seq);
    ASSERT_STR(client, "wire");
    ASSERT_EQ_INT(seq, 7);
}

static void test_decode_errors(void)
{
    wgd *d = setup(128);
    unsigned char junk[37];
    for (unsigned i = 0; i < sizeof junk; i++)
        junk[i] = (unsigned char)(i * 37 + 11);
    lcm_publish(d->io.lcm, "T_CMD", junk, sizeof junk);
    drain(d);
    ASSERT_EQ_INT(F.nack, 1);
    ASSERT_STR(F.code, "EDECODE");
    ASSERT_EQ_INT(F.cmd_seq, -1);
    ASSERT_STR(F.client, "");
    ASSERT_CONTAINS(F.message, "unknown");
    /* a real cmd_t cut short: client and seq recovered from its header */
    char *n[1] = {"omega"};
    double v = 1.1;
    wormgear_cmd_t c = {.seq = 4242, .client = "cutter", .op = "set", .nparams = 1,
                        .names = n, .values = &v, .unit = "", .name = ""};
    unsigned char buf[512];
    int len = wormgear_cmd_t_encode(buf, 0, sizeof buf, &c);
    ASSERT_TRUE(len > 50);
    lcm_publish(d->io.lcm, "T_CMD", buf, 50);
    drain(d);
    ASSERT_EQ_INT(F.nack, 2);
    ASSERT_STR(F.code, "EDECODE");
    ASSERT_EQ_INT(F.cmd_seq, 4242);
    ASSERT_STR(F.client, "cutter");
    ASSERT_CONTAINS(F.message, "truncated");
    lcm_publish(d->io.lcm, "T_CMD", buf, 0); /* empty */
    drain(d);
    ASSERT_EQ_INT(F.nack, 3);
    ASSERT_EQ_INT(F.cmd_seq, -1);
    ASSERT_EQ_INT(d->stat.cmds_refused, 3);
    ASSERT_EQ_INT(set1(d, "omega", 1.1), WG_OK); /* still serving */
    teardown(d);
}

/* Random corruption of a valid command: every message gets exactly one ACK,
 * nothing crashes or leaks (run under ASan), the daemon keeps serving. */
static void test_fuzz_one_ack_each(void)
{
    wgd *d = setup(128);
    unsigned char buf[1024], m[1024];
    int len = encode_full(buf, sizeof buf);
    unsigned seed = 20240611u;
    printf("  fuzz seed %u\n", seed);
    for (int i = 0; i < 1000; i++) {
        memcpy(m, buf, (size_t)len);
        for (int k = 0; k < 1 + i % 4; k++) {
            seed = seed * 1103515245u + 12345u;
            m[(seed >> 8) % (unsigned)len] ^= (unsigned char)(1u << ((seed >> 4) % 8));
        }
        seed = seed * 1103515245u + 12345u;
        int n0 = F.nack;
        cmd_handle(d, m, (size_t)(i % 7 ? len : (int)((seed >> 8) % (unsigned)len)));
        drain(d);
        ASSERT_EQ_INT(F.nack, n0 + 1);
    }
    ASSERT_EQ_INT(set1(d, "omega", 1.0), WG_OK);
    run(d, 1000);
    teardown(d);
}

TEST_MAIN(TEST(test_wire_check), TEST(test_decode_errors), TEST(test_fuzz_one_ack_each))

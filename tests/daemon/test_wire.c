/* test_wire.c - raw bytes on the command channel: the wire check in front
 * of the generated decoder, undecodable and truncated messages answered
 * (client and seq recovered), 1000 corrupted commands with one ACK each. */
#include "fixture.h"
#include "wire.h"

static int encode_full(unsigned char *buf, int max)
{
    char *n[3] = {"omega", "xi_p", "k_a"};
    double v[3] = {1.1, 0.09, 0.3};
    wormgear_cmd_t c = {.utime = 1700000000123456, .seq = 7, .client = "wire", .op = "set",
                        .nparams = 3, .names = n,
                        .values = v, .has_from = 1, .from = 2, .duration = 3, .unit = "s",
                        .nsteps = 9, .name = "x", .rate = 1};
    return wormgear_cmd_t_encode(buf, 0, max, &c);
}

static void test_wire_check(void)
{
    unsigned char buf[1024];
    char why[160];
    int len = encode_full(buf, sizeof buf);
    ASSERT_EQ_INT(wire_cmd_check(buf, (size_t)len, NULL, why, sizeof why), WG_OK);
    for (int cut = 0; cut < len; cut++) /* every strict prefix is refused */
        ASSERT_EQ_INT(wire_cmd_check(buf, (size_t)cut, NULL, why, sizeof why), WG_EDECODE);
    /* nparams (after fingerprint, utime, seq, client, op) set huge / negative */
    size_t at = 24 + 4 + 5 + 4 + 4;
    unsigned char bad[1024];
    memcpy(bad, buf, (size_t)len);
    bad[at] = 0x7f, bad[at + 1] = bad[at + 2] = bad[at + 3] = 0xff;
    ASSERT_EQ_INT(wire_cmd_check(bad, (size_t)len, NULL, why, sizeof why), WG_EDECODE);
    ASSERT_CONTAINS(why, "nparams");
    bad[at] = 0xff;
    ASSERT_EQ_INT(wire_cmd_check(bad, (size_t)len, NULL, why, sizeof why), WG_EDECODE);
    memcpy(bad, buf, (size_t)len);
    bad[24] = 0x80; /* client length negative */
    ASSERT_EQ_INT(wire_cmd_check(bad, (size_t)len, NULL, why, sizeof why), WG_EDECODE);
    ASSERT_CONTAINS(why, "string length");
    memcpy(bad, buf, (size_t)len);
    bad[28 + 4] = 'X'; /* the client's NUL */
    ASSERT_EQ_INT(wire_cmd_check(bad, (size_t)len, NULL, why, sizeof why), WG_EDECODE);
    ASSERT_CONTAINS(why, "NUL");
    char client[65];
    int64_t seq, utime;
    wire_cmd_header(buf, 40, client, sizeof client, &seq, &utime);
    ASSERT_STR(client, "wire");
    ASSERT_EQ_INT(seq, 7);
    ASSERT_EQ_INT(utime, 1700000000123456);
    wire_cmd_header(buf, 23, client, sizeof client, &seq, &utime); /* no seq: nothing */
    ASSERT_EQ_INT(seq, -1);
    ASSERT_EQ_INT(utime, 0);
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

/* Issue 10, defect 11: bytes after a complete message, and a NUL inside a
 * string ("get\0junk" acted as get), are refused; EDECODE names the field
 * and the limit (defect 12). */
static void test_trailing_and_inner_nul(void)
{
    wgd *d = setup(128);
    wormgear_cmd_t c = {.seq = 31, .client = "tail", .op = "get", .unit = "", .name = ""};
    unsigned char buf[600];
    int len = wormgear_cmd_t_encode(buf, 0, sizeof buf - 8, &c);
    memcpy(buf + len, "junkjunk", 8);
    int n0 = F.nack;
    cmd_handle(d, buf, (size_t)len + 8);
    drain(d);
    ASSERT_EQ_INT(F.nack, n0 + 1);
    ASSERT_STR(F.code, "EDECODE");
    ASSERT_CONTAINS(F.message, "8 bytes after the end");
    ASSERT_STR(F.client, "tail");
    ASSERT_EQ_INT(F.cmd_seq, 31);
    len = wormgear_cmd_t_encode(buf, 0, sizeof buf, &c);
    size_t op = 24 + 4 + 5; /* "get" + NUL: its length field, then 'g' 'e' 't' 0 */
    ASSERT_EQ_INT(buf[op + 3], 4);
    unsigned char big[600];
    size_t k = 0; /* rebuild with op = "get\0junk" (length 9) */
    memcpy(big, buf, op), k = op;
    big[k++] = 0, big[k++] = 0, big[k++] = 0, big[k++] = 9;
    memcpy(big + k, "get\0junk", 9), k += 9;
    memcpy(big + k, buf + op + 4 + 4, (size_t)len - op - 8), k += (size_t)len - op - 8;
    cmd_handle(d, big, k);
    drain(d);
    ASSERT_STR(F.code, "EDECODE");
    ASSERT_CONTAINS(F.message, "field op");
    ASSERT_CONTAINS(F.message, "NUL byte inside");
    /* a string over the limit: the field and the limit named */
    static char longname[5001];
    memset(longname, 'n', 5000);
    char *nm[1] = {longname};
    double v = 1;
    wormgear_cmd_t l = {.seq = 32, .client = "tail", .op = "set", .nparams = 1, .names = nm,
                        .values = &v, .unit = "", .name = ""};
    static unsigned char lb[6000];
    len = wormgear_cmd_t_encode(lb, 0, sizeof lb, &l);
    cmd_handle(d, lb, (size_t)len);
    drain(d);
    ASSERT_STR(F.code, "EDECODE");
    ASSERT_CONTAINS(F.message, "field names[0]");
    ASSERT_CONTAINS(F.message, "4096");
    ASSERT_EQ_INT(F.cmd_seq, 32);
    teardown(d);
}

/* Issue 10, defect 4: the client id comes back byte for byte (UTF-8, tabs,
 * control bytes) up to 256 bytes on every ACK path (get, step, a set at
 * the section); a longer one is refused with an ACK that carries the seq
 * and the first 256 bytes, also when the string is over the wire limit. */
static void test_client_echo(void)
{
    wgd *d = setup(128);
    static char id[6000];
    memset(id, 'c', sizeof id - 1);
    static const size_t ok_len[] = {71, 72, 255, 256};
    for (unsigned i = 0; i < 4; i++) {
        id[ok_len[i]] = 0;
        wormgear_cmd_t g = {.op = "get", .client = id};
        ASSERT_EQ_INT(send(d, &g), WG_OK);
        ASSERT_EQ_INT(strlen(F.client), ok_len[i]);
        wormgear_cmd_t s = {.op = "step", .nsteps = 3, .client = id};
        ASSERT_EQ_INT(send(d, &s), WG_OK); /* the daemon is in lockstep */
        ASSERT_EQ_INT(strlen(F.client), ok_len[i]);
        id[ok_len[i]] = 'c';
    }
    static const size_t over[] = {257, 4096, 5000};
    for (unsigned i = 0; i < 3; i++) {
        id[over[i]] = 0;
        wormgear_cmd_t g = {.op = "get", .client = id, .seq = 900 + i, .unit = "", .name = ""};
        static unsigned char b[7000];
        int len = wormgear_cmd_t_encode(b, 0, sizeof b, &g);
        int n0 = F.nack;
        cmd_handle(d, b, (size_t)len);
        drain(d);
        ASSERT_EQ_INT(F.nack, n0 + 1);
        ASSERT_EQ_INT(F.accepted, 0);
        ASSERT_EQ_INT(F.cmd_seq, 900 + i);
        ASSERT_EQ_INT(strlen(F.client), 256);
        ASSERT_CONTAINS(F.message, "256");
        id[over[i]] = 'c';
    }
    static const char *odd[] = {"rig@m\xc3\xbcller", "tab\there", "ctl\x01\x02\x7f"};
    for (unsigned i = 0; i < 3; i++) {
        wormgear_cmd_t g = {.op = "get", .client = (char *)odd[i]};
        ASSERT_EQ_INT(send(d, &g), WG_OK);
        ASSERT_STR(F.client, odd[i]);
    }
    /* the deferred set's ACK, sent at the section, echoes it too */
    run(d, 5);
    char *n[1] = {"xi_p"};
    double v = 0.09;
    wormgear_cmd_t s = {.op = "set", .nparams = 1, .names = n, .values = &v, .at_section = 1,
                        .client = (char *)odd[0], .unit = "", .name = "", .seq = 950};
    wormgear_cmd_t_publish(d->io.lcm, "T_CMD", &s);
    drain(d);
    run(d, 200);
    ASSERT_EQ_INT(F.cmd_seq, 950);
    ASSERT_STR(F.client, odd[0]);
    teardown(d);
}

/* A TICK carries a client id since ticks are signed: its bytes are walked
 * as a command's are before the generated decoder (which would take any
 * string length) sees them. In the daemon a bad one owes nothing, is
 * counted and told on STATUS, and answered on ACK (op "tick", EDECODE),
 * addressed to what its bytes still say. */
static void test_tick_check(void)
{
    unsigned char buf[1024], bad[1024], mac[32] = {0};
    char why[160], id[300];
    wormgear_tick_t t = {.utime = 1, .seq = 3, .nsteps = 5, .client = "rig",
                         .mac_len = 32, .mac = mac};
    int len = wormgear_tick_t_encode(buf, 0, sizeof buf, &t);
    int32_t mac_len = -1;
    ASSERT_EQ_INT(wire_tick_check(buf, (size_t)len, &mac_len, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(mac_len, 32);
    for (int cut = 0; cut < len; cut++)
        ASSERT_EQ_INT(wire_tick_check(buf, (size_t)cut, NULL, why, sizeof why), WG_EDECODE);
    ASSERT_EQ_INT(wire_tick_check(buf, (size_t)len + 1, NULL, why, sizeof why), WG_EDECODE);
    ASSERT_CONTAINS(why, "1 bytes after the end of a complete tick_t");
    memcpy(bad, buf, (size_t)len);
    bad[32] = 0x7f; /* the client's length (after fingerprint, utime, seq, nsteps) huge */
    ASSERT_EQ_INT(wire_tick_check(bad, (size_t)len, NULL, why, sizeof why), WG_EDECODE);
    ASSERT_CONTAINS(why, "client");
    memset(id, 'x', sizeof id - 1);
    id[sizeof id - 1] = 0;
    t.client = id; /* 299 bytes: over WIRE_MAX_CLIENT */
    len = wormgear_tick_t_encode(buf, 0, sizeof buf, &t);
    ASSERT_EQ_INT(wire_tick_check(buf, (size_t)len, NULL, why, sizeof why), WG_EDECODE);
    ASSERT_CONTAINS(why, "the limit is 256");
    ASSERT_EQ_INT(wire_cmd_check(buf, (size_t)len, NULL, why, sizeof why), WG_EDECODE);
    ASSERT_CONTAINS(why, "not a wormgear.cmd_t");
    wgd *d = setup(128);
    uint64_t refused = d->stat.ticks_refused;
    int nack = F.nack;
    lcm_publish(d->io.lcm, "T_TICK", buf, (unsigned)len);
    drain(d);
    ASSERT_EQ_INT(F.nack, nack + 1); /* the id too long: its first 256 bytes echoed */
    ASSERT_STR(F.op, "tick");
    ASSERT_STR(F.code, "EDECODE");
    ASSERT_EQ_INT(F.cmd_seq, 3);
    ASSERT_EQ_INT(F.cmd_utime, 1);
    ASSERT_EQ_INT((int)strlen(F.client), WIRE_MAX_CLIENT);
    ASSERT_TRUE(strspn(F.client, "x") == WIRE_MAX_CLIENT);
    ASSERT_CONTAINS(F.message, "the limit is 256");
    memcpy(bad, buf, (size_t)len);
    lcm_publish(d->io.lcm, "T_TICK", bad, 20);
    drain(d);
    ASSERT_EQ_INT(d->owed.ticks, 0);
    ASSERT_EQ_INT(d->stat.ticks_refused, refused + 2);
    ASSERT_CONTAINS(d->stat.tick_why, "undecodable TICK message (20 bytes) ignored: ");
    ASSERT_EQ_INT(F.nack, nack + 2); /* nothing left to address it to */
    ASSERT_EQ_INT(F.cmd_seq, -1);
    ASSERT_STR(F.client, "");
    ASSERT_STR(F.code, "EDECODE");
    t.client = "rig";
    len = wormgear_tick_t_encode(buf, 0, sizeof buf, &t);
    lcm_publish(d->io.lcm, "T_TICK", buf, (unsigned)len); /* keyless: a MAC is ignored */
    drain(d);
    ASSERT_EQ_INT(d->owed.ticks, 5);
    teardown(d);
}

TEST_MAIN(TEST(test_wire_check), TEST(test_tick_check), TEST(test_decode_errors), TEST(test_fuzz_one_ack_each),
          TEST(test_trailing_and_inner_nul), TEST(test_client_echo))

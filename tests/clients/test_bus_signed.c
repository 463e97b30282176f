/* test_bus_signed.c - what a client with a key takes (bus_signed, bus.h):
 * the daemon's signed ACK, PARAMS and STATUS, and of those only ones sent
 * after the client started (the daemon's clock may lag by BUS_AHEAD_S) and
 * not before the newest of their type already taken. A signed answer is
 * matched to its command by client id and seq: played back, an answer to
 * an earlier process with the same pid and seq was taken (wgctl counts
 * from 1), and a STATUS captured an hour ago could stand for the daemon's
 * mode when wgrig put the daemon back. The hint says what came. */
#include "test.h"

#include "bus.h"
#include "bus_msg.h"
#include "cli.h"
#include "lcmtypes/wormgear_status_t.h"

#include <string.h>

static const unsigned char KEY[WG_KEY_BYTES] = {7,  1,  2,  3,  4,  5,  6,  7,  8,  9,  10,
                                                11, 12, 13, 14, 15, 16, 17, 18, 19, 20, 21,
                                                22, 23, 24, 25, 26, 27, 28, 29, 30, 31};
static unsigned char buf[4096];

/* An ACK to c's last command (its client, seq and utime echoed), sent at
 * utime, signed with KEY (or not). */
static int ack_op(const bus *c, int64_t utime, int sign, const char *code, const char *op)
{
    unsigned char mac[WG_MAC_BYTES] = {0};
    wormgear_ack_t m = {.utime = utime, .client = (char *)c->client, .cmd_seq = c->seq,
                        .cmd_utime = c->cmd_utime,
                        .op = (char *)op, .accepted = !strcmp(code, "OK"), .code = (char *)code,
                        .message = "done", .mac_len = WG_MAC_BYTES, .mac = mac};
    int n = wormgear_ack_t_encode(buf, 0, sizeof buf, &m);
    if (sign)
        wg_mac_seal(KEY, buf, (size_t)n);
    return n;
}

static int ack(const bus *c, int64_t utime, int sign, const char *code)
{
    return ack_op(c, utime, sign, code, "set");
}

static int status(int64_t utime)
{
    unsigned char mac[WG_MAC_BYTES] = {0};
    double z[6] = {0};
    wormgear_status_t m = {.utime = utime, .scene = "s", .mode = "fast", .run = "running",
                           .health = "ok", .fault = "", .motion = "", .nbearing = 6,
                           .bearing_impacts_per_period = z, .bearing_impact_vmax = z,
                           .regime = "", .tick_refusal = "", .mac_len = WG_MAC_BYTES, .mac = mac};
    int n = wormgear_status_t_encode(buf, 0, sizeof buf, &m);
    wg_mac_seal(KEY, buf, (size_t)n);
    return n;
}

static int take(bus *c, int type, int n)
{
    lcm_recv_buf_t rb = {.data = buf, .data_size = (uint32_t)n};
    return bus_signed(c, type, &rb);
}

#define S INT64_C(1000000)

static bus *open_signing(void)
{
    static bus c;
    char why[256];
    ASSERT_EQ_INT(bus_open(&c, "memq://", "T_", "t", why, sizeof why), 0);
    c.signing = 1;
    memcpy(c.key, KEY, sizeof KEY);
    return &c;
}

static void test_fresh_and_old(void)
{
    bus *c = open_signing();
    int64_t t0 = c->opened_us;
    ASSERT_EQ_INT(take(c, BUS_ACK, ack(c, t0 - S / 2, 1, "OK")), 1); /* clock 0.5 s behind */
    ASSERT_EQ_INT(take(c, BUS_ACK, ack(c, t0 + 5 * S, 1, "OK")), 1);
    ASSERT_EQ_INT(take(c, BUS_ACK, ack(c, t0 + 4 * S, 1, "OK")), 0); /* before the newest */
    ASSERT_EQ_INT(c->old_n, 1);
    ASSERT_NEAR(c->old_s, 1.0, 1e-9);
    ASSERT_STR(c->old_type, "ACK");
    ASSERT_EQ_INT(take(c, BUS_ACK, ack(c, t0 + 5 * S, 1, "OK")), 1); /* the same time: taken */
    /* each type on its own: a STATUS 2 s before the newest ACK is new for STATUS */
    ASSERT_EQ_INT(take(c, BUS_STATUS, status(t0 + 3 * S)), 1);
    ASSERT_EQ_INT(take(c, BUS_STATUS, status(t0 - 3600 * S)), 0); /* an hour old */
    ASSERT_EQ_INT(c->old_n, 2);
    ASSERT_STR(c->old_type, "STATUS");
    ASSERT_EQ_INT(take(c, BUS_ACK, ack(c, t0 + 6 * S, 0, "OK")), 0); /* unsigned: another count */
    ASSERT_EQ_INT(c->unverified_n, 1);
    ASSERT_EQ_INT(c->old_n, 2);
    bus_close(c);
    /* a new client: 1.5 s before it opened is too old, whatever came before */
    c = open_signing();
    ASSERT_EQ_INT(take(c, BUS_STATUS, status(c->opened_us - 3 * S / 2)), 0);
    ASSERT_EQ_INT(take(c, BUS_STATUS, status(c->opened_us - 9 * S / 10)), 1);
    c->signing = 0; /* nothing to verify: everything taken */
    ASSERT_EQ_INT(take(c, BUS_STATUS, status(0)), 1);
    bus_close(c);
}

/* An ACK to this command, signed, but sent before the client started (an
 * earlier wgctl with this pid and seq): not taken, and the hint says it
 * was the daemon's key but an old answer; a fresh one is then taken. */
static void test_played_back_ack(void)
{
    bus *c = open_signing();
    char ch[64], hint[1024];
    wormgear_cmd_t cmd = bus_cmd("get");
    ASSERT_TRUE(bus_send(c, &cmd) == 1);
    int n = ack(c, c->opened_us - 3600 * S, 1, "OK");
    lcm_publish(c->lcm, bus_channel(c, "ACK", ch, sizeof ch), buf, (unsigned)n);
    ASSERT_EQ_INT(bus_wait_ack(c, 200), -1);
    bus_hint(c, hint, sizeof hint);
    ASSERT_CONTAINS(hint, "an answer signed with this key came (OK: done), and was not taken");
    ASSERT_CONTAINS(hint, "3600.0 s before this client started");
    n = ack(c, c->opened_us - 3600 * S, 0, "EAUTH");
    lcm_publish(c->lcm, ch, buf, (unsigned)n);
    ASSERT_EQ_INT(bus_wait_ack(c, 200), -1);
    bus_hint(c, hint, sizeof hint);
    ASSERT_CONTAINS(hint, "not signed with this key (EAUTH: done)");
    n = ack(c, cli_wall_us(), 1, "OK");
    lcm_publish(c->lcm, ch, buf, (unsigned)n);
    ASSERT_EQ_INT(bus_wait_ack(c, 1000), 0);
    ASSERT_TRUE(c->ack.accepted);
    bus_close(c);
}

/* The daemon's signed, fresh answer to an earlier process's command with
 * this client id and seq (a reused pid, within the second before this
 * client started, or while the daemon's clock stepped back): the freshness
 * rules take it, but the ACK names its command by utime too, so it is not
 * this command's answer (not even counted as unverified: someone else's). */
static void test_ack_names_the_command(void)
{
    bus *c = open_signing();
    char ch[64];
    wormgear_cmd_t cmd = bus_cmd("get");
    ASSERT_TRUE(bus_send(c, &cmd) == 1);
    int64_t mine = c->cmd_utime;
    ASSERT_EQ_INT(cmd.utime, mine);
    c->cmd_utime = mine - S / 2; /* the earlier process's command, half a second before */
    int n = ack(c, cli_wall_us(), 1, "OK");
    c->cmd_utime = mine;
    lcm_publish(c->lcm, bus_channel(c, "ACK", ch, sizeof ch), buf, (unsigned)n);
    ASSERT_EQ_INT(bus_wait_ack(c, 200), -1);
    ASSERT_TRUE(!c->ack.got && !c->unverified.got);
    n = ack(c, cli_wall_us(), 1, "OK");
    lcm_publish(c->lcm, ch, buf, (unsigned)n);
    ASSERT_EQ_INT(bus_wait_ack(c, 1000), 0);
    ASSERT_TRUE(c->ack.accepted);
    bus_close(c);
}

/* A refused tick's ACK (op "tick") names the tick by client, seq and
 * utime; command and tick seqs are counters of their own, so the utime
 * tells them apart (bus.c's stamp: no two messages of one bus share one),
 * and the tick's answer is not taken for the command's: it goes to
 * c->tick_ack, and only with op "tick". */
static void test_tick_answer_not_the_command(void)
{
    bus *c = open_signing();
    char ch[64];
    wormgear_cmd_t cmd = bus_cmd("get");
    ASSERT_TRUE(bus_send(c, &cmd) > 0);
    c->tick_seq = c->seq - 1; /* the next tick's seq is the command's */
    ASSERT_TRUE(bus_tick(c, 1) == c->seq);
    int64_t mine = c->cmd_utime;
    c->cmd_utime = c->tick_utime; /* a refused tick's answer: the same client and seq */
    static unsigned char tick_ack[4096];
    int nt = ack_op(c, cli_wall_us(), 1, "EAUTH", "tick");
    memcpy(tick_ack, buf, (size_t)nt);
    int n = ack(c, cli_wall_us(), 1, "EAUTH");
    c->cmd_utime = mine;
    lcm_publish(c->lcm, bus_channel(c, "ACK", ch, sizeof ch), buf, (unsigned)n);
    ASSERT_EQ_INT(bus_wait_ack(c, 200), -1);
    ASSERT_TRUE(!c->ack.got && !c->unverified.got && !c->tick_ack.got); /* op "set" */
    lcm_publish(c->lcm, ch, tick_ack, (unsigned)nt);
    ASSERT_EQ_INT(bus_wait_ack(c, 200), -1); /* the command's still unanswered ... */
    ASSERT_TRUE(!c->ack.got && c->tick_ack.got); /* ... the tick's refused */
    ASSERT_STR(c->tick_ack.code, "EAUTH");
    bus_close(c);
}

TEST_MAIN(TEST(test_fresh_and_old), TEST(test_played_back_ack), TEST(test_ack_names_the_command),
          TEST(test_tick_answer_not_the_command))

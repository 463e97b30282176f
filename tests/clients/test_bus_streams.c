/* test_bus_streams.c - telling senders apart on one channel (bus.h): in
 * order, a gap, a daemon restart, a replay played into a live bus (the
 * symptom of issue 12 item 8: "restarted x20, dropped 6539493"), two live
 * senders on one clock, sender ids, and eviction when too many lines; and
 * strings off the bus made safe to show on a terminal (cli_text). */
#include "test.h"

#include "bus.h"
#include "cli.h"

#include <limits.h>

/* Feed one message at receive time now_s (the wall clock moves with it). */
static int note(bus_streams *b, int64_t seq, double utime_s, double now_s, int64_t sender,
                int *line)
{
    const double wall0 = 1.7e9; /* an epoch second */
    return bus_streams_note(b, seq, (int64_t)((wall0 + utime_s) * 1e6), sender, now_s,
                            (int64_t)((wall0 + now_s) * 1e6), line);
}

static void test_in_order_and_gap(void)
{
    bus_streams b = {0};
    int line;
    ASSERT_EQ_INT(note(&b, 10, 0.0, 0.0, 0, &line), BUS_NEW);
    ASSERT_EQ_INT(note(&b, 11, 0.02, 0.02, 0, &line), BUS_IN_ORDER);
    ASSERT_EQ_INT(note(&b, 15, 0.04, 0.04, 0, &line), BUS_GAP);
    ASSERT_EQ_INT(b.n, 1);
    ASSERT_EQ_INT(b.gaps, 1);
    ASSERT_EQ_INT(b.missing, 3);
    ASSERT_EQ_INT(b.senders, 1);
    ASSERT_EQ_INT(b.restarts, 0);
    ASSERT_TRUE(!bus_stream_replayed(&b.s[0]));
}

/* A daemon stops at seq 500 and starts again from 0: one restart, no loss;
 * the old line expires. */
static void test_restart(void)
{
    bus_streams b = {0};
    int line;
    double t = 0;
    for (int64_t q = 400; q <= 500; q++, t += 0.02)
        note(&b, q, t, t, 0, &line);
    t += 0.5;
    ASSERT_EQ_INT(note(&b, 0, t, t, 0, &line), BUS_RESTART);
    for (int64_t q = 1; q < 300; q++, t += 0.02)
        ASSERT_EQ_INT(note(&b, q, t, t, 0, &line), BUS_IN_ORDER);
    ASSERT_EQ_INT(b.restarts, 1);
    ASSERT_EQ_INT(b.senders, 1);
    ASSERT_EQ_INT(b.missing, 0);
    ASSERT_EQ_INT(b.n, 1); /* the old line expired after 5 s of silence */
    ASSERT_EQ_INT(b.s[0].first_seq, 0);
}

/* A log recorded an hour ago played into a live bus: seq interleaved both
 * below and above the live ones. Two senders, one replayed; no restart, no
 * loss (a seq counter alone reports both by the thousand). */
static void test_replay_into_live(void)
{
    bus_streams b = {0};
    bus_seq naive = {0};
    int line, live = -1, rep = -1;
    double t = 0;
    for (int k = 0; k < 400; k++, t += 0.01) {
        int64_t ql = 5000 + k, qr = (k < 200 ? 100 : 9000) + k; /* the replay jumps over */
        note(&b, ql, t, t, 0, &line);
        live = line;
        bus_seq_note(&naive, ql);
        note(&b, qr, t - 3600.0 + (k < 200 ? 0 : 0.3), t + 0.005, 0, &line);
        rep = line;
        bus_seq_note(&naive, qr);
    }
    ASSERT_TRUE(naive.restarts > 100 && naive.missing > 100000); /* the old symptom */
    ASSERT_EQ_INT(b.n, 2);
    ASSERT_EQ_INT(b.restarts, 0);
    ASSERT_EQ_INT(b.senders, 2);
    ASSERT_EQ_INT(b.gaps, 1); /* the replay's own jump, 100+199 -> 9200 */
    ASSERT_TRUE(live != rep);
    ASSERT_TRUE(!bus_stream_replayed(&b.s[live]));
    ASSERT_TRUE(bus_stream_replayed(&b.s[rep]));
    ASSERT_EQ_INT(b.s[live].msgs, 400);
    ASSERT_EQ_INT(b.s[rep].msgs, 400);
}

/* Two live daemons on one prefix (one clock): the first step back looks
 * like a restart, until the old line goes on: then it is taken back. */
static void test_two_live_senders(void)
{
    bus_streams b = {0};
    int line;
    double t = 0;
    for (int k = 0; k < 50; k++, t += 0.01) {
        note(&b, 1000 + k, t, t, 0, &line);
        note(&b, 10 + k, t, t + 0.001, 0, &line);
    }
    ASSERT_EQ_INT(b.n, 2);
    ASSERT_EQ_INT(b.restarts, 0);
    ASSERT_EQ_INT(b.senders, 2);
    ASSERT_EQ_INT(b.concurrent, 1);
    ASSERT_EQ_INT(b.missing, 0);
}

/* With sender ids the id decides, whatever the seq and clock do. */
static void test_sender_ids(void)
{
    bus_streams b = {0};
    int l1, l2;
    ASSERT_EQ_INT(note(&b, 7, 0, 0, 0x1111, &l1), BUS_NEW);
    ASSERT_EQ_INT(note(&b, 7, 0, 0.01, 0x2222, &l2), BUS_NEW);
    ASSERT_EQ_INT(note(&b, 8, 0, 0.02, 0x1111, &l1), BUS_IN_ORDER);
    ASSERT_EQ_INT(note(&b, 10, 0, 0.03, 0x2222, &l2), BUS_GAP);
    ASSERT_TRUE(l1 != l2);
    ASSERT_EQ_INT(b.s[l1].sender, 0x1111);
    ASSERT_EQ_INT(b.missing, 2); /* 8 and 9 of sender 0x2222 */
    ASSERT_EQ_INT(b.senders, 2);
}

/* More senders than lines: the least recently heard makes room. */
static void test_eviction(void)
{
    bus_streams b = {0};
    int line;
    for (int k = 0; k < BUS_NSTREAM + 2; k++)
        note(&b, 0, -100.0 * (k + 1), 0.01 * k, 0, &line); /* each its own clock */
    ASSERT_EQ_INT(b.n, BUS_NSTREAM);
    ASSERT_EQ_INT(b.senders, BUS_NSTREAM + 2);
    ASSERT_EQ_INT(b.s[0].id, 3);
}

/* Escapes a terminal would obey (ESC, BEL, the C1 CSI U+009B, DEL) and
 * bytes outside well-formed UTF-8 become '?'; text, UTF-8 (µ, €, 😀)
 * included, stays; the copy is cut at a character; cleaning in place works. */
static void test_text_clean(void)
{
    char out[64];
    ASSERT_STR(cli_text(out, sizeof out, "x_n 1.5 \xc2\xb5m \xe2\x82\xac \xf0\x9f\x98\x80"),
               "x_n 1.5 \xc2\xb5m \xe2\x82\xac \xf0\x9f\x98\x80");
    ASSERT_STR(cli_text(out, sizeof out, "a\033[2Jb\007c\xc2\x9b" "31m\x7f\xff\xc0\xaf\xed\xa0\x80."),
               "a?[2Jb?c?31m???????.");
    ASSERT_STR(cli_text(out, 4, "ab\xc2\xb5"), "ab"); /* no half of µ */
    ASSERT_STR(cli_text(out, sizeof out, NULL), "");
    char in[] = "<b>\033]0;t\007</b>";
    ASSERT_STR(cli_text(in, sizeof in, in), "<b>?]0;t?</b>");
}

/* Any sender's int64 seq and utime: no overflow (UBSan stopped wgmon and
 * wglog on one such STATUS, a hostile-input review), the counts saturate. */
static void test_hostile_numbers(void)
{
    bus_streams b = {0};
    int line;
    ASSERT_EQ_INT(bus_streams_note(&b, 5, INT64_MIN, 0, 0.0, 1700000000000000, &line), BUS_NEW);
    ASSERT_EQ_INT(bus_streams_note(&b, INT64_MIN, INT64_MAX, 0, 0.1, 1700000000100000, &line),
                  BUS_NEW);
    ASSERT_EQ_INT(note(&b, INT64_MIN + 1, 0, 0.2, 0x1111, &line), BUS_NEW);
    ASSERT_EQ_INT(note(&b, INT64_MAX, 0, 0.3, 0x1111, &line), BUS_GAP); /* 2^64 - 3 lost */
    ASSERT_EQ_INT(note(&b, INT64_MAX, 0, 0.4, 0x1111, &line), BUS_RESTART);
    ASSERT_TRUE(b.missing == LONG_MAX);
    bus_seq s = {0};
    ASSERT_EQ_INT(bus_seq_note(&s, INT64_MAX - 1), 0);
    ASSERT_EQ_INT(bus_seq_note(&s, INT64_MAX), 0);
    ASSERT_EQ_INT(bus_seq_note(&s, INT64_MIN), -1);
    ASSERT_EQ_INT(bus_seq_note(&s, INT64_MAX), 1);
    ASSERT_TRUE(s.missing == LONG_MAX);
    ASSERT_EQ_INT(s.gaps, 1);
}

TEST_MAIN(TEST(test_in_order_and_gap), TEST(test_restart), TEST(test_replay_into_live),
          TEST(test_two_live_senders), TEST(test_sender_ids), TEST(test_eviction), TEST(test_text_clean),
          TEST(test_hostile_numbers))

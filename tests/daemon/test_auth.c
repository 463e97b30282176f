/* test_auth.c - signed commands (issue 10): with a key, a command signed
 * with it is accepted; unsigned, signed with another key, stale or replayed
 * commands get EAUTH and change nothing; key files are checked. A captured
 * command stays refused after a restart (a fresh auth, as a new process
 * has) and a key change, whatever the client's clock; thousands of client
 * ids within the window are all accepted and none becomes replayable. */
#include "fixture.h"

#include <sodium.h>
#include <sys/stat.h>

static unsigned char key_a[WG_KEY_BYTES], key_b[WG_KEY_BYTES];

/* Encode a set of omega, signed with key (NULL: unsigned), utime shifted
 * by skew seconds from now; publish it and handle it. */
static void send_set(wgd *d, const unsigned char *key, int64_t seq, double skew, double omega)
{
    char *n[1] = {"omega"};
    unsigned char buf[1024], mac[WG_MAC_BYTES] = {0};
    wormgear_cmd_t c = {.utime = lcmio_now_us() + (int64_t)(skew * 1e6), .seq = seq,
                        .client = "signer", .op = "set", .nparams = 1, .names = n,
                        .values = &omega, .unit = "", .name = "",
                        .mac_len = key ? WG_MAC_BYTES : 0, .mac = mac};
    int len = wormgear_cmd_t_encode(buf, 0, sizeof buf, &c);
    if (key)
        wg_mac(key, buf, (size_t)len - WG_MAC_BYTES - 4, buf + len - WG_MAC_BYTES);
    lcm_publish(d->io.lcm, "T_CMD", buf, (unsigned)len);
    drain(d);
}

static void write_key(const char *path, const unsigned char *key, int mode)
{
    char hex[2 * WG_KEY_BYTES + 1];
    sodium_bin2hex(hex, sizeof hex, key, WG_KEY_BYTES);
    FILE *f = fopen(path, "w");
    fprintf(f, "%s\n", hex);
    fclose(f);
    chmod(path, (mode_t)mode);
}

static void new_keys(void)
{
    ASSERT_TRUE(sodium_init() >= 0);
    crypto_auth_keygen(key_a);
    crypto_auth_keygen(key_b);
}

static void test_signed_commands(void)
{
    new_keys();
    char path[300];
    snprintf(path, sizeof path, "%s/key", fx_statedir());
    write_key(path, key_a, 0600);
    wgd *d = setup(128);
    char why[300];
    /* taken 2 s ago: the daemon waits AUTH_AHEAD_S after taking a key */
    ASSERT_EQ_INT(auth_load(&d->auth, path, lcmio_now_us() - 2000000, why, sizeof why), WG_OK);
    double om = d->sim.p.v[WG_P_OMEGA];
    send_set(d, key_a, 10, 0, 1.1); /* signed with the key: applied */
    ASSERT_STR(F.code, "OK");
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.1, 0);
    om = 1.1;
    struct { const unsigned char *key; int64_t seq; double skew; const char *says; } bad[] = {
        {NULL, 11, 0, "unsigned command"},      {key_b, 12, 0, "bad signature"},
        {key_a, 13, 60, "60 s ahead of the daemon's clock"},       {key_a, 14, -45, "stale command"},
        {key_a, 14, 1.5, "1.5 s ahead"},
        {key_a, 10, 0, "replayed or reordered"}, {key_a, 9, 0, "replayed or reordered"}};
    for (unsigned i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        send_set(d, bad[i].key, bad[i].seq, bad[i].skew, 1.3);
        ASSERT_STR(F.code, "EAUTH");
        ASSERT_CONTAINS(F.message, bad[i].says);
        ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], om, 0); /* nothing changed */
    }
    send_set(d, key_a, 15, 0, 1.2); /* the next seq: accepted */
    ASSERT_STR(F.code, "OK");
    ASSERT_EQ_INT(d->auth.refused, 7);
    /* key files: group-readable, not a key, missing; the old key stays */
    write_key(path, key_b, 0644);
    ASSERT_EQ_INT(auth_load(&d->auth, path, lcmio_now_us(), why, sizeof why), WG_EIO);
    ASSERT_CONTAINS(why, "chmod 600");
    FILE *f = fopen(path, "w");
    fprintf(f, "not a key\n");
    fclose(f);
    chmod(path, 0600);
    ASSERT_EQ_INT(auth_load(&d->auth, path, lcmio_now_us(), why, sizeof why), WG_EINVAL);
    ASSERT_CONTAINS(why, "64 hexadecimal digits");
    /* a placeholder key (every byte the same) was taken */
    for (int b = 0; b < 2; b++) {
        f = fopen(path, "w");
        for (int k = 0; k < 32; k++)
            fprintf(f, "%s", b ? "ff" : "00");
        fclose(f);
        ASSERT_EQ_INT(auth_load(&d->auth, path, lcmio_now_us(), why, sizeof why), WG_EINVAL);
        ASSERT_CONTAINS(why, "every byte of the key is the same, a placeholder anyone can guess");
    }
    ASSERT_EQ_INT(auth_load(&d->auth, "/nonexistent/key", lcmio_now_us(), why, sizeof why),
                  WG_EIO);
    ASSERT_TRUE(d->auth.on);
    send_set(d, key_a, 16, 0, 1.25);
    ASSERT_STR(F.code, "OK");
    /* off: unsigned again */
    ASSERT_EQ_INT(auth_load(&d->auth, "", lcmio_now_us(), why, sizeof why), WG_OK);
    send_set(d, NULL, 17, 0, 1.15);
    ASSERT_STR(F.code, "OK");
    /* the 64 digits, then one line end or none: "\nX", "\0\n", "\r\r" after them
     * were taken (two stray bytes passed) */
    static const struct { const char *tail; int len, ok; } ends[] = {
        {"", 0, 1}, {"\n", 1, 1}, {"\r\n", 2, 1}, {"\nX", 2, 0}, {"\0\n", 2, 0},
        {"\r\r", 2, 0}, {"\n\n", 2, 0}, {" ", 1, 0}, {"\r", 1, 0}};
    for (size_t i = 0; i < sizeof ends / sizeof ends[0]; i++) {
        FILE *f = fopen(path, "w");
        for (int k = 0; k < 32; k++)
            fprintf(f, "%02x", 0x40 + k);
        fwrite(ends[i].tail, 1, (size_t)ends[i].len, f);
        fclose(f);
        int rc = auth_load(&d->auth, path, lcmio_now_us(), why, sizeof why);
        if ((rc == WG_OK) != ends[i].ok)
            TEST_FAIL_("key file ending %zu: rc %d, want %s", i, rc,
                       ends[i].ok ? "taken" : "refused");
    }
    unlink(path);
    teardown(d);
}

/* Encode a TICK of nsteps from client with seq, signed with key (NULL:
 * unsigned), utime shifted by skew seconds from now, into buf; publish it
 * and handle it. Returns its length (to play it back). */
static int send_tick(wgd *d, const unsigned char *key, int64_t seq, double skew,
                     int64_t nsteps, unsigned char *buf, int cap)
{
    unsigned char mac[WG_MAC_BYTES] = {0};
    wormgear_tick_t t = {.utime = lcmio_now_us() + (int64_t)(skew * 1e6), .seq = seq,
                         .nsteps = nsteps, .client = "signer", /* the id of send_set too */
                         .mac_len = key ? WG_MAC_BYTES : 0, .mac = mac};
    int len = wormgear_tick_t_encode(buf, 0, cap, &t);
    if (key)
        wg_mac_seal(key, buf, (size_t)len);
    lcm_publish(d->io.lcm, "T_TICK", buf, (unsigned)len);
    drain(d);
    return len;
}

/* With a key a TICK is a command without an answer: anyone on the group
 * could otherwise drive a lockstep run (a rig's co-simulation) step by
 * step. A signed tick owes its steps; unsigned, another key's, stale,
 * ahead, or played back, it owes nothing, counts as refused (the seq gaps
 * untouched: a forger's seq says nothing) and says why. A client's
 * ticks count apart from its commands: tick seq 1 after command seq 10. */
static void test_signed_ticks(void)
{
    new_keys();
    char path[300], why[300];
    snprintf(path, sizeof path, "%s/key", fx_statedir());
    write_key(path, key_a, 0600);
    wgd *d = setup(128);
    ASSERT_EQ_INT(auth_load(&d->auth, path, lcmio_now_us() - 2000000, why, sizeof why), WG_OK);
    send_set(d, key_a, 10, 0, 1.1);
    ASSERT_STR(F.code, "OK");
    unsigned char buf[512], other[512];
    int len = send_tick(d, key_a, 1, 0, 100, buf, sizeof buf);
    ASSERT_EQ_INT(d->owed.ticks, 100);
    uint64_t gaps = d->stat.tick_gaps;
    ASSERT_EQ_INT(d->stat.ticks_refused, 0);
    lcm_publish(d->io.lcm, "T_TICK", buf, (unsigned)len); /* played back */
    drain(d);
    ASSERT_EQ_INT(d->owed.ticks, 100);
    ASSERT_EQ_INT(d->stat.ticks_refused, 1);
    ASSERT_CONTAINS(d->stat.tick_why,
                    "TICK (seq 1, 100 steps) refused: replayed or reordered tick");
    struct { const unsigned char *key; int64_t seq; double skew; } bad[] = {
        {NULL, 2, 0}, {key_b, 3, 0}, {key_a, 4, 60}, {key_a, 5, -45}, {key_a, 1, 0}};
    for (unsigned i = 0; i < sizeof bad / sizeof bad[0]; i++)
        send_tick(d, bad[i].key, bad[i].seq, bad[i].skew, 1000, other, sizeof other);
    ASSERT_EQ_INT(d->owed.ticks, 100);
    ASSERT_EQ_INT(d->stat.ticks_refused, 6);
    ASSERT_EQ_INT(d->stat.tick_gaps, gaps); /* seqs 2 ... 5 skipped: not counted as lost */
    ASSERT_STR(F.op, "tick"); /* each answered: the last */
    ASSERT_STR(F.code, "EAUTH");
    ASSERT_EQ_INT(F.cmd_seq, 1);
    ASSERT_EQ_INT(d->auth.refused, 6);
    report_status(d);
    drain(d);
    ASSERT_EQ_INT(F.ticks_refused, 6); /* what the driver sees */
    ASSERT_CONTAINS(F.tick_refusal, "TICK (seq 1, 1000 steps) refused: replayed or reordered");
    send_tick(d, key_a, 6, 0, 20, other, sizeof other);
    ASSERT_EQ_INT(d->owed.ticks, 120);
    send_set(d, key_a, 11, 0, 1.2); /* the command counter untouched by the ticks */
    ASSERT_STR(F.code, "OK");
    ASSERT_EQ_INT(auth_load(&d->auth, "", lcmio_now_us(), why, sizeof why), WG_OK);
    send_tick(d, NULL, 7, 0, 5, other, sizeof other); /* signing off: unsigned taken */
    ASSERT_EQ_INT(d->owed.ticks, 125);
    unlink(path);
    teardown(d);
}

/* ---- the auth module alone, on a clock of our own -------------------------- */

#define T0 INT64_C(1700000000000000) /* a wall time, us */
#define SEC INT64_C(1000000)

typedef struct msg {
    unsigned char buf[512];
    int len;
    int32_t mac_len;
    int chan; /* AUTH_CMD (sign) or AUTH_TICK (sign_tick) */
    char client[64];
    int64_t seq, utime;
} msg;

static char WHY[640];

/* A get from client with seq, signed with key at utime (the client's clock). */
static msg sign(const unsigned char *key, const char *client, int64_t seq, int64_t utime)
{
    msg m = {.seq = seq, .utime = utime};
    unsigned char mac[WG_MAC_BYTES] = {0};
    snprintf(m.client, sizeof m.client, "%s", client);
    wormgear_cmd_t c = {.utime = utime, .seq = seq, .client = m.client, .op = "get",
                        .unit = "", .name = "", .mac_len = WG_MAC_BYTES, .mac = mac};
    m.len = wormgear_cmd_t_encode(m.buf, 0, sizeof m.buf, &c);
    wg_mac(key, m.buf, (size_t)m.len - WG_MAC_BYTES - 4, m.buf + m.len - WG_MAC_BYTES);
    ASSERT_EQ_INT(wire_cmd_check(m.buf, (size_t)m.len, &m.mac_len, WHY, sizeof WHY), WG_OK);
    return m;
}

/* The same as a TICK of 1 step (chan AUTH_TICK); key NULL: unsigned. */
static msg sign_tick(const unsigned char *key, const char *client, int64_t seq, int64_t utime)
{
    msg m = {.seq = seq, .utime = utime, .chan = AUTH_TICK};
    unsigned char mac[WG_MAC_BYTES] = {0};
    snprintf(m.client, sizeof m.client, "%s", client);
    wormgear_tick_t t = {.utime = utime, .seq = seq, .nsteps = 1, .client = m.client,
                         .mac_len = key ? WG_MAC_BYTES : 0, .mac = mac};
    m.len = wormgear_tick_t_encode(m.buf, 0, sizeof m.buf, &t);
    if (key)
        wg_mac_seal(key, m.buf, (size_t)m.len);
    ASSERT_EQ_INT(wire_tick_check(m.buf, (size_t)m.len, &m.mac_len, WHY, sizeof WHY), WG_OK);
    return m;
}

/* Hand m to a at daemon wall time now_us: WG_OK, or WG_EAUTH with WHY. */
static int check(auth *a, const msg *m, int64_t now_us)
{
    WHY[0] = 0;
    return auth_check(a, m->chan, m->buf, (size_t)m->len, m->mac_len, m->client, m->seq,
                      m->utime, now_us, WHY, sizeof WHY);
}

/* A daemon that takes the key in path at now_us: a fresh auth, as every
 * new process (a restart, a restart after SIGKILL) has. */
static auth *start(const char *path, int64_t now_us)
{
    auth *a = calloc(1, sizeof *a);
    char why[300];
    ASSERT_EQ_INT(auth_load(a, path, now_us, why, sizeof why), WG_OK);
    return a;
}

static const char *key_file(const char *name, const unsigned char *key)
{
    static char path[2][300];
    char *p = path[key == key_b];
    snprintf(p, sizeof path[0], "%s/%s", fx_statedir(), name);
    write_key(p, key, 0600);
    return p;
}

/* Commands captured from a run stay refused by the next one, through the
 * whole freshness window, from clients behind, with, and ahead of the
 * daemon's clock; a command signed after the new run opened is accepted. */
static void test_replay_after_restart(void)
{
    new_keys();
    const char *path = key_file("key", key_a);
    auth *a = start(path, T0);
    int64_t t = T0 + 10 * SEC;
    msg cap[] = {sign(key_a, "wgctl-1@h", 1, t - 2 * SEC), /* 2 s behind */
                 sign(key_a, "wgctl-2@h", 1, t),           /* the daemon's clock */
                 sign(key_a, "wgctl-3@h", 1, t + 9 * SEC / 10), /* 0.9 s ahead */
                 sign(key_a, "wgweb-4@h", 7, t)};          /* a long-lived client */
    int n = (int)(sizeof cap / sizeof cap[0]);
    for (int i = 0; i < n; i++) {
        ASSERT_EQ_INT(check(a, &cap[i], t), WG_OK);
        ASSERT_EQ_INT(check(a, &cap[i], t + 1000), WG_EAUTH); /* the same run */
        ASSERT_CONTAINS(WHY, "replayed or reordered");
    }
    free(a); /* killed */
    int64_t t1 = t + 1000; /* the next run takes the key 1 ms later */
    a = start(path, t1);
    ASSERT_TRUE(auth_open_us(a) == t1 + (int64_t)(AUTH_AHEAD_S * SEC));
    for (int64_t now = t1; now < t + 32 * SEC; now += SEC / 8) {
        for (int i = 0; i < n; i++) {
            ASSERT_EQ_INT(check(a, &cap[i], now), WG_EAUTH);
            if (!strstr(WHY, "stale command"))
                ASSERT_CONTAINS(WHY, "before this daemon started taking signed commands");
        }
    }
    ASSERT_EQ_INT(a->refused, 4 * 256);
    /* signed at the start: refused, saying when to sign again (the daemon
     * subscribes only then); signed after it: accepted, also from an id
     * whose old command was refused */
    int64_t open = auth_open_us(a);
    msg early = sign(key_a, "wgctl-5@h", 1, t1);
    ASSERT_EQ_INT(check(a, &early, t1), WG_EAUTH);
    ASSERT_CONTAINS(WHY, "sign it again in 1.000 s");
    msg now = sign(key_a, "wgctl-5@h", 1, open + 1);
    ASSERT_EQ_INT(check(a, &now, open + 1), WG_OK);
    msg web = sign(key_a, "wgweb-4@h", 8, open + 2);
    ASSERT_EQ_INT(check(a, &web, open + 2), WG_OK);
    ASSERT_EQ_INT(check(a, &cap[3], open + 3), WG_EAUTH); /* tracked again: its counter */
    ASSERT_CONTAINS(WHY, "seq 7 is not above 8");
    /* a client whose clock lags 3 s is refused until its clock passes the
     * opening, and told so */
    msg lag = sign(key_a, "wgctl-6@h", 1, open + SEC - 3 * SEC);
    ASSERT_EQ_INT(check(a, &lag, open + SEC), WG_EAUTH);
    ASSERT_CONTAINS(WHY, "this host's clock lags the daemon's");
    lag = sign(key_a, "wgctl-6@h", 1, open + 4 * SEC - 3 * SEC);
    ASSERT_EQ_INT(check(a, &lag, open + 4 * SEC), WG_OK);
    auth_fini(a);
    free(a);
    unlink(path);
}

/* Another key starts afresh: a command signed with it before the switch
 * (refused then, and captured) is refused after it too. The same key
 * re-read keeps every counter and opens at once. */
static void test_key_change(void)
{
    new_keys();
    const char *pa = key_file("key", key_a), *pb = key_file("key_b", key_b);
    char why[300];
    auth *a = start(pa, T0);
    int64_t t = T0 + 5 * SEC;
    msg m = sign(key_a, "x", 5, t);
    ASSERT_EQ_INT(check(a, &m, t), WG_OK);
    ASSERT_EQ_INT(auth_load(a, pa, t + SEC, why, sizeof why), WG_OK); /* SIGHUP, same key */
    ASSERT_EQ_INT(check(a, &m, t + SEC), WG_EAUTH);
    ASSERT_CONTAINS(WHY, "replayed or reordered");
    msg y = sign(key_a, "y", 1, t + SEC);
    ASSERT_EQ_INT(check(a, &y, t + SEC), WG_OK);
    msg early = sign(key_b, "z", 1, t + 2 * SEC); /* the client switched first */
    ASSERT_EQ_INT(check(a, &early, t + 2 * SEC), WG_EAUTH);
    ASSERT_CONTAINS(WHY, "bad signature");
    ASSERT_EQ_INT(auth_load(a, pb, t + 3 * SEC, why, sizeof why), WG_OK);
    ASSERT_EQ_INT(check(a, &early, t + 5 * SEC), WG_EAUTH);
    ASSERT_CONTAINS(WHY, "before this daemon started taking signed commands");
    msg z = sign(key_b, "z", 2, t + 5 * SEC);
    ASSERT_EQ_INT(check(a, &z, t + 5 * SEC), WG_OK);
    auth_fini(a);
    free(a);
    unlink(pa);
    unlink(pb);
}

/* A loop of one-shot clients (every wgctl process an id of its own): three
 * times as many ids within 1.6 s as are tracked, all accepted; every one
 * replayed after is refused, tracked or not; an id silent for the window is
 * let go (a reused pid counts from 1 again); "" is an id like any other. */
static void test_many_clients(void)
{
    new_keys();
    const char *path = key_file("key", key_a);
    auth *a = start(path, T0);
    enum { N = 3 * AUTH_CLIENTS };
    msg *m = calloc(N, sizeof *m);
    int64_t t = T0 + 2 * SEC, dt = 500; /* one command each 0.5 ms */
    for (int i = 0; i < N; i++) {
        char id[32];
        snprintf(id, sizeof id, "wgctl-%d@h", 1000 + i);
        m[i] = sign(key_a, id, 1, t + i * dt);
        ASSERT_EQ_INT(check(a, &m[i], t + i * dt + 100), WG_OK);
    }
    int64_t end = t + N * dt + SEC;
    int tracked = 0, untracked = 0;
    for (int i = 0; i < N; i++) {
        ASSERT_EQ_INT(check(a, &m[i], end), WG_EAUTH);
        tracked += strstr(WHY, "replayed or reordered") != NULL;
        untracked += strstr(WHY, "stopped tracking to make room") != NULL;
    }
    printf("replays refused: %d by their counters, %d by the floor\n", tracked, untracked);
    ASSERT_EQ_INT(tracked, AUTH_CLIENTS);
    ASSERT_EQ_INT(untracked, N - AUTH_CLIENTS);
    msg next = sign(key_a, "wgctl-9999@h", 1, end); /* a new one, clock agreeing */
    ASSERT_EQ_INT(check(a, &next, end), WG_OK);
    msg reuse = sign(key_a, m[N - 1].client, 1, end + 31 * SEC);
    ASSERT_EQ_INT(check(a, &reuse, end + 31 * SEC), WG_OK);
    msg anon = sign(key_a, "", 1, end + 31 * SEC);
    ASSERT_EQ_INT(check(a, &anon, end + 31 * SEC), WG_OK);
    ASSERT_EQ_INT(check(a, &anon, end + 31 * SEC + 1), WG_EAUTH);
    ASSERT_CONTAINS(WHY, "replayed or reordered");
    free(m);
    auth_fini(a);
    free(a);
    unlink(path);
}

/* One id's ticks and commands count apart, and a tick's refusal says
 * "tick": a rig may tick from 1 after sending commands, and reads why. */
static void test_tick_counters(void)
{
    new_keys();
    const char *path = key_file("key", key_a);
    auth *a = start(path, T0);
    int64_t t = T0 + 2 * SEC;
    msg c5 = sign(key_a, "rig-1@h", 5, t);
    ASSERT_EQ_INT(check(a, &c5, t), WG_OK);
    msg k1 = sign_tick(key_a, "rig-1@h", 1, t);
    ASSERT_EQ_INT(check(a, &k1, t), WG_OK);
    ASSERT_EQ_INT(check(a, &k1, t + 1), WG_EAUTH);
    ASSERT_CONTAINS(WHY, "replayed or reordered tick: seq 1 is not above 1");
    msg c2 = sign(key_a, "rig-1@h", 2, t);
    ASSERT_EQ_INT(check(a, &c2, t), WG_EAUTH);
    ASSERT_CONTAINS(WHY, "replayed or reordered command: seq 2 is not above 5");
    msg u = sign_tick(NULL, "rig-1@h", 2, t);
    ASSERT_EQ_INT(check(a, &u, t), WG_EAUTH);
    ASSERT_CONTAINS(WHY, "unsigned tick: this daemon accepts signed ticks only");
    msg other = sign_tick(key_b, "rig-1@h", 2, t);
    ASSERT_EQ_INT(check(a, &other, t), WG_EAUTH);
    ASSERT_CONTAINS(WHY, "bad signature");
    msg stale = sign_tick(key_a, "rig-1@h", 3, t - 40 * SEC);
    ASSERT_EQ_INT(check(a, &stale, t), WG_EAUTH);
    ASSERT_CONTAINS(WHY, "stale tick");
    msg early = sign_tick(key_a, "rig-2@h", 1, T0 + SEC / 2);
    ASSERT_EQ_INT(check(a, &early, t), WG_EAUTH);
    ASSERT_CONTAINS(WHY, "before this daemon started taking signed commands");
    msg k2 = sign_tick(key_a, "rig-1@h", 2, t);
    ASSERT_EQ_INT(check(a, &k2, t), WG_OK);
    ASSERT_EQ_INT(a->refused, 6);
    auth_fini(a);
    free(a);
    unlink(path);
}

TEST_MAIN(TEST(test_signed_commands), TEST(test_signed_ticks), TEST(test_replay_after_restart),
          TEST(test_key_change), TEST(test_many_clients), TEST(test_tick_counters))

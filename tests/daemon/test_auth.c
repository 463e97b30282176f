/* test_auth.c - signed commands (issue 10): with a key, a command signed
 * with it is accepted; unsigned, signed with another key, stale or replayed
 * commands get EAUTH and change nothing; key files are checked. */
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

static void test_signed_commands(void)
{
    ASSERT_TRUE(sodium_init() >= 0);
    crypto_auth_keygen(key_a);
    crypto_auth_keygen(key_b);
    char path[300];
    snprintf(path, sizeof path, "%s/key", fx_statedir());
    write_key(path, key_a, 0600);
    wgd *d = setup(128);
    char why[300];
    ASSERT_EQ_INT(auth_load(&d->auth, path, why, sizeof why), WG_OK);
    double om = d->sim.p.v[WG_P_OMEGA];
    send_set(d, key_a, 10, 0, 1.1); /* signed with the key: applied */
    ASSERT_STR(F.code, "OK");
    ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], 1.1, 0);
    om = 1.1;
    struct { const unsigned char *key; int64_t seq; double skew; const char *says; } bad[] = {
        {NULL, 11, 0, "unsigned command"},      {key_b, 12, 0, "bad signature"},
        {key_a, 13, 60, "stale command"},       {key_a, 14, -45, "stale command"},
        {key_a, 10, 0, "replayed or reordered"}, {key_a, 9, 0, "replayed or reordered"}};
    for (unsigned i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        send_set(d, bad[i].key, bad[i].seq, bad[i].skew, 1.3);
        ASSERT_STR(F.code, "EAUTH");
        ASSERT_CONTAINS(F.message, bad[i].says);
        ASSERT_NEAR(d->sim.p.v[WG_P_OMEGA], om, 0); /* nothing changed */
    }
    send_set(d, key_a, 15, 0, 1.2); /* the next seq: accepted */
    ASSERT_STR(F.code, "OK");
    ASSERT_EQ_INT(d->auth.refused, 6);
    /* key files: group-readable, not a key, missing; the old key stays */
    write_key(path, key_b, 0644);
    ASSERT_EQ_INT(auth_load(&d->auth, path, why, sizeof why), WG_EIO);
    ASSERT_CONTAINS(why, "chmod 600");
    FILE *f = fopen(path, "w");
    fprintf(f, "not a key\n");
    fclose(f);
    chmod(path, 0600);
    ASSERT_EQ_INT(auth_load(&d->auth, path, why, sizeof why), WG_EINVAL);
    ASSERT_CONTAINS(why, "64 hexadecimal digits");
    ASSERT_EQ_INT(auth_load(&d->auth, "/nonexistent/key", why, sizeof why), WG_EIO);
    ASSERT_TRUE(d->auth.on);
    send_set(d, key_a, 16, 0, 1.25);
    ASSERT_STR(F.code, "OK");
    ASSERT_EQ_INT(auth_load(&d->auth, "", why, sizeof why), WG_OK); /* off: unsigned again */
    send_set(d, NULL, 17, 0, 1.15);
    ASSERT_STR(F.code, "OK");
    unlink(path);
    teardown(d);
}

TEST_MAIN(TEST(test_signed_commands))

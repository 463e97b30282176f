/* test_conf.c - the configuration key table in-process: a reload applies
 * live keys (calling their apply hooks) and keeps restart-only ones, named;
 * the mode command's number check uses the table's range and wording; what
 * a config file may be (a regular file within the limit, read without
 * blocking) and hold (no NUL byte, each key once, lines that fit). */
#include "conf.h"
#include "wormgear/wg_sim.h"

#include <signal.h>
#include <sys/stat.h>
#include <unistd.h>

static char cfgpath[] = "/tmp/wgd-conf-XXXXXX";

/* Each test removes the config file it wrote. */
#define TEST_TEARDOWN_CHECK() ASSERT_TRUE(access(cfgpath, F_OK) != 0)
#include "test.h"

typedef struct calls {
    int mode, tick, verbose, was_mode, now_tick;
    conf *run;
} calls;

static void on_mode(void *ctx, const conf *was)
{
    calls *k = ctx;
    k->mode++;
    k->was_mode = was->mode;
}

static void on_tick(void *ctx, const conf *was)
{
    calls *k = ctx;
    (void)was;
    k->tick++;
    k->now_tick = k->run->tick_us; /* the new value is in place */
}

static void on_verbose(void *ctx, const conf *was)
{
    (void)was;
    ((calls *)ctx)->verbose++;
}

static const conf_apply_fn hooks[CONF_NAPPLY] = {
    [CONF_APPLY_MODE] = on_mode, [CONF_APPLY_TICK] = on_tick, [CONF_APPLY_VERBOSE] = on_verbose};

/* Live keys are copied and their hooks run; restart-only keys and the
 * [params] overrides keep their running values and are named. */
static void test_reload_live_and_restart(void)
{
    conf run, next, loaded;
    char kept[200], held[200];
    conf_defaults(&run);
    run.mode = MODE_LOCKSTEP;
    calls k = {.run = &run};
    next = run;
    next.mode = MODE_FAST, next.rate = 0.25, next.tick_us = 2000, next.verbose = 1;
    next.accept_commands = 0;
    snprintf(next.scene, sizeof next.scene, "lowfreq");
    next.steps_per_period = 256;
    next.nsets = 1;
    snprintf(next.sets[0], sizeof next.sets[0], "omega=1.1");
    loaded = run;
    conf_reload(&run, &loaded, &next, hooks, &k, kept, sizeof kept, held, sizeof held);
    ASSERT_EQ_INT(run.mode, MODE_FAST);
    ASSERT_NEAR(run.rate, 0.25, 0);
    ASSERT_EQ_INT(run.tick_us, 2000);
    ASSERT_EQ_INT(run.verbose, 1);
    ASSERT_EQ_INT(run.accept_commands, 0);
    ASSERT_STR(run.scene, "table3");
    ASSERT_EQ_INT(run.steps_per_period, 128);
    ASSERT_EQ_INT(run.nsets, 0);
    ASSERT_STR(kept, "scene, steps_per_period and [params]");
    ASSERT_EQ_INT(k.mode, 1);
    ASSERT_EQ_INT(k.was_mode, MODE_LOCKSTEP);
    ASSERT_EQ_INT(k.tick, 1);
    ASSERT_EQ_INT(k.now_tick, 2000);
    ASSERT_EQ_INT(k.verbose, 1);
    /* nothing changed: no hook, nothing named */
    k = (calls){.run = &run};
    next = run;
    loaded = run;
    conf_reload(&run, &loaded, &next, hooks, &k, kept, sizeof kept, held, sizeof held);
    ASSERT_STR(kept, "");
    ASSERT_EQ_INT(k.mode + k.tick + k.verbose, 0);
    /* a changed [params] value (same count) is named too */
    snprintf(next.sets[0], sizeof next.sets[0], "omega=1.2");
    next.nsets = 1;
    run.nsets = 1;
    snprintf(run.sets[0], sizeof run.sets[0], "omega=1.1");
    loaded = run;
    conf_reload(&run, &loaded, &next, hooks, &k, kept, sizeof kept, held, sizeof held);
    ASSERT_STR(kept, "[params]");
    ASSERT_STR(run.sets[0], "omega=1.1");
}

/* Every restart-only key changed: the message names them all, in table
 * order (as the reload warning always listed them). */
static void test_reload_names_every_restart_key(void)
{
    conf run, next, loaded;
    char kept[200], held[200];
    conf_defaults(&run);
    next = run;
    snprintf(next.scene, sizeof next.scene, "lowfreq");
    snprintf(next.url, sizeof next.url, "memq://");
    snprintf(next.prefix, sizeof next.prefix, "X_");
    next.steps_per_period = 64, next.stepper = WG_STEPPER_RK4, next.mlock = 1, next.nsets = 1;
    snprintf(next.sets[0], sizeof next.sets[0], "omega=1.1");
    calls k = {.run = &run};
    loaded = run;
    conf_reload(&run, &loaded, &next, hooks, &k, kept, sizeof kept, held, sizeof held);
    ASSERT_STR(kept, "scene, url, prefix, steps_per_period, stepper, mlock and [params]");
    ASSERT_EQ_INT(k.mode + k.tick + k.verbose, 0);
    ASSERT_STR(run.url, "udpm://239.255.76.67:7667?ttl=0");
    ASSERT_STR(run.prefix, "WORMGEAR_");
}

/* A reload applies what the configuration changed since the last load; a
 * value a command set (mode fast, contacts mesh) stays where the file left
 * that key alone, and is named (a SIGHUP with the file untouched put the
 * daemon back to realtime 1 and said nothing). */
static void test_reload_keeps_commands(void)
{
    conf run, next, loaded;
    char kept[200], held[200];
    conf_defaults(&run);
    loaded = run;
    run.mode = MODE_FAST, run.rate = 0.01, run.contacts = 1; /* by commands */
    calls k = {.run = &run};
    next = loaded; /* the file as it was */
    conf_reload(&run, &loaded, &next, hooks, &k, kept, sizeof kept, held, sizeof held);
    ASSERT_EQ_INT(run.mode, MODE_FAST);
    ASSERT_NEAR(run.rate, 0.01, 0);
    ASSERT_EQ_INT(run.contacts, 1);
    ASSERT_STR(held, "mode, rate and contacts");
    ASSERT_STR(kept, "");
    ASSERT_EQ_INT(k.mode, 0);
    /* the file changes the rate: that is applied, the mode stays the command's */
    next.rate = 0.5;
    conf_reload(&run, &loaded, &next, hooks, &k, kept, sizeof kept, held, sizeof held);
    ASSERT_EQ_INT(run.mode, MODE_FAST);
    ASSERT_NEAR(run.rate, 0.5, 0);
    ASSERT_STR(held, "mode and contacts");
    /* and then the mode: applied, its hook run */
    next.mode = MODE_LOCKSTEP;
    conf_reload(&run, &loaded, &next, hooks, &k, kept, sizeof kept, held, sizeof held);
    ASSERT_EQ_INT(run.mode, MODE_LOCKSTEP);
    ASSERT_EQ_INT(k.mode, 1);
    ASSERT_STR(held, "contacts");
}

static void write_conf(const char *text)
{
    FILE *f = fopen(cfgpath, "w");
    ASSERT_TRUE(f != NULL);
    if (f) {
        fputs(text, f);
        fclose(f);
    }
}

static void write_bytes(const char *text, size_t n)
{
    FILE *f = fopen(cfgpath, "w");
    ASSERT_TRUE(f != NULL);
    if (f) {
        ASSERT_EQ_INT(fwrite(text, 1, n, f), n);
        fclose(f);
    }
}

/* conf_read_file of text: its return code, the message in why. */
static int read_text(const char *text, size_t n, char *why, size_t len)
{
    conf c;
    conf_defaults(&c);
    write_bytes(text, n);
    int rc = conf_read_file(&c, cfgpath, why, len);
    unlink(cfgpath);
    return rc;
}
#define READ_STR(text, why) read_text(text, strlen(text), why, sizeof why)

/* Only a regular file within the limit is read; a FIFO or a device is
 * never opened (the FIFO blocked the daemon in open() for good: the alarm
 * ends the test if it does again; /dev/zero was read forever). */
static void test_file_kinds(void)
{
    char why[400], a0[] = "wormgeard", a1[] = "-c", a2[sizeof cfgpath];
    conf c;
    conf_defaults(&c);
    ASSERT_EQ_INT(mkfifo(cfgpath, 0600), 0);
    alarm(10);
    ASSERT_EQ_INT(conf_read_file(&c, cfgpath, why, sizeof why), 2);
    ASSERT_CONTAINS(why, "is a FIFO, not a regular file");
    memcpy(a2, cfgpath, sizeof cfgpath); /* the SIGHUP path (conf_load) alike */
    char *argv[] = {a0, a1, a2, NULL};
    ASSERT_EQ_INT(conf_load(&c, 3, argv, why, sizeof why), 2);
    ASSERT_CONTAINS(why, "is a FIFO, not a regular file");
    unlink(cfgpath);
    ASSERT_EQ_INT(conf_read_file(&c, "/dev/zero", why, sizeof why), 2);
    ASSERT_STR(why, "config file /dev/zero is a character device, not a regular file");
    alarm(0);
    ASSERT_EQ_INT(conf_read_file(&c, "/tmp", why, sizeof why), 2);
    ASSERT_CONTAINS(why, "is a directory");
    ASSERT_EQ_INT(conf_read_file(&c, "/nonexistent/wg.conf", why, sizeof why), 2);
    ASSERT_CONTAINS(why, "No such file");
    /* the size limit: one byte over is refused, saying the limit */
    char *big = malloc(CONF_FILE_MAX + 1);
    ASSERT_TRUE(big != NULL);
    if (!big)
        return;
    memset(big, '#', CONF_FILE_MAX + 1);
    for (size_t i = 100; i <= CONF_FILE_MAX; i += 101)
        big[i] = '\n'; /* comment lines that fit the parser */
    ASSERT_EQ_INT(read_text(big, CONF_FILE_MAX + 1, why, sizeof why), 2);
    ASSERT_CONTAINS(why, "is 1048577 bytes (limit 1048576)");
    big[CONF_FILE_MAX - 1] = '\n';
    ASSERT_EQ_INT(read_text(big, CONF_FILE_MAX, why, sizeof why), 0); /* at the limit: read */
    free(big);
}

/* A NUL byte ended the line for the parser, which took the rest silently
 * (rate 1 kept, or "rate = 2" read from "rate = 2\0garbage"): refused,
 * at its line and column. */
static void test_nul_bytes(void)
{
    char why[400];
    static const char a[] = "[wormgeard]\n\0rate = 5000\n", b[] = "[wormgeard]\nrate = 2\0x\n";
    ASSERT_EQ_INT(read_text(a, sizeof a - 1, why, sizeof why), 2);
    ASSERT_CONTAINS(why, ":2: a NUL byte (column 1)");
    ASSERT_EQ_INT(read_text(b, sizeof b - 1, why, sizeof why), 2);
    ASSERT_CONTAINS(why, ":2: a NUL byte (column 9)");
}

/* Text quoted from the file in a refusal has no control byte (it set the
 * terminal's title, cleared the screen and reached the journal). */
static void test_refusal_text_clean(void)
{
    char why[400];
    ASSERT_EQ_INT(READ_STR("mode = \x1b[2J\x1b]0;t\x07\xc2\x9b" "31mfast\n", why), 2);
    ASSERT_CONTAINS(why, "mode: '?[2J?]0;t???31mfast' is not one of realtime, fast, lockstep");
    for (const char *p = why; *p; p++)
        ASSERT_TRUE((unsigned char)*p >= 0x20 && *p != 0x7f);
}

/* A key set twice took the last value silently: refused at the second,
 * naming the first (top level and [wormgeard] are one section). An
 * indented line continued the value above it (inih's multi-line values):
 * refused as such, not as a duplicate. */
static void test_keys_once(void)
{
    char why[400];
    ASSERT_EQ_INT(READ_STR("[wormgeard]\nrate = 2\nmode = fast\nrate = 3\n", why), 2);
    ASSERT_CONTAINS(why, ":4: rate: set again (first set at line 2)");
    ASSERT_EQ_INT(READ_STR("rate = 2\n[wormgeard]\nrate = 2\n", why), 2);
    ASSERT_CONTAINS(why, ":3: rate: set again (first set at line 1)");
    ASSERT_EQ_INT(READ_STR("[params]\nomega = 1.1\n\n[params]\nomega = 1.2\n", why), 2);
    ASSERT_CONTAINS(why, ":5: omega: set again (first set at line 2)");
    ASSERT_EQ_INT(READ_STR("[wormgeard]\nrate = 2\n  5\n", why), 2);
    ASSERT_CONTAINS(why, ":3: an indented line continues the value of rate");
    /* an indented first key of a section is a key, a comment line is no value */
    ASSERT_EQ_INT(READ_STR("[wormgeard]\n  rate = 2\n  # note\nmode = fast\n[params]\n"
                           "  omega = 1.1\n", why), 0);
}

/* A line longer than the parser's buffer was cut into pieces, the error
 * reported at a later line ("bad.conf:3: syntax error" for line 2): now at
 * its own line, with the limit. */
static void test_long_line(void)
{
    char text[6000], why[400];
    int n = snprintf(text, sizeof text, "[wormgeard]\n# ");
    memset(text + n, 'x', 5000);
    snprintf(text + n + 5000, sizeof text - (size_t)n - 5000, "\nrate = 2\n");
    ASSERT_EQ_INT(READ_STR(text, why), 2);
    ASSERT_CONTAINS(why, ":2: line too long: 5002 characters, the limit is 198");
    /* the limit exactly: 198 characters read, 199 refused (with a newline or without) */
    memset(text, '#', 199);
    memcpy(text + 199, "\nrate = 2\n", 11);
    ASSERT_EQ_INT(READ_STR(text, why), 2);
    ASSERT_CONTAINS(why, ":1: line too long: 199 characters");
    ASSERT_EQ_INT(READ_STR(text + 1, why), 0);
    text[199] = 0;
    ASSERT_EQ_INT(READ_STR(text, why), 2);
    ASSERT_EQ_INT(READ_STR(text + 1, why), 0);
}

/* The SIGHUP path: load the file again, reload into the running one. */
static void test_reload_from_file(void)
{
    char a0[] = "wormgeard", a1[] = "-c", a2[sizeof cfgpath], why[400], kept[200], held[200];
    memcpy(a2, cfgpath, sizeof cfgpath);
    char *argv[] = {a0, a1, a2, NULL};
    conf run, next, loaded;
    write_conf("[wormgeard]\nmode = lockstep\nrate = 0.5\n[params]\nomega = 1.0\n");
    ASSERT_EQ_INT(conf_load(&run, 3, argv, why, sizeof why), 0);
    write_conf("[wormgeard]\nmode = fast\nscene = lowfreq\n[params]\nomega = 1.1\n");
    ASSERT_EQ_INT(conf_load(&next, 3, argv, why, sizeof why), 0);
    calls k = {.run = &run};
    loaded = run;
    conf_reload(&run, &loaded, &next, hooks, &k, kept, sizeof kept, held, sizeof held);
    ASSERT_STR(kept, "scene and [params]");
    ASSERT_EQ_INT(run.mode, MODE_FAST);
    ASSERT_NEAR(run.rate, 1, 0); /* no longer in the file: the default */
    ASSERT_STR(run.path, cfgpath);
    ASSERT_STR(run.sets[0], "omega=1"); /* the value read, in its shortest text */
    ASSERT_EQ_INT(k.mode, 1);
    unlink(cfgpath);
}

/* A number from a command is checked against the table without a trip
 * through text, with the words conf_set uses for the same value. */
static void test_check_number(void)
{
    char why[200], why_text[200];
    conf c;
    conf_defaults(&c);
    ASSERT_EQ_INT(conf_check_number("rate", 0.5, why, sizeof why), 0);
    ASSERT_EQ_INT(conf_check_number("rate", 1000, why, sizeof why), 0);
    ASSERT_EQ_INT(conf_check_number("rate", 1e9, why, sizeof why), 2);
    ASSERT_STR(why, "rate: '1000000000' must be a number in [1e-06, 1000]");
    ASSERT_EQ_INT(conf_set(&c, "rate", "1000000000", why_text, sizeof why_text), 2);
    ASSERT_STR(why, why_text);
    ASSERT_EQ_INT(conf_check_number("rate", NAN, why, sizeof why), 2);
    ASSERT_STR(why, "rate: 'nan' must be a number in [1e-06, 1000]");
    ASSERT_EQ_INT(conf_check_number("rate", INFINITY, why, sizeof why), 2);
    ASSERT_EQ_INT(conf_check_number("tick_us", 150.5, why, sizeof why), 2);
    ASSERT_CONTAINS(why, "an integer in [100, 100000]");
    ASSERT_EQ_INT(conf_check_number("scene", 1, why, sizeof why), 2);
    ASSERT_CONTAINS(why, "unknown");
    ASSERT_EQ_INT(conf_check_number("no_such_key", 1, why, sizeof why), 2);
    ASSERT_NEAR(c.rate, 1, 0); /* the failed conf_set changed nothing */
}

static int make_path(void)
{
    int fd = mkstemp(cfgpath);
    if (fd < 0)
        return -1;
    close(fd);
    return unlink(cfgpath); /* the name only: each test writes and removes it */
}
/* $WORMGEAR_PREFIX and $WORMGEAR_URL, as the clients read them: used
 * below the options; one the key would refuse is refused naming the
 * variable (before: the default kept, silently, so the daemon listened on
 * another prefix than the clients beside it). */
static void test_environment(void)
{
    char why[400], a0[] = "wormgeard", a1[] = "--prefix", a2[] = "OPT_";
    char *argv[] = {a0, NULL}, *argv2[] = {a0, a1, a2, NULL};
    conf c;
    setenv("WORMGEAR_PREFIX", "RIG2_", 1);
    setenv("WORMGEAR_URL", "memq://", 1);
    ASSERT_EQ_INT(conf_load(&c, 1, argv, why, sizeof why), 0);
    ASSERT_STR(c.prefix, "RIG2_");
    ASSERT_STR(c.url, "memq://");
    ASSERT_EQ_INT(conf_load(&c, 3, argv2, why, sizeof why), 0);
    ASSERT_STR(c.prefix, "OPT_");
    setenv("WORMGEAR_PREFIX", "bad prefix", 1);
    ASSERT_EQ_INT(conf_load(&c, 1, argv, why, sizeof why), 2);
    ASSERT_STR(why, "environment: $WORMGEAR_PREFIX: prefix: 'bad prefix' must match "
               "[A-Za-z0-9_.-]{0,40} (fix or unset it)");
    setenv("WORMGEAR_PREFIX", "", 1); /* no prefix: allowed */
    ASSERT_EQ_INT(conf_load(&c, 1, argv, why, sizeof why), 0);
    ASSERT_STR(c.prefix, "");
    unsetenv("WORMGEAR_PREFIX");
    unsetenv("WORMGEAR_URL");
    ASSERT_EQ_INT(conf_load(&c, 1, argv, why, sizeof why), 0);
    ASSERT_STR(c.prefix, "WORMGEAR_");
}

/* A file may set every parameter once (a cap of 32 overrides refused one
 * setting all 35), and a --set of one replaces the file's value, one entry. */
static void test_every_parameter_set(void)
{
    char text[4096] = "[params]\n", why[400];
    for (int i = 0; i < WG_NPARAM; i++) {
        wg_params p;
        wg_params_default(&p);
        size_t n = strlen(text);
        snprintf(text + n, sizeof text - n, "%s = %.17g\n", wg_param_info_get(i)->name, p.v[i]);
    }
    write_bytes(text, strlen(text));
    char a0[] = "wormgeard", a1[] = "-c", a3[] = "--set", a4[] = "omega=1.3";
    char *argv[] = {a0, a1, cfgpath, a3, a4, NULL};
    conf c;
    ASSERT_EQ_INT(conf_load(&c, 5, argv, why, sizeof why), 0);
    unlink(cfgpath);
    ASSERT_EQ_INT(c.nsets, WG_NPARAM);
    int omega = 0;
    for (int i = 0; i < c.nsets; i++)
        omega += !strncmp(c.sets[i], "omega=", 6);
    ASSERT_EQ_INT(omega, 1);
    ASSERT_STR(c.sets[0], "omega=1.3");
}

/* A --set value is kept as read, whatever its spelling (one of 160
 * characters was cut at 127 to another number). */
static void test_set_long_spelling(void)
{
    char why[400], a0[] = "wormgeard", a1[] = "--set", a2[200];
    snprintf(a2, sizeof a2, "omega=1e-%0150d1", 0); /* 0.1 */
    char *argv[] = {a0, a1, a2, NULL};
    conf c;
    ASSERT_EQ_INT(conf_load(&c, 3, argv, why, sizeof why), 0);
    ASSERT_EQ_INT(c.nsets, 1);
    ASSERT_STR(c.sets[0], "omega=0.1");
}

#define main tests_main
TEST_MAIN(TEST(test_reload_live_and_restart), TEST(test_reload_names_every_restart_key),
          TEST(test_reload_keeps_commands), TEST(test_reload_from_file), TEST(test_check_number),
          TEST(test_file_kinds), TEST(test_nul_bytes), TEST(test_refusal_text_clean),
          TEST(test_keys_once), TEST(test_long_line),
          TEST(test_environment), TEST(test_set_long_spelling), TEST(test_every_parameter_set))
#undef main

int main(int argc, char **argv)
{
    if (make_path()) {
        perror("mkstemp");
        return 1;
    }
    return tests_main(argc, argv);
}

/* Scenes: shipped files load; physical and dimensionless table3 agree;
 * every malformed line is reported as file:line with the allowed range. */
#include "test.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_sim.h"
#include "wormgear/wg_status.h"

#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

static char dir[64];

/* Write text to DIR/name and return the path (static buffer per call). */
static const char *scene_file(const char *name, const char *text)
{
    static char path[8][128];
    static int slot;
    char *p = path[slot++ % 8];
    snprintf(p, 128, "%s/%s", dir, name);
    FILE *f = fopen(p, "w");
    fputs(text, f);
    fclose(f);
    return p;
}

static void expect_error(const char *name, const char *text, int code, const char *where,
                         const char *what)
{
    wg_scene sc;
    char why[600], loc[200];
    const char *path = scene_file(name, text);
    int rc = wg_scene_load(&sc, path, why, sizeof why);
    ASSERT_EQ_INT(rc, code);
    snprintf(loc, sizeof loc, "%s%s", path, where);
    ASSERT_CONTAINS(why, loc);
    ASSERT_CONTAINS(why, what);
    printf("  %s\n", why);
}

static void test_shipped_scenes_load(void)
{
    const char *names[] = {"table3", "table3-physical", "lowfreq", "realistic", "torsional"};
    for (int i = 0; i < 5; i++) {
        wg_scene sc;
        char why[600];
        int rc = wg_scene_open(&sc, names[i], why, sizeof why);
        if (rc)
            fprintf(stderr, "%s\n", why);
        ASSERT_EQ_INT(rc, WG_OK);
        ASSERT_EQ_INT(wg_params_check(&sc.p, why, sizeof why), WG_OK);
    }
    wg_scene sc;
    char why[600];
    ASSERT_EQ_INT(wg_scene_open(&sc, "torsional", why, sizeof why), WG_OK);
    ASSERT_TRUE(wg_params_torsional(&sc.p));
    ASSERT_EQ_INT(wg_scene_open(&sc, "lowfreq", why, sizeof why), WG_OK);
    /* lowfreq: kappa = 4, zeta_b = 0.14 -> k = 4 mu, xi = 0.14 sqrt(k) */
    ASSERT_NEAR(sc.p.v[WG_P_K1X], 4 * sc.p.v[WG_P_MU1], 1e-4);
    ASSERT_NEAR(sc.p.v[WG_P_XI2Z], 0.14 * sqrt(sc.p.v[WG_P_K2Z]), 1e-5);
    ASSERT_EQ_INT(wg_scene_open(&sc, "no-such-scene", why, sizeof why), WG_EIO);
    ASSERT_CONTAINS(why, "scene 'no-such-scene' not found");
}

typedef struct xs {
    int n;
    double xn[64];
} xs;

static void grab(void *ctx, const wg_section *s)
{
    xs *x = ctx;
    if (x->n < 64)
        x->xn[x->n++] = s->out.xn;
}

static void test_physical_equals_dimensionless(void)
{
    wg_scene a, b;
    char why[600];
    ASSERT_EQ_INT(wg_scene_open(&a, "table3", why, sizeof why), WG_OK);
    ASSERT_EQ_INT(wg_scene_open(&b, "table3-physical", why, sizeof why), WG_OK);
    ASSERT_TRUE(b.physical && !a.physical);
    for (int i = 0; i < WG_NPARAM; i++) {
        double x = a.p.v[i], y = b.p.v[i];
        if (fabs(x - y) > 2e-4 * fmax(fabs(x), 1e-3))
            fprintf(stderr, "%s: %.8g vs %.8g\n", wg_param_info_get(i)->name, x, y);
        ASSERT_TRUE(fabs(x - y) <= 2e-4 * fmax(fabs(x), 1e-3));
    }
    /* derived scale reported (MODEL.md s3: omega_n = 31901 rad/s) */
    ASSERT_NEAR(b.scale.omega_n_rad_s, 31901, 1);
    ASSERT_NEAR(b.scale.me_kg, 1.965, 1e-3);
    /* same trajectory: Poincare x_n over 40 periods at omega = 0.5 */
    xs out[2] = {{0}, {0}};
    wg_scene *sc[2] = {&a, &b};
    for (int k = 0; k < 2; k++) {
        sc[k]->p.v[WG_P_OMEGA] = 0.5;
        wg_sim s;
        wg_sim_config cfg = {WG_MODEL_CONSISTENT, WG_STEPPER_RK4_EVENT, 256};
        ASSERT_EQ_INT(wg_sim_init(&s, &sc[k]->p, &cfg, why, sizeof why), WG_OK);
        wg_sink sink = {&out[k], NULL, grab, NULL};
        ASSERT_EQ_INT(wg_sim_run(&s, 256 * 40, &sink, NULL), WG_OK);
        wg_sim_fini(&s);
    }
    ASSERT_EQ_INT(out[0].n, 40);
    double worst = 0;
    for (int i = 0; i < 40; i++)
        worst = fmax(worst, fabs(out[0].xn[i] - out[1].xn[i]));
    printf("  physical vs dimensionless table3: max |dx_n| over 40 sections %.2e\n", worst);
    ASSERT_TRUE(worst < 1e-3);
}

static void test_malformed_lines(void)
{
    expect_error("range.ini", "[scene]\nname = r\n[params]\nomega = 1\nxi_p = 5\n", WG_ERANGE,
                 ":5:", "xi_p: value 5 out of range [0, 2]");
    expect_error("nan.ini", "[params]\n\nomega = fast\n", WG_EINVAL, ":3:",
                 "omega: 'fast' is not a number (allowed [0.01, 10])");
    /* a '#' after a value is no comment to inih (';' is): refused, saying so, for
     * numbers and words alike; the scene's name and description are free text */
    expect_error("hash.ini", "[params]\nomega = 1.2 # note\n", WG_EINVAL, ":2:",
                 "omega: '1.2 # note': a comment after a value starts with ';', not '#' (a "
                 "value may not hold ' #')");
    expect_error("hash2.ini", "[scene]\nmodel = printed\t# the paper's\n", WG_EINVAL, ":2:",
                 "model: 'printed\t# the paper's': a comment after a value starts with ';'");
    {
        wg_scene sc;
        char why[600];
        const char *p = scene_file("hash3.ini", "[scene]\nname = g #2\ndescription = gear #2 ; "
                                                "a note\n[params]\nomega = 1.2 ; ok\n");
        ASSERT_EQ_INT(wg_scene_load(&sc, p, why, sizeof why), WG_OK);
        ASSERT_STR(sc.name, "g #2");
        ASSERT_STR(sc.description, "gear #2");
        ASSERT_NEAR(sc.p.v[WG_P_OMEGA], 1.2, 0);
    }
    expect_error("long.ini", "[params]\nomega = 1234567890123456789012345678901234567890x\n",
                 WG_EINVAL, ":2:", "omega: '1234567890123456789012345678901234567...' is not");
    /* the cut backs off a UTF-8 character it would split (byte 37 is inside the e-acute) */
    expect_error("utf8.ini",
                 "[params]\nomega = 123456789012345678901234567890123456\xc3\xa9xxxxx\n",
                 WG_EINVAL, ":2:", "omega: '123456789012345678901234567890123456...' is not");
    expect_error("inf.ini", "[params]\nomega = inf\n", WG_EINVAL, ":2:", "not a number");
    expect_error("key.ini", "[params]\nomega = 1\nfoo = 1\n", WG_EUNKNOWN, ":3:",
                 "[params] foo: unknown parameter (wgsim --help lists them)");
    expect_error("sect.ini", "[params]\nomega = 1\n[nope]\nx = 1\n", WG_EUNKNOWN, ":4:",
                 "[nope]: unknown section");
    expect_error("syntax.ini", "[params]\nomega = 1\nthis line has no equals sign\n", WG_EINVAL,
                 ":3:", "syntax error");
    expect_error("model.ini", "[scene]\nmodel = fancy\n", WG_EINVAL, ":2:",
                 "'fancy' is not one of [consistent, printed]");
    expect_error("phys.ini", "[physical]\nbacklash_um = -5\n", WG_ERANGE, ":2:",
                 "backlash_um: value -5 out of range [0, 10000] um");
    expect_error("cos.ini", "[params]\na1 = 0.5\n", WG_ERANGE, ":2:", "a1^2 + a2^2 + a3^2");
    expect_error("init.ini", "[initial]\nstate = wobbly\n", WG_EINVAL, ":2:",
                 "not one of [equilibrium, given]");
    /* rigid_bearings is 0 or 1 (0.5 loaded as rigid); [scale] beside [physical] was
     * overwritten without a word; text quoted from the file has no control byte */
    expect_error("rigid.ini", "[physical]\nrigid_bearings = 0.5\n", WG_ERANGE, ":2:",
                 "[physical] rigid_bearings = 0.5: 0 (the bearings' stiffness and clearance) "
                 "or 1 (rigid: the torsional model), nothing between");
    expect_error("both.ini",
                 "[physical]\nwheel_radius_mm = 74\nworm_mass_kg = 0.716\n"
                 "worm_inertia_kgm2 = 1.733e-4\nwheel_mass_kg = 4.86\n"
                 "wheel_inertia_kgm2 = 1.331e-2\nmesh_stiffness_N_m = 2e9\n"
                 "[scale]\nlength_m = 0.5\n",
                 WG_EINVAL, ":9:", "[scale] in a scene with [physical]: its scale comes from");
    expect_error("esc.ini", "[scene]\nmodel = \x1b]0;pwned\x07\x1b[2J\xc2\x9b" "1m\n", WG_EINVAL,
                 ":2:", "model: '?]0;pwned??[2J??1m' is not one of");
    /* a physical scene missing a mass names the key */
    expect_error("need.ini", "[physical]\nwheel_radius_mm = 74\n", WG_EINVAL, ":",
                 "[physical] needs worm_mass_kg");
    /* derived value out of range: says where it came from */
    expect_error("derived.ini",
                 "[physical]\nwheel_radius_mm = 74\nworm_mass_kg = 0.716\n"
                 "worm_inertia_kgm2 = 1.733e-4\nwheel_mass_kg = 4.86\n"
                 "wheel_inertia_kgm2 = 1.331e-2\nmesh_stiffness_N_m = 2e9\n"
                 "bearing_stiffness_N_m = 1e14\n",
                 WG_ERANGE, ":8:", "bearing_stiffness_N_m gives k1x = ");
    /* a given initial state is used */
    wg_scene sc;
    char why[600];
    const char *p = scene_file("given.ini", "[initial]\nstate = given\nx1 = 0.5\ny1 = 0\nz1 = 0\n"
                                            "x2 = 0\ny2 = 0\nz2 = 0\ns = 1.5\ndx1 = 0\ndy1 = 0\n"
                                            "dz1 = 0\ndx2 = 0\ndy2 = 0\ndz2 = 0\nds = -0.25\n");
    ASSERT_EQ_INT(wg_scene_load(&sc, p, why, sizeof why), WG_OK);
    double y[16];
    wg_scene_initial(&sc, y);
    ASSERT_NEAR(y[0], 0.5, 0);
    ASSERT_NEAR(y[13], -0.25, 0);
    ASSERT_NEAR(y[6], 1.5, 0);
    ASSERT_NEAR(y[1], 0.0, 0);
}

/* What the loader took silently before: a key given twice (the later value
 * won), an indented line (libinih continues the value before it), a file
 * with no settings (the defaults ran), state = given with values missing
 * (they started at 0), and state values the start ignores. */
static void test_silent_no_more(void)
{
    expect_error("dup.ini", "[params]\nomega = 1\nxi_p = 0.1\nomega = 0.5\n", WG_EINVAL, ":4:",
                 "[params] omega: given twice (first at line 2)");
    expect_error("dup2.ini", "[params]\nomega = 1\n[scene]\nname = a\n[params]\nomega = 2\n",
                 WG_EINVAL, ":6:", "[params] omega: given twice (first at line 2)");
    expect_error("dup3.ini", "[scene]\nname = a\n\nname = b\n", WG_EINVAL, ":4:",
                 "[scene] name: given twice (first at line 2)");
    expect_error("dup4.ini", "[physical]\nbacklash_um = 5\nbacklash_um = 5\n", WG_EINVAL, ":3:",
                 "[physical] backlash_um: given twice (first at line 2)");
    expect_error("dup5.ini", "[initial]\nstate = equilibrium\nstate = given\n", WG_EINVAL, ":3:",
                 "[initial] state: given twice (first at line 2)");
    expect_error("dup6.ini", "[params]\nomega = 1\n[params]\n  omega = 2\n", WG_EINVAL, ":4:",
                 "[params] omega: given twice (first at line 2)");
    expect_error("cont.ini", "[params]\nomega = 1\n  0.5\n", WG_EINVAL, ":3:",
                 "[params] omega: this indented line would continue the value of line 2");
    /* an indented header after a key is that value's continuation to inih:
     * said so (before: "[scene] name: given twice", a new user's trial) */
    expect_error("cont2.ini", "[scene]\nname = x\n  [params]\nomega = 0.5\n", WG_EINVAL, ":3:",
                 "[scene] name: this indented line would continue the value of line 2; a value "
                 "is one line (remove the indent)");
    /* a line longer than inih's buffer, and NUL bytes: refused at their
     * line (a long comment carried a key, omega = 2.5, and a NUL cut a value
     * or hid a line; a hostile-input review) */
    char longc[400];
    snprintf(longc, sizeof longc, "[params]\n; a comment %0187dxomega = 2.5\nxi_p = 0.1\n", 0);
    expect_error("long.ini", longc, WG_EINVAL, ":2:", "line too long: 211 characters, the "
                 "limit is 198");
    static const char nul1[] = "[params]\nomega = 1.2\0garbage\n",
                      nul2[] = "[params]\n\0omega = 99\n";
    const char *bins[2] = {nul1, nul2};
    size_t lens[2] = {sizeof nul1 - 1, sizeof nul2 - 1};
    for (int i = 0; i < 2; i++) {
        wg_scene sc;
        char why[600], path[128];
        snprintf(path, sizeof path, "%s/nul%d.ini", dir, i);
        FILE *f = fopen(path, "wb");
        ASSERT_TRUE(f && fwrite(bins[i], 1, lens[i], f) == lens[i]);
        if (f)
            fclose(f);
        ASSERT_EQ_INT(wg_scene_load(&sc, path, why, sizeof why), WG_EINVAL);
        ASSERT_CONTAINS(why, i ? ":2: a NUL byte (column 1)" : ":2: a NUL byte (column 12)");
    }
    { /* a path longer than the loader keeps: refused (cut, it named another file) */
        wg_scene sc;
        char why[600], longp[700];
        snprintf(longp, sizeof longp, "%s/%0600d.ini", dir, 0);
        ASSERT_EQ_INT(wg_scene_open(&sc, longp, why, sizeof why), WG_EINVAL);
        ASSERT_CONTAINS(why, "scene file path of ");
        ASSERT_CONTAINS(why, "the limit is 511");
    }
    /* name and description are shown on terminals and written into files:
     * no control bytes (an escape sequence in a name reached the terminal,
     * a \x01 broke the SVG and the JSON), and never cut (a review) */
    expect_error("name1.ini", "[scene]\nname = a\033]0;pwned\007\n", WG_EINVAL, ":2:",
                 "[scene] name: 1 to 63 printable ASCII characters (a snapshot stores it); a "
                 "control or non-ASCII byte at column 2");
    char longn[120];
    snprintf(longn, sizeof longn, "[scene]\nname = %070d\n", 0);
    expect_error("name2.ini", longn, WG_EINVAL, ":2:", "; 70 given");
    expect_error("desc1.ini", "[scene]\ndescription = x\001y\n", WG_EINVAL, ":2:",
                 "[scene] description: at most 159 bytes, no control characters; a control "
                 "byte at column 2");
    expect_error("empty.ini", "", WG_EINVAL, ": ", "no settings");
    expect_error("nokeys.ini", "; a comment\n[params]\n\n[scene]\n", WG_EINVAL, ": ",
                 "no settings");
    expect_error("given1.ini", "[initial]\nstate = given\nx1 = 0.5\n", WG_EINVAL, ":2:",
                 "state = given needs all 14 state values of the consistent model; missing: y1, "
                 "z1, x2, y2, z2, s, dx1, dy1, dz1, dx2, dy2, dz2, ds");
    expect_error("given2.ini",
                 "[initial]\nstate = given\nx1 = 0\ny1 = 0\nz1 = 0\nx2 = 0\ny2 = 0\nz2 = 0\n"
                 "s = 0\ndx1 = 0\ndy1 = 0\ndz1 = 0\ndx2 = 0\ndy2 = 0\ndz2 = 0\nds = 0\n"
                 "[scene]\nmodel = printed\n",
                 WG_EINVAL, ":2:", "of the printed model; missing: th1, th2, dth1, dth2");
    expect_error("given3.ini",
                 "[initial]\nstate = given\nx1 = 0\ny1 = 0\nz1 = 0\nx2 = 0\ny2 = 0\nz2 = 0\n"
                 "s = 0\ndx1 = 0\ndy1 = 0\ndz1 = 0\ndx2 = 0\ndy2 = 0\ndz2 = 0\nds = 0\n"
                 "th2 = 0\n",
                 WG_EINVAL, ":17:", "[initial] th2: not a state value of the consistent model");
    expect_error("eq1.ini", "[initial]\nstate = equilibrium\nz2 = 0.5\nx1 = 1\n", WG_EINVAL,
                 ":3:", "[initial] z2: a state value, but the start is the equilibrium");
    expect_error("eq2.ini", "[params]\nomega = 1\n[initial]\nds = 0.5\n", WG_EINVAL, ":4:",
                 "[initial] ds: a state value, but the start is the equilibrium (the default)");
    /* the printed model's own layout loads */
    wg_scene sc;
    char why[600];
    const char *p = scene_file("printed.ini", "[scene]\nmodel = printed\n[initial]\nstate = given\n"
                                              "x1 = 0\ny1 = 0\nz1 = 0\nx2 = 0\ny2 = 0\nz2 = 0\n"
                                              "th1 = 0.25\nth2 = 0\ndx1 = 0\ndy1 = 0\ndz1 = 0\n"
                                              "dx2 = 0\ndy2 = 0\ndz2 = 0\ndth1 = 0\ndth2 = -1\n");
    ASSERT_EQ_INT(wg_scene_load(&sc, p, why, sizeof why), WG_OK);
    ASSERT_NEAR(sc.y0[6], 0.25, 0);
    ASSERT_NEAR(sc.y0[15], -1, 0);
}

static void setup(void)
{
    snprintf(dir, sizeof dir, "/tmp/wgscene.XXXXXX");
    if (!mkdtemp(dir))
        abort();
}

static void teardown(void)
{
    char cmd[128];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    if (system(cmd) != 0)
        fprintf(stderr, "could not remove %s\n", dir);
}

/* Name or file, the one rule (wgrig opens a scene name that came off the
 * bus only when it is a name) */
static void test_name_or_file(void)
{
    ASSERT_TRUE(wg_scene_is_file("../../etc/passwd"));
    ASSERT_TRUE(wg_scene_is_file("my.ini"));
    ASSERT_TRUE(!wg_scene_is_file("table3"));
    ASSERT_TRUE(!wg_scene_is_file("table3-physical"));
    ASSERT_TRUE(!wg_scene_is_file(".ini")); /* a name: ".ini.ini" in the scene directories */
    char path[256], why[256];
    ASSERT_EQ_INT(wg_scene_find("x/y.ini", path, sizeof path, why, sizeof why), WG_OK);
    ASSERT_STR(path, "x/y.ini");
}

/* A name not found: the message lists the scenes there, each once, even
 * when two directories searched hold the same ones (here $WG_SCENE_PATH
 * names its directories twice). */
static void test_not_found_lists_each_once(void)
{
    const char *env = getenv("WG_SCENE_PATH");
    ASSERT_TRUE(env && *env && strlen(env) < 512);
    char saved[512], twice[1100], why[1600];
    snprintf(saved, sizeof saved, "%s", env);
    snprintf(twice, sizeof twice, "%s:%s", saved, saved);
    setenv("WG_SCENE_PATH", twice, 1);
    wg_scene sc;
    ASSERT_EQ_INT(wg_scene_open(&sc, "no-such-scene", why, sizeof why), WG_EIO);
    setenv("WG_SCENE_PATH", saved, 1);
    printf("  %s\n", why);
    ASSERT_CONTAINS(why, "scenes there: lowfreq, realistic, table3, table3-physical, torsional");
    int n = 0;
    for (const char *q = why; (q = strstr(q, "lowfreq")); q++)
        n++;
    ASSERT_EQ_INT(n, 1);
}

/* A file that cannot be opened: the message says why (it said only
 * "cannot open scene file"). */
static void test_open_reason(void)
{
    wg_scene sc;
    char why[600], path[128];
    snprintf(path, sizeof path, "%s/no-dir/good", dir);
    ASSERT_EQ_INT(wg_scene_load(&sc, path, why, sizeof why), WG_EIO);
    printf("  %s\n", why);
    ASSERT_CONTAINS(why, "cannot open scene file ");
    ASSERT_CONTAINS(why, path);
    ASSERT_CONTAINS(why, ": No such file or directory");
}

/* A directory or a FIFO is not a scene. A directory opened and read as an
 * empty file (the defaults ran under its name), a FIFO blocked the open;
 * both are refused naming the path, and a directory NAME.ini is not listed
 * among the scenes there. */
static void test_not_a_regular_file(void)
{
    char sub[96], path[128], fifo[128], why[1600];
    wg_scene sc;
    snprintf(sub, sizeof sub, "%s/sp", dir);
    snprintf(path, sizeof path, "%s/x.ini", sub);
    snprintf(fifo, sizeof fifo, "%s/fifo.ini", dir);
    ASSERT_EQ_INT(mkdir(sub, 0700), 0);
    ASSERT_EQ_INT(mkdir(path, 0700), 0);
    ASSERT_EQ_INT(mkfifo(fifo, 0600), 0);
    ASSERT_EQ_INT(wg_scene_load(&sc, path, why, sizeof why), WG_EIO);
    printf("  %s\n", why);
    ASSERT_CONTAINS(why, path);
    ASSERT_CONTAINS(why, "x.ini is a directory, not a regular file");
    ASSERT_EQ_INT(wg_scene_load(&sc, fifo, why, sizeof why), WG_EIO);
    printf("  %s\n", why);
    ASSERT_CONTAINS(why, fifo);
    ASSERT_CONTAINS(why, "fifo.ini is a FIFO, not a regular file");
    /* a scene is a few hundred bytes: a file over 1 MiB is not one */
    char big[128];
    snprintf(big, sizeof big, "%s/big.ini", dir);
    FILE *bf = fopen(big, "w");
    ASSERT_TRUE(bf && fputs("[params]\nomega = 1\n", bf) >= 0);
    for (int i = 0; bf && i < (1 << 20) / 16; i++)
        fputs("; padding .....\n", bf); /* 16 bytes */
    ASSERT_TRUE(bf && fclose(bf) == 0);
    ASSERT_EQ_INT(wg_scene_load(&sc, big, why, sizeof why), WG_EIO);
    printf("  %s\n", why);
    ASSERT_CONTAINS(why, "big.ini is 1048595 bytes (limit 1048576)");
    unlink(big);
    /* by name in $WG_SCENE_PATH: found, refused; the list leaves it out */
    char saved[512], y[128];
    snprintf(saved, sizeof saved, "%s", getenv("WG_SCENE_PATH"));
    snprintf(y, sizeof y, "%s/y.ini", sub);
    FILE *f = fopen(y, "w");
    ASSERT_TRUE(f && fputs("[params]\nomega = 1\n", f) >= 0 && fclose(f) == 0);
    setenv("WG_SCENE_PATH", sub, 1);
    ASSERT_EQ_INT(wg_scene_open(&sc, "x", why, sizeof why), WG_EIO);
    ASSERT_CONTAINS(why, "x.ini is a directory, not a regular file");
    /* a scene file x.ini later on the path is found past the directory (the
     * directory shadowed it: refused by name) */
    char sub2[96], later[128], two[200];
    snprintf(sub2, sizeof sub2, "%s/sp2", dir);
    snprintf(later, sizeof later, "%s/x.ini", sub2);
    snprintf(two, sizeof two, "%s:%s", sub, sub2);
    ASSERT_EQ_INT(mkdir(sub2, 0700), 0);
    f = fopen(later, "w");
    ASSERT_TRUE(f && fputs("[params]\nomega = 1.25\n", f) >= 0 && fclose(f) == 0);
    setenv("WG_SCENE_PATH", two, 1);
    ASSERT_EQ_INT(wg_scene_open(&sc, "x", why, sizeof why), WG_OK);
    ASSERT_NEAR(sc.p.v[WG_P_OMEGA], 1.25, 0);
    ASSERT_STR(sc.path, later);
    unlink(later);
    rmdir(sub2);
    setenv("WG_SCENE_PATH", sub, 1);
    ASSERT_EQ_INT(wg_scene_open(&sc, "no-such-scene", why, sizeof why), WG_EIO);
    setenv("WG_SCENE_PATH", saved, 1);
    printf("  %s\n", why);
    ASSERT_STR(strstr(why, "scenes there: "), "scenes there: y");
}

static void test_all(void)
{
    setup();
    test_shipped_scenes_load();
    test_not_found_lists_each_once();
    test_physical_equals_dimensionless();
    test_malformed_lines();
    test_silent_no_more();
    test_name_or_file();
    test_open_reason();
    test_not_a_regular_file();
    teardown();
}

TEST_MAIN(TEST(test_all))

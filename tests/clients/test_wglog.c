/* test_wglog.c - wglog on a synthetic log written with the eventlog API:
 * every wormgear type, a seq gap, a restart, a foreign channel; the summary
 * counts them, the CSV holds the published values bit-exactly in their
 * shortest form, the state columns by name and motion by name, strings are
 * quoted, --units physical converts with the log's scale, bad usage exits 2
 * naming the option. $WGLOG is the binary. */
#include "test.h"

#include "lcmtypes/wormgear_ack_t.h"
#include "lcmtypes/wormgear_cmd_t.h"
#include "lcmtypes/wormgear_contact_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "lcmtypes/wormgear_tick_t.h"

#include <lcm/eventlog.h>
#include <stdint.h>
#include <sys/wait.h>
#include <unistd.h>

static char dir[64], logpath[128];

static void put(lcm_eventlog_t *l, const char *ch, int64_t ts, void *buf, int len)
{
    lcm_eventlog_event_t ev = {0, ts, (int32_t)strlen(ch), len, (char *)ch, buf};
    ASSERT_EQ_INT(lcm_eventlog_write_event(l, &ev), 0);
}

#define PUT(T, l, ch, ts, msg)                                                             \
    do {                                                                                   \
        int n_ = T##_encoded_size(msg);                                                    \
        char *b_ = malloc((size_t)n_);                                                     \
        ASSERT_EQ_INT(T##_encode(b_, 0, n_, msg), n_);                                     \
        put(l, ch, ts, b_, n_);                                                            \
        free(b_);                                                                          \
    } while (0)

/* x_n of STATE message seq, sample i: not exactly representable decimals. */
static double xn_of(int64_t seq, int i) { return seq + i / 7.0 + 1e-13 / 3.0; }

static void write_states(lcm_eventlog_t *l)
{
    static const int64_t seqs[] = {0, 1, 2, 4, 5}; /* 3 is missing */
    for (int k = 0; k < 5; k++) {
        double v[14][3];
        for (int i = 0; i < 3; i++)
            for (int j = 0; j < 14; j++)
                v[j][i] = j == 3 ? xn_of(seqs[k], i) : sqrt(2.0) * (j + 1) + i;
        wormgear_state_t m = {.utime = 1000 + k, .seq = seqs[k], .step0 = 30 * seqs[k],
                              .decimation = 10, .n = 3, .tau = v[0], .t_s = v[1],
                              .omega = v[2], .xn = v[3], .dxn = v[4], .force = v[5],
                              .fb_x1 = v[6], .fb_y1 = v[7], .fb_z1 = v[8], .fb_x2 = v[9],
                              .fb_y2 = v[10], .fb_z2 = v[11], .theta1 = v[12], .theta2 = v[13]};
        PUT(wormgear_state_t, l, "RIG1_STATE", 1000000 + 20000 * k, &m);
    }
}

static void write_others(lcm_eventlog_t *l)
{
    static const int64_t sseq[] = {0, 1, 0}; /* a restart */
    for (int k = 0; k < 3; k++) {
        wormgear_status_t s = {.seq = sseq[k], .scene = "table3", .mode = "realtime",
                               .run = "running", .health = "ok", .fault = "",
                               .motion = "single_sided", .regime = "periodic", .omega = 0.7,
                               .tick_refusal = ""};
        PUT(wormgear_status_t, l, "RIG1_STATUS", 1000000 + 500000 * k, &s);
    }
    double y[2][14] = {{0}}, d2[2] = {0.5, 0.25};
    double *rows[2] = {y[0], y[1]};
    int64_t per[2] = {7, 8};
    int8_t mot[2] = {1, 1};
    int32_t imp[2] = {1, 2};
    y[1][13] = -1.0 / 3.0;
    int32_t bi[2][6] = {{0, 0, 0, 1, 0, 1}, {0, 0, 0, 2, 0, 1}}, *bir[2] = {bi[0], bi[1]};
    double bv[2][6] = {{0, 0, 0, 0.25, 0, 0.5}, {0}}, *bvr[2] = {bv[0], bv[1]};
    wormgear_poincare_t p = {.seq = 0, .nstate = 14, .n = 2, .period = per, .tau = d2,
                             .t_s = d2, .omega = d2, .xn = d2, .dxn = d2, .force = d2,
                             .min_xn = d2, .max_xn = d2, .motion = mot, .impacts = imp, .y = rows,
                             .nbearing = 6, .bearing_impacts = bir, .bearing_vmax = bvr};
    PUT(wormgear_poincare_t, l, "RIG1_POINCARE", 1100000, &p);
    int8_t cc[2] = {0, 4}, kk[2] = {1, 2};
    wormgear_contact_t c = {.seq = 0, .n = 2, .tau = d2, .t_s = d2, .velocity = d2,
                            .period = per, .contact = cc, .kind = kk};
    PUT(wormgear_contact_t, l, "RIG1_CONTACT", 1100000, &c);
    /* a third name, as a sender on the bus may write it, must stay one header cell */
    char *names[3] = {"omega", "xi_p", "k,a\"x"}, *units[3] = {"1", "1", "1"};
    double val[3] = {0.7, 0.08, 0.25};
    int8_t ramp[3] = {1, 1, 1};
    wormgear_params_t pa = {.seq = 0, .reason = "start", .cmd_client = "", .cmd_seq = -1,
                            .scene = "table3", .model = "consistent", .stepper = "rk4-event",
                            .omega_n_rad_s = 31901, .length_m = 1e-4,
                            .mesh_stiffness_N_m = 2e9,
                            .n = 3, .name = names, .unit = units, .value = val, .min = val,
                            .max = val, .def = val, .rampable = ramp, .ramp_param = ""};
    PUT(wormgear_params_t, l, "RIG1_PARAMS", 1000001, &pa);
    wormgear_cmd_t cmd = {.seq = 9, .client = "t", .op = "set", .nparams = 2, .names = names,
                          .values = val, .unit = "", .name = ""};
    PUT(wormgear_cmd_t, l, "RIG1_CMD", 1200000, &cmd);
    wormgear_ack_t a = {.seq = 0, .client = "t", .cmd_seq = 9, .cmd_utime = 1199000,
                        .op = "set", .code = "ERANGE",
                        .message = "omega = 99 out of range [0.01, 10], \"said\" the table"};
    PUT(wormgear_ack_t, l, "RIG1_ACK", 1200100, &a);
    wormgear_tick_t t = {.seq = 0, .nsteps = 5, .client = (char *)""};
    PUT(wormgear_tick_t, l, "RIG1_TICK", 1300000, &t);
    put(l, "OTHER", 1300001, "not an lcm message", 18);
    put(l, "EVIL\033]0;pwned\007\033[2J", 1300002, "x", 1); /* escapes in a channel name */
}

/* A log played into a live bus: RIG2_STATUS carries the live daemon (seq
 * 100.., utime = now) and a replay of an hour ago (seq 3.., interleaved). */
static void write_mixed(lcm_eventlog_t *l)
{
    const int64_t t0 = 1700000000000000; /* an epoch time, us */
    for (int k = 0; k < 5; k++) {
        wormgear_status_t a = {.seq = 100 + k, .utime = t0 + 500000 * k, .scene = "table3",
                               .mode = "realtime", .run = "running", .health = "ok",
                               .fault = "", .motion = "no_impact", .regime = "period-1",
                               .tick_refusal = ""};
        wormgear_status_t b = a;
        b.seq = 3 + k, b.utime = t0 - 3600000000 + 500000 * k;
        PUT(wormgear_status_t, l, "RIG2_STATUS", t0 + 500000 * k + 1000, &a);
        PUT(wormgear_status_t, l, "RIG2_STATUS", t0 + 500000 * k + 2000, &b);
    }
}

/* Run the shell command; its stdout into out (may be NULL); its exit code,
 * or -1. */
static int run(const char *cmd, char *out, size_t len)
{
    FILE *p = popen(cmd, "r");
    if (!p)
        return -1;
    size_t n = out ? fread(out, 1, len - 1, p) : 0;
    if (out)
        out[n] = 0;
    int st = pclose(p);
    return WIFEXITED(st) ? WEXITSTATUS(st) : -1;
}

static void setup(void)
{
    snprintf(dir, sizeof dir, "/tmp/test_wglog.XXXXXX");
    ASSERT_TRUE(mkdtemp(dir) != NULL);
    snprintf(logpath, sizeof logpath, "%s/t.lcmlog", dir);
    lcm_eventlog_t *l = lcm_eventlog_create(logpath, "w");
    ASSERT_TRUE(l != NULL);
    write_states(l);
    write_others(l);
    write_mixed(l);
    lcm_eventlog_destroy(l);
}

static const char *wglog(void)
{
    const char *w = getenv("WGLOG");
    return w ? w : "wglog";
}

static void test_summary(void)
{
    char cmd[512], out[8192];
    snprintf(cmd, sizeof cmd, "%s summary %s", wglog(), logpath);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 0);
    fputs(out, stdout);
    /* channel type msgs samples bytes rate gaps missing restarts bad */
    char *s = strstr(out, "RIG1_STATE ");
    long msgs = 0, samples = 0, gaps = 0, missing = 0, restarts = 0;
    double rate = 0;
    ASSERT_TRUE(s && sscanf(s, "RIG1_STATE state_t %ld %ld %*d %lf %ld %ld %ld", &msgs,
                            &samples, &rate, &gaps, &missing, &restarts) == 6);
    ASSERT_EQ_INT(msgs, 5);
    ASSERT_EQ_INT(samples, 15);
    ASSERT_NEAR(rate, 50.0, 1e-9); /* 4 intervals over 80 ms */
    ASSERT_EQ_INT(gaps, 1);
    ASSERT_EQ_INT(missing, 1);
    ASSERT_EQ_INT(restarts, 0);
    s = strstr(out, "RIG1_STATUS ");
    ASSERT_TRUE(s && sscanf(s, "RIG1_STATUS status_t %ld %*d %*d %*f %ld %ld %ld", &msgs, &gaps,
                            &missing, &restarts) == 4);
    ASSERT_EQ_INT(restarts, 1);
    ASSERT_CONTAINS(out, "RIG1_POINCARE");
    ASSERT_CONTAINS(out, "RIG1_TICK");
    ASSERT_CONTAINS(out, "OTHER");
    ASSERT_CONTAINS(out, "26 events");
    ASSERT_CONTAINS(out, "EVIL?]0;pwned??[2J "); /* shown as text, */
    ASSERT_TRUE(strchr(out, '\033') == NULL && strchr(out, '\007') == NULL); /* never obeyed */
    /* the replay is one more sender: no gap, no restart */
    long senders = 0;
    s = strstr(out, "RIG2_STATUS ");
    ASSERT_TRUE(s && sscanf(s, "RIG2_STATUS status_t %ld %*d %*d %*f %ld %ld %ld %*d %ld", &msgs,
                            &gaps, &missing, &restarts, &senders) == 5);
    ASSERT_EQ_INT(msgs, 10);
    ASSERT_EQ_INT(gaps, 0);
    ASSERT_EQ_INT(missing, 0);
    ASSERT_EQ_INT(restarts, 0);
    ASSERT_EQ_INT(senders, 2);
    ASSERT_CONTAINS(out, "note: RIG2_STATUS: a sender from seq 3 at 0.001 s, its clock -3600.002 s "
                         "from the log's (a replay)");
}

/* Column `col` (0-based) of line `row` (0 = header) of a CSV, as text. */
static int cell(const char *path, int row, int col, char *buf, size_t len)
{
    FILE *f = fopen(path, "r");
    char line[8192];
    int r = -1;
    for (int i = 0; f && fgets(line, sizeof line, f); i++)
        if (i == row) {
            char *p = line;
            for (int c = 0; c < col && p; c++)
                p = strchr(p, ',') ? strchr(p, ',') + 1 : NULL;
            if (p) {
                snprintf(buf, len, "%.*s", (int)strcspn(p, ",\n"), p);
                r = 0;
            }
        }
    if (f)
        fclose(f);
    return r;
}

static void test_export(void)
{
    char cmd[512], path[256], c[256];
    snprintf(cmd, sizeof cmd, "%s export %s --out %s/csv -q", wglog(), logpath, dir);
    ASSERT_EQ_INT(run(cmd, NULL, 0), 0);
    snprintf(path, sizeof path, "%s/csv/RIG1_STATE.csv", dir);
    ASSERT_EQ_INT(cell(path, 0, 9, c, sizeof c), 0);
    ASSERT_STR(c, "xn");
    static const int64_t seqs[] = {0, 1, 2, 4, 5};
    for (int r = 1; r <= 15; r++) {
        int64_t seq = seqs[(r - 1) / 3];
        int i = (r - 1) % 3;
        ASSERT_EQ_INT(cell(path, r, 2, c, sizeof c), 0);
        ASSERT_EQ_INT(atoll(c), seq);
        ASSERT_EQ_INT(cell(path, r, 9, c, sizeof c), 0);
        ASSERT_TRUE(strtod(c, NULL) == xn_of(seq, i)); /* bit-exact */
    }
    ASSERT_TRUE(cell(path, 16, 0, c, sizeof c) < 0); /* 15 samples, no more */
    ASSERT_EQ_INT(cell(path, 0, 18, c, sizeof c), 0);
    ASSERT_STR(c, "theta1");
    ASSERT_EQ_INT(cell(path, 0, 19, c, sizeof c), 0);
    ASSERT_STR(c, "theta2");
    ASSERT_EQ_INT(cell(path, 2, 19, c, sizeof c), 0);
    ASSERT_TRUE(strtod(c, NULL) == sqrt(2.0) * 14 + 1);
    snprintf(path, sizeof path, "%s/csv/RIG1_POINCARE.csv", dir);
    ASSERT_EQ_INT(cell(path, 0, 15, c, sizeof c), 0);
    ASSERT_STR(c, "x1"); /* the state by name, not y0 ... y13 */
    ASSERT_EQ_INT(cell(path, 0, 17, c, sizeof c), 0);
    ASSERT_STR(c, "z1");
    ASSERT_EQ_INT(cell(path, 0, 28, c, sizeof c), 0);
    ASSERT_STR(c, "ds");
    ASSERT_EQ_INT(cell(path, 2, 28, c, sizeof c), 0);
    ASSERT_TRUE(strtod(c, NULL) == -1.0 / 3.0);
    ASSERT_EQ_INT(cell(path, 0, 32, c, sizeof c), 0);
    ASSERT_STR(c, "x2_impacts");
    ASSERT_EQ_INT(cell(path, 2, 32, c, sizeof c), 0);
    ASSERT_STR(c, "2");
    ASSERT_EQ_INT(cell(path, 0, 40, c, sizeof c), 0);
    ASSERT_STR(c, "z2_vmax");
    ASSERT_EQ_INT(cell(path, 1, 40, c, sizeof c), 0);
    ASSERT_TRUE(strtod(c, NULL) == 0.5);
    ASSERT_EQ_INT(cell(path, 1, 13, c, sizeof c), 0);
    ASSERT_STR(c, "single_sided"); /* motion by name */
    ASSERT_EQ_INT(cell(path, 1, 8, c, sizeof c), 0);
    ASSERT_STR(c, "0.5");
    snprintf(path, sizeof path, "%s/csv/RIG1_CONTACT.csv", dir);
    ASSERT_EQ_INT(cell(path, 2, 10, c, sizeof c), 0);
    ASSERT_STR(c, "x2");
    snprintf(path, sizeof path, "%s/csv/RIG1_PARAMS.csv", dir);
    ASSERT_EQ_INT(cell(path, 0, 22, c, sizeof c), 0);
    ASSERT_STR(c, "xi_p");
    ASSERT_EQ_INT(cell(path, 1, 22, c, sizeof c), 0);
    ASSERT_STR(c, "0.08"); /* shortest round trip, not 0.080000000000000002 */
    FILE *fp = fopen(path, "r");
    char hdr[2048] = "";
    ASSERT_TRUE(fp && fread(hdr, 1, sizeof hdr - 1, fp) > 0);
    if (fp)
        fclose(fp);
    ASSERT_CONTAINS(hdr, ",xi_p,\"k,a\"\"x\"\n"); /* quoted, the quote doubled */
    snprintf(path, sizeof path, "%s/csv/RIG1_CMD.csv", dir);
    ASSERT_EQ_INT(cell(path, 1, 5, c, sizeof c), 0);
    ASSERT_STR(c, "omega=0.7;xi_p=0.08");
    snprintf(path, sizeof path, "%s/csv/RIG1_ACK.csv", dir);
    FILE *f = fopen(path, "r");
    char all[2048] = "";
    ASSERT_TRUE(f && fread(all, 1, sizeof all - 1, f) > 0);
    if (f)
        fclose(f);
    ASSERT_CONTAINS(all, "client,cmd_seq,cmd_utime,op,");
    ASSERT_CONTAINS(all, ",t,9,1199000,set,0,0,ERANGE,\"omega = 99 out of range [0.01, 10], "
                         "\"\"said\"\" the table\""); /* the command it answers: t, 9, 1199000 */
    snprintf(path, sizeof path, "%s/csv/OTHER.csv", dir);
    ASSERT_TRUE(access(path, F_OK) != 0); /* foreign channel skipped */
}

/* --units physical: the samples in Hz, um, m/s, N with the scale of the
 * log's PARAMS (which comes after the first STATE: the pre-pass finds it). */
static void test_physical(void)
{
    char cmd[512], path[256], c[256];
    snprintf(cmd, sizeof cmd, "%s export %s --out %s/phys -q --units physical --channel "
             "'RIG1_(STATE|POINCARE|CONTACT)'", wglog(), logpath, dir);
    ASSERT_EQ_INT(run(cmd, NULL, 0), 0);
    snprintf(path, sizeof path, "%s/phys/RIG1_STATE.csv", dir);
    static const char *const head[] = {"f_mesh_hz", "x_n_um", "dx_n_m_s", "F_N", "fb_x1_N"};
    for (int k = 0; k < 5; k++) {
        ASSERT_EQ_INT(cell(path, 0, 8 + k, c, sizeof c), 0);
        ASSERT_STR(c, head[k]);
    }
    ASSERT_EQ_INT(cell(path, 2, 9, c, sizeof c), 0);
    ASSERT_TRUE(strtod(c, NULL) == xn_of(0, 1) * (1e-4 * 1e6)); /* x_n b_c in um */
    ASSERT_EQ_INT(cell(path, 2, 11, c, sizeof c), 0);
    ASSERT_TRUE(strtod(c, NULL) == (sqrt(2.0) * 6 + 1) * (2e9 * 1e-4)); /* F K_m b_c in N */
    ASSERT_EQ_INT(cell(path, 0, 18, c, sizeof c), 0);
    ASSERT_STR(c, "theta1_rad");
    ASSERT_EQ_INT(cell(path, 2, 18, c, sizeof c), 0);
    ASSERT_TRUE(strtod(c, NULL) == sqrt(2.0) * 13 + 1); /* radians either way */
    snprintf(path, sizeof path, "%s/phys/RIG1_POINCARE.csv", dir);
    ASSERT_EQ_INT(cell(path, 0, 15, c, sizeof c), 0);
    ASSERT_STR(c, "x1_um");
    ASSERT_EQ_INT(cell(path, 0, 28, c, sizeof c), 0);
    ASSERT_STR(c, "ds_m_s");
    ASSERT_EQ_INT(cell(path, 2, 28, c, sizeof c), 0);
    ASSERT_TRUE(strtod(c, NULL) == -1.0 / 3.0 * (1e-4 * 31901)); /* v b_c omega_n in m/s */
    snprintf(path, sizeof path, "%s/phys/RIG1_CONTACT.csv", dir);
    ASSERT_EQ_INT(cell(path, 0, 6, c, sizeof c), 0);
    ASSERT_STR(c, "velocity_m_s");
    /* a log without PARAMS has no scale: refused, saying why */
    char lone[160], out[1024];
    snprintf(lone, sizeof lone, "%s/lone.lcmlog", dir);
    lcm_eventlog_t *l = lcm_eventlog_create(lone, "w");
    ASSERT_TRUE(l != NULL);
    write_states(l);
    lcm_eventlog_destroy(l);
    snprintf(cmd, sizeof cmd, "%s export %s --out %s/lone --units physical 2>&1", wglog(), lone,
             dir);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 1);
    ASSERT_CONTAINS(out, "has no PARAMS message, so its physical scale");
    snprintf(cmd, sizeof cmd, "%s export %s --units metric 2>&1", wglog(), lone);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 2);
    ASSERT_CONTAINS(out, "--units 'metric': dimensionless or physical");
}

static void test_channel_filter(void)
{
    char cmd[512], out[4096];
    snprintf(cmd, sizeof cmd, "%s summary %s --channel 'RIG1_(STATE|ACK)'", wglog(), logpath);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 0);
    ASSERT_CONTAINS(out, "2 channels");
    ASSERT_TRUE(!strstr(out, "RIG1_STATUS"));
    /* a pattern matching no channel: said, with the channels there are, exit 1
     * (it printed "0 channels" and exited 0) */
    snprintf(cmd, sizeof cmd, "%s summary %s --channel NOPE 2>&1", wglog(), logpath);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 1);
    fputs(out, stdout);
    ASSERT_CONTAINS(out, "no channel of ");
    ASSERT_CONTAINS(out, "matches --channel 'NOPE' (a regex matching the whole name); its "
                         "channels include RIG1_STATE, ");
    ASSERT_TRUE(!strstr(out, "0 channels"));
    /* each channel named once, however many events it has */
    ASSERT_TRUE(strstr(strstr(out, "RIG1_STATE,") + 1, "RIG1_STATE,") == NULL);
    snprintf(cmd, sizeof cmd, "%s export %s --channel 'RIG1_STAT' --out %s/none 2>&1", wglog(),
             logpath, dir);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 1);
    ASSERT_CONTAINS(out, "matches --channel 'RIG1_STAT'");
}

/* Two channels whose names map to one file name (A/B and A_B): each its
 * own CSV (they were written into one, interleaved), and said. */
static void test_export_names_collide(void)
{
    char path[160], cmd[1024], out[4096];
    snprintf(path, sizeof path, "%s/collide.lcmlog", dir);
    lcm_eventlog_t *l = lcm_eventlog_create(path, "w");
    ASSERT_TRUE(l != NULL);
    for (int k = 0; k < 4; k++) {
        wormgear_tick_t t = {.utime = 1000 + k, .seq = k, .nsteps = 10 + k, .client = ""};
        PUT(wormgear_tick_t, l, k % 2 ? "R/TICK" : "R_TICK", 1000000 + 1000 * k, &t);
    }
    lcm_eventlog_destroy(l);
    snprintf(cmd, sizeof cmd, "mkdir -p %s/cx && %s export %s --out %s/cx 2>&1 && "
             "wc -l <%s/cx/R_TICK.csv && wc -l <'%s/cx/R_TICK~2.csv'", dir, wglog(), path, dir,
             dir, dir);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 0);
    ASSERT_CONTAINS(out, "R/TICK: another channel's CSV has its file name");
    ASSERT_CONTAINS(out, "\n3\n3\n"); /* a header and 2 rows each */
    /* channel names of 300 bytes, alike in their first 200: each CSV's name
     * cut to 200 bytes, the second ~2 (the export stopped: File name too long) */
    char longa[301], longb[301];
    memset(longa, 'A', 300), memset(longb, 'A', 300);
    longa[300] = longb[300] = 0, longb[299] = 'B';
    l = lcm_eventlog_create(path, "w");
    ASSERT_TRUE(l != NULL);
    for (int k = 0; k < 4; k++) {
        wormgear_tick_t t = {.utime = 1000 + k, .seq = k, .nsteps = 10 + k, .client = ""};
        PUT(wormgear_tick_t, l, k % 2 ? longb : longa, 1000000 + 1000 * k, &t);
    }
    lcm_eventlog_destroy(l);
    char name[201];
    memset(name, 'A', 200), name[200] = 0;
    snprintf(cmd, sizeof cmd, "mkdir -p %s/cl && %s export %s --out %s/cl 2>&1 && "
             "wc -l <%s/cl/%s.csv && wc -l <'%s/cl/%s~2.csv'", dir, wglog(), path, dir, dir,
             name, dir, name);
    char big[8192];
    ASSERT_EQ_INT(run(cmd, big, sizeof big), 0);
    ASSERT_CONTAINS(big, "\n3\n3\n");
}

/* A big-endian int32 at p (the log's lengths). */
/* The lines of a file an export wrote (-1 if it cannot be read); its first
 * into first (len bytes) when first is not NULL. */
static int csv_lines(const char *path, char *first, size_t len)
{
    static char buf[8192];
    FILE *f = fopen(path, "r");
    if (!f)
        return -1;
    int n = 0;
    if (first)
        first[0] = 0;
    while (fgets(buf, sizeof buf, f))
        if (n++ == 0 && first)
            snprintf(first, len, "%s", buf);
    fclose(f);
    return n;
}

static int32_t get32(const unsigned char *p)
{
    return (int32_t)((uint32_t)p[0] << 24 | (uint32_t)p[1] << 16 | (uint32_t)p[2] << 8 | p[3]);
}

/* A log holding messages no daemon sends: a CONTACT whose count is 2^31 - 1
 * and a STATUS whose scene string claims 2^31 - 1 bytes, between good ones.
 * wglog died inside LCM's generated decoder on them (SIGSEGV); they are
 * now counted bad, the good ones read, and the export writes the rest. */
static void test_hostile_messages(void)
{
    char path[160], cmd[640], out[8192];
    snprintf(path, sizeof path, "%s/bent.lcmlog", dir);
    lcm_eventlog_t *l = lcm_eventlog_create(path, "w");
    ASSERT_TRUE(l != NULL);
    double v[1] = {1.0};
    int64_t per[1] = {0};
    int8_t k[1] = {0};
    unsigned char buf[2048];
    for (int i = 0; i < 3; i++) {
        wormgear_contact_t c = {.seq = i, .n = 1, .tau = v, .t_s = v, .velocity = v,
                                .period = per, .contact = k, .kind = k};
        int n = wormgear_contact_t_encode(buf, 0, sizeof buf, &c);
        ASSERT_TRUE(n > 32);
        if (i == 1) /* n, after the fingerprint, utime, seq and bearing_every */
            buf[28] = 0x7f, buf[29] = buf[30] = buf[31] = 0xff;
        put(l, "BENT_CONTACT", 1000 * (i + 1), buf, n);
        wormgear_status_t st = {.seq = i, .scene = "s", .mode = "m", .run = "r", .health = "h",
                                .fault = "", .motion = "", .regime = "",
                                .tick_refusal = ""};
        n = wormgear_status_t_encode(buf, 0, sizeof buf, &st);
        if (i == 1) /* the scene string's length */
            buf[24] = 0x7f, buf[25] = buf[26] = buf[27] = 0xff;
        put(l, "BENT_STATUS", 1000 * (i + 1) + 500, buf, n);
    }
    lcm_eventlog_destroy(l);
    snprintf(cmd, sizeof cmd, "%s summary %s", wglog(), path);
    int rc = run(cmd, out, sizeof out);
    fputs(out, stdout);
    ASSERT_TRUE(rc == 0 || rc == 1); /* not killed by a signal (-1) */
    /* channel type msgs samples bytes rate gaps missing restarts senders bad */
    long msgs = -1;
    char *s = strstr(out, "BENT_CONTACT ");
    ASSERT_TRUE(s && sscanf(s, "BENT_CONTACT contact_t %ld", &msgs) == 1);
    ASSERT_EQ_INT(msgs, 3);
    snprintf(cmd, sizeof cmd, "%s export %s --out %s/bent", wglog(), path, dir);
    rc = run(cmd, NULL, 0);
    ASSERT_TRUE(rc == 0 || rc == 1);
    snprintf(path, sizeof path, "%s/bent/BENT_CONTACT.csv", dir);
    ASSERT_EQ_INT(csv_lines(path, NULL, 0), 1 + 2); /* the header and the two good rows */
    /* the same log cut inside its last event, and a directory: exit 1 with
     * the reason (they gave exit 0: a part of the log, "0 events"), the
     * summary of what could be read */
    snprintf(cmd, sizeof cmd, "head -c -10 %s/bent.lcmlog >%s/cut.lcmlog && %s summary "
             "%s/cut.lcmlog 2>&1", dir, dir, wglog(), dir);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 1);
    ASSERT_CONTAINS(out, "cut.lcmlog: damaged: ");
    ASSERT_CONTAINS(out, "in 1 stretch, the first at byte");
    ASSERT_CONTAINS(out, "the 5 whole events around them are read");
    ASSERT_CONTAINS(out, "BENT_CONTACT ");
    /* damage inside the log: the second event's data length bent to
     * 2^31 - 1. The reader finds the next sync word and reads on (it
     * stopped there, the last 4 events unread); a 2-byte tail after the
     * last event is damage too (it passed as a clean end) */
    snprintf(path, sizeof path, "%s/bent.lcmlog", dir);
    FILE *f = fopen(path, "rb");
    ASSERT_TRUE(f != NULL);
    static unsigned char img[8192];
    size_t len = f ? fread(img, 1, sizeof img, f) : 0;
    if (f)
        fclose(f);
    size_t second = 28 + (size_t)get32(img + 20) + (size_t)get32(img + 24);
    ASSERT_TRUE(len > second + 28 && get32(img + second) == (int32_t)0xEDA1DA01);
    img[second + 24] = 0x7f, img[second + 25] = img[second + 26] = img[second + 27] = 0xff;
    snprintf(path, sizeof path, "%s/mid.lcmlog", dir);
    f = fopen(path, "wb");
    ASSERT_TRUE(f && fwrite(img, 1, len, f) == len && fwrite("xy", 1, 2, f) == 2);
    if (f)
        fclose(f);
    snprintf(cmd, sizeof cmd, "%s summary %s 2>&1", wglog(), path);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 1);
    fputs(out, stdout);
    ASSERT_CONTAINS(out, "in 2 stretches, the first at byte");
    ASSERT_CONTAINS(out, "the 5 whole events around them are read");
    s = strstr(out, "BENT_CONTACT ");
    ASSERT_TRUE(s && sscanf(s, "BENT_CONTACT contact_t %ld", &msgs) == 1);
    ASSERT_EQ_INT(msgs, 3);
    s = strstr(out, "BENT_STATUS ");
    ASSERT_TRUE(s && sscanf(s, "BENT_STATUS status_t %ld", &msgs) == 1);
    ASSERT_EQ_INT(msgs, 2);
    snprintf(cmd, sizeof cmd, "%s summary %s 2>&1", wglog(), dir);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 1);
    ASSERT_CONTAINS(out, "is a directory, not a regular file");
    /* a file that is no log at all (a README given by mistake): said so,
     * not "damaged: N of N bytes skipped" */
    snprintf(path, sizeof path, "%s/text.md", dir);
    f = fopen(path, "w");
    ASSERT_TRUE(f && fputs("# not a log\nsome text\n", f) >= 0);
    if (f)
        fclose(f);
    snprintf(cmd, sizeof cmd, "%s summary %s 2>&1", wglog(), path);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 1);
    ASSERT_CONTAINS(out, "text.md: not an LCM log: no event in its 22 bytes");
}

/* A channel whose first message fails the check: its CSV still gets its
 * header, with the state columns of the first good POINCARE (it had none,
 * the rows 14 cells short); the bad one is said on stderr and the export
 * exits 1 (it went without a word, exit 0). The bad one here is what the
 * fuzzer found: no rows and nstate 2^31 - 1, which passed the check and
 * made wglog write a header of 2^31 columns. */
static void test_first_message_bad(void)
{
    char path[160], cmd[640], out[8192];
    snprintf(path, sizeof path, "%s/first.lcmlog", dir);
    lcm_eventlog_t *l = lcm_eventlog_create(path, "w");
    ASSERT_TRUE(l != NULL);
    wormgear_poincare_t bad = {.seq = 0, .nstate = INT32_MAX, .n = 0, .nbearing = 6};
    PUT(wormgear_poincare_t, l, "FIRST_POINCARE", 1000, &bad);
    double y[14] = {0}, d[1] = {0.5}, *rows[1] = {y}, bv[6] = {0}, *bvr[1] = {bv};
    int64_t per[1] = {7};
    int8_t mot[1] = {1};
    int32_t imp[1] = {1}, bi[6] = {0}, *bir[1] = {bi};
    wormgear_poincare_t p = {.seq = 1, .nstate = 14, .n = 1, .period = per, .tau = d,
                             .t_s = d, .omega = d, .xn = d, .dxn = d, .force = d,
                             .min_xn = d, .max_xn = d, .motion = mot, .impacts = imp, .y = rows,
                             .nbearing = 6, .bearing_impacts = bir, .bearing_vmax = bvr};
    PUT(wormgear_poincare_t, l, "FIRST_POINCARE", 2000, &p);
    lcm_eventlog_destroy(l);
    snprintf(cmd, sizeof cmd, "timeout 20 %s export %s --out %s/first 2>&1", wglog(), path, dir);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 1);
    ASSERT_CONTAINS(out, "FIRST_POINCARE: 1 of 2 messages are not whole poincare_t messages");
    snprintf(path, sizeof path, "%s/first/FIRST_POINCARE.csv", dir);
    char line[8192];
    ASSERT_EQ_INT(csv_lines(path, line, sizeof line), 2); /* the header and the good row */
    ASSERT_CONTAINS(line, "log_utime,utime,seq,");
    ASSERT_CONTAINS(line, ",x1,y1,z1,x2,y2,z2,s,dx1,");
}

/* 5000 channels, each event found in the name index (each compared with
 * every channel before: 60,000 channels took minutes): every one listed
 * once, with its own count (the first has three events, the others two). */
static void test_many_channels(void)
{
    char path[160], cmd[640], name[16];
    snprintf(path, sizeof path, "%s/many.lcmlog", dir);
    lcm_eventlog_t *l = lcm_eventlog_create(path, "w");
    ASSERT_TRUE(l != NULL);
    unsigned char b[8] = {1, 2, 3, 4, 5, 6, 7, 8};
    for (int k = 0; k < 2; k++)
        for (int i = 0; i < 5000; i++) {
            snprintf(name, sizeof name, "H%05d", i);
            put(l, name, 1000 + i, b, 8);
        }
    put(l, "H00000", 99999, b, 8);
    lcm_eventlog_destroy(l);
    snprintf(cmd, sizeof cmd, "%s summary %s | awk '/^H/ { n++; m[$3]++; if ($1 == \"H00000\") "
             "f = $3 } END { print n, m[2], f }'", wglog(), path);
    char out[256];
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 0);
    ASSERT_STR(out, "5000 4999 3\n");
}

/* A log at path of nchan TICK channels ("<letter>0000_TICK", ...), each with
 * nmsg messages in turn: message k has utime 1000 + k, seq k, nsteps 10 k + 1,
 * the log's time 1000 k + the channel's index. */
static void write_ticks(const char *path, char letter, int nchan, int nmsg)
{
    char name[24]; /* a letter, an int (up to 11 characters), "_TICK" */
    lcm_eventlog_t *l = lcm_eventlog_create(path, "w");
    ASSERT_TRUE(l != NULL);
    for (int k = 0; k < nmsg; k++)
        for (int i = 0; i < nchan; i++) {
            wormgear_tick_t t = {.utime = 1000 + k, .seq = k, .nsteps = 10 * k + 1,
                                 .client = "", .mac_len = 0, .mac = NULL};
            snprintf(name, sizeof name, "%c%04d_TICK", letter, i);
            PUT(wormgear_tick_t, l, name, 1000 * k + i, &t);
        }
    lcm_eventlog_destroy(l);
}

/* Export of more channels than descriptors: each channel's CSV was kept
 * open, and a log of 1,500 TICK channels stopped at "Too many open files"
 * (here under ulimit -n 64). Now at most 256 are open, the rest reopened:
 * every CSV has its header and its three rows, in order. */
static void test_export_many_channels(void)
{
    char path[160], cmd[640], out[4096], line[256];
    snprintf(path, sizeof path, "%s/manyx.lcmlog", dir);
    write_ticks(path, 'M', 1500, 3);
    snprintf(cmd, sizeof cmd, "ulimit -n 64 && %s export %s --out %s/manyx 2>&1", wglog(), path,
             dir);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 0);
    for (int i = 0; i < 1500; i += 149) {
        snprintf(path, sizeof path, "%s/manyx/M%04d_TICK.csv", dir, i);
        ASSERT_EQ_INT(csv_lines(path, NULL, 0), 4);
        FILE *f = fopen(path, "r");
        ASSERT_TRUE(f != NULL);
        for (int k = -1; k < 3 && fgets(line, sizeof line, f); k++) {
            if (k < 0) {
                ASSERT_CONTAINS(line, "log_utime,utime,seq,");
                continue;
            }
            char want[64];
            snprintf(want, sizeof want, "%d,%d,%d,%d\n", 1000 * k + i, 1000 + k, k, 10 * k + 1);
            ASSERT_STR(line, want);
        }
        fclose(f);
    }
    /* a write that fails (files over 2 KiB: ulimit -f, SIGXFSZ ignored) is said
     * once per channel; it was said again at every close of the open CSVs, and
     * rows were added after the torn one (541 lines for these 40 channels) */
    snprintf(path, sizeof path, "%s/big.lcmlog", dir);
    write_ticks(path, 'B', 40, 200);
    static char big[1 << 16];
    snprintf(cmd, sizeof cmd, "trap '' XFSZ; ulimit -n 16 && ulimit -f 2 && %s export %s --out "
             "%s/big 2>&1", wglog(), path, dir);
    ASSERT_EQ_INT(run(cmd, big, sizeof big), 1);
    int said = 0;
    for (const char *q = big; (q = strstr(q, "failed: File too large")); q++)
        said++;
    ASSERT_EQ_INT(said, 40);
    ASSERT_CONTAINS(big, "B0007_TICK.csv (channel B0007_TICK) failed: File too large: the file is "
                         "incomplete");
}

static void test_usage(void)
{
    char cmd[512], out[4096];
    snprintf(cmd, sizeof cmd, "%s frobnicate %s 2>&1", wglog(), logpath);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 2);
    ASSERT_CONTAINS(out, "command 'frobnicate': one of record, summary, export");
    snprintf(cmd, sizeof cmd, "%s summary %s --channel '(' 2>&1", wglog(), logpath);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 2);
    ASSERT_CONTAINS(out, "--channel '('");
    snprintf(cmd, sizeof cmd, "%s summary %s/nonexistent.lcmlog 2>&1", wglog(), dir);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 1);
    ASSERT_CONTAINS(out, "cannot open log");
    snprintf(cmd, sizeof cmd, "%s --help", wglog());
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 0);
    ASSERT_CONTAINS(out, "--out DIR");
    ASSERT_CONTAINS(out, "(default .)");
}

/* Logs a reader may be handed: empty (qsort was called on no array: UB),
 * and stamped INT64_MIN then INT64_MAX (the spans overflowed: UB), on an
 * untyped channel and on STATE from two senders (the note of the second
 * sender's start time). Summarised, exit 0; the ASan/UBSan build stops on
 * any undefined behaviour. */
static void test_extreme_logs(void)
{
    char path[160], cmd[512], out[4096];
    snprintf(path, sizeof path, "%s/empty.lcmlog", dir);
    FILE *f = fopen(path, "w");
    ASSERT_TRUE(f != NULL);
    fclose(f);
    snprintf(cmd, sizeof cmd, "%s summary %s 2>&1", wglog(), path);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 0);
    ASSERT_CONTAINS(out, "0 events, 0.000 s, 0 channels");
    snprintf(path, sizeof path, "%s/stamps.lcmlog", dir);
    lcm_eventlog_t *l = lcm_eventlog_create(path, "w");
    ASSERT_TRUE(l != NULL);
    put(l, "X", INT64_MIN, "12345678", 8);
    put(l, "X", INT64_MAX, "12345678", 8);
    double v[3] = {1, 2, 3};
    for (int k = 0; k < 2; k++) {
        wormgear_state_t m = {.utime = k ? INT64_MAX : INT64_MIN, .seq = k ? 0 : 5, .n = 1,
                              .decimation = 1, .tau = v, .t_s = v, .omega = v, .xn = v,
                              .dxn = v, .force = v, .fb_x1 = v, .fb_y1 = v, .fb_z1 = v,
                              .fb_x2 = v, .fb_y2 = v, .fb_z2 = v, .theta1 = v, .theta2 = v};
        PUT(wormgear_state_t, l, "RIG9_STATE", k ? INT64_MAX : INT64_MIN, &m);
    }
    lcm_eventlog_destroy(l);
    snprintf(cmd, sizeof cmd, "%s summary %s 2>&1", wglog(), path);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 0);
    fputs(out, stdout);
    ASSERT_CONTAINS(out, "4 events");
    ASSERT_CONTAINS(out, "2 channels");
    ASSERT_TRUE(strstr(out, "runtime error") == NULL);
    /* a summary its standard output does not take: said, exit 1 (it was 0) */
    snprintf(cmd, sizeof cmd, "%s summary %s 2>&1 >/dev/full", wglog(), path);
    ASSERT_EQ_INT(run(cmd, out, sizeof out), 1);
    ASSERT_CONTAINS(out, "wglog: writing the standard output failed: No space left on device");
}

static void test_cleanup(void)
{
    char cmd[256];
    snprintf(cmd, sizeof cmd, "rm -rf '%s'", dir);
    ASSERT_EQ_INT(run(cmd, NULL, 0), 0);
}

static void test_all(void)
{
    setup();
    test_summary();
    test_export();
    test_physical();
    test_channel_filter();
    test_hostile_messages();
    test_first_message_bad();
    test_many_channels();
    test_export_many_channels();
    test_export_names_collide();
    test_usage();
    test_extreme_logs();
    test_cleanup();
}

TEST_MAIN(TEST(test_all))

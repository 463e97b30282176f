/* wgfuzz.c - an attacker on the multicast group: a structured, seeded fuzzer
 * of the real wormgeard's inputs (CMD and TICK messages, snapshot files).
 *
 *   wgfuzz WORMGEARD commands [SEED|- [N]]  directed cases for every defect
 *            class, N random hostile cmd_t, every truncation of valid
 *            messages, bit flips, trailing bytes, a burst, hostile ticks
 *   wgfuzz WORMGEARD snapshots [SEED]      every truncation and single-byte
 *            flip of a valid snapshot; FIFO, symlink, directory, oversized
 *   wgfuzz WORMGEARD kill [SEED]           SIGKILL at random moments of
 *            repeated saves: the file is always the old or the new one
 *   wgfuzz WORMGEARD wire [SEED|- [N]]     raw UDP datagrams on the group,
 *            beneath LCM's framing (its udpm: short and fragmented messages):
 *            bad magic, cut headers, unterminated and 60 kB channel names,
 *            impossible fragments, a flood of first fragments of 16-256 MB
 *            messages that never end, N x 10 random datagrams; then the
 *            daemon answers within the limit, its state is the same bytes,
 *            its memory grew less than 64 MB
 *   wgfuzz WORMGEARD commands-keyed [SEED|- [N]]  the commands run against
 *            a daemon with a key (command_key_file), by an attacker without
 *            it: every hostile message refused EAUTH or EDECODE, one ACK
 *            each, nothing changed; every hostile tick refused and told on
 *            STATUS. wgfuzz's own commands and the big tick are signed.
 *
 * Invariants, checked for every message: exactly one ACK, matched on client
 * and seq (an undecodable one: one ACK before the next command's); a refused
 * command changes nothing (the daemon is paused and a full save after it is
 * byte-identical to the one before); every ACK within ACK_LIMIT_MS; no
 * sanitizer report in the daemon's log; SIGTERM -> exit 0. Prints the seed,
 * then the figures (commands, unanswered, state changes by refused
 * commands, slowest and p99 ACK). Run through tests/netns.sh. */
#include "lcmtypes/wormgear_ack_t.h"
#include "lcmtypes/wormgear_cmd_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "lcmtypes/wormgear_tick_t.h"
#include "proc_status.h"
#include "wormgear/wg_key.h"
#include "wormgear/wg_mcast.h"
#include "wormgear/wg_status.h"

#include <arpa/inet.h>
#include <errno.h>
#include <fcntl.h>
#include <lcm/lcm.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/socket.h>
#include <sys/stat.h>
#include <sys/wait.h>
#include <time.h>
#include <unistd.h>

enum { ACK_LIMIT_MS = 1000, MAXMSG = 60000, LOGACK = 8, CLIENT_LIMIT = 256 };

/* ---- the fuzzer's state --------------------------------------------------- */

typedef struct ackrec {
    char client[CLIENT_LIMIT + 64];
    size_t client_len;
    int64_t cmd_seq;
    int accepted, code;
    char codename[24], message[1024];
    double at_ms;
} ackrec;

typedef struct fz {
    const char *bin;
    char url[128], dir[96], log[128], keyfile[128];
    int keyed;                   /* commands-keyed: the daemon has keyfile's key */
    unsigned char key[WG_KEY_BYTES];
    int64_t tick_seq;            /* our own signed ticks' seq */
    pid_t pid;
    lcm_t *lcm;
    uint64_t rng;
    int64_t seq;                 /* our own commands' seq */
    ackrec win[LOGACK];          /* ACKs since the last mark (the window) */
    int nwin, nwin_total;
    long acks_total;
    long foreign_acks;           /* ACKs to another client than ours (the wire's refusals) */
    long tick_acks;              /* ACKs with op "tick": a refused tick's answer (not in win) */
    int64_t tick_ack_seq;        /* the last one's cmd_seq, code and client */
    char tick_ack_code[24], tick_ack_client[64];
    long long st_ticks_lost;     /* the last STATUS's ticks_lost (gaps in the TICK seq) */
    long long st_rx_dropped;     /* ... rx_dropped and cmds_dropped */
    long long st_cmds_dropped, st_handled; /* handled: accepted + refused */
    long long st_ticks_refused;  /* ... ticks_refused, and why the last */
    long long st_steps;
    char st_tick_refusal[600];
    int have_status;
    double lat[200000];
    long nlat;
    long commands, unanswered, extra, changed, failures, accepted, refused;
    double slowest;
    char slowest_what[160];
} fz;

static fz F;
static int g_failed;

static void fail(const char *fmt, ...) __attribute__((format(printf, 1, 2)));
static void fail(const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    fprintf(stderr, "FAIL: ");
    vfprintf(stderr, fmt, ap);
    fputc('\n', stderr);
    va_end(ap);
    F.failures++;
    g_failed = 1;
}

static double now_ms(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return (double)ts.tv_sec * 1e3 + (double)ts.tv_nsec * 1e-6;
}

static uint64_t rnd(void) /* xorshift64*, seeded */
{
    F.rng ^= F.rng >> 12, F.rng ^= F.rng << 25, F.rng ^= F.rng >> 27;
    return F.rng * 2685821657736338717ull;
}

static int rndi(int n) { return (int)(rnd() % (uint64_t)n); }

/* ---- wire encoding of our own, byte by byte (so it can lie) ---------------- */

typedef struct enc {
    unsigned char b[MAXMSG];
    size_t n;
} enc;

static void put_be(enc *e, uint64_t v, int bytes)
{
    for (int i = bytes - 1; i >= 0 && e->n < MAXMSG; i--)
        e->b[e->n++] = (unsigned char)(v >> (8 * i));
}

static void put_i64(enc *e, int64_t v) { put_be(e, (uint64_t)v, 8); }
static void put_i32(enc *e, int32_t v) { put_be(e, (uint32_t)v, 4); }
static void put_i8(enc *e, int8_t v) { put_be(e, (uint8_t)v, 1); }

static void put_f64(enc *e, double d)
{
    uint64_t v;
    memcpy(&v, &d, 8);
    put_be(e, v, 8);
}

/* An LCM string: length (with the NUL), bytes, NUL. `len` bytes of s may
 * hold NULs of their own. */
static void put_strn(enc *e, const char *s, size_t len)
{
    put_i32(e, (int32_t)(len + 1));
    for (size_t i = 0; i < len && e->n < MAXMSG; i++)
        e->b[e->n++] = (unsigned char)s[i];
    put_i8(e, 0);
}

static void put_str(enc *e, const char *s) { put_strn(e, s, strlen(s)); }

/* A cmd_t, every field given (strings as byte runs). */
typedef struct cmdspec {
    int64_t utime, seq;
    const char *client;
    size_t client_len;           /* 0: strlen */
    const char *op;
    size_t op_len;               /* 0: strlen */
    int32_t nparams;
    const char *names[80];
    double values[80];
    int8_t has_from;
    double from, duration;
    const char *unit;
    int64_t nsteps;
    const char *name;
    double rate;
    int8_t at_section;
} cmdspec;

static void encode_cmd(enc *e, const cmdspec *c)
{
    e->n = 0;
    put_i64(e, __wormgear_cmd_t_get_hash());
    put_i64(e, c->utime);
    put_i64(e, c->seq);
    put_strn(e, c->client, c->client_len ? c->client_len : strlen(c->client));
    put_strn(e, c->op, c->op_len ? c->op_len : strlen(c->op));
    put_i32(e, c->nparams);
    for (int i = 0; i < c->nparams; i++)
        put_str(e, c->names[i] ? c->names[i] : "");
    for (int i = 0; i < c->nparams; i++)
        put_f64(e, c->values[i]);
    put_i8(e, c->has_from);
    put_f64(e, c->from);
    put_f64(e, c->duration);
    put_str(e, c->unit ? c->unit : "");
    put_i64(e, c->nsteps);
    put_str(e, c->name ? c->name : "");
    put_f64(e, c->rate);
    put_i8(e, c->at_section);
    put_i32(e, 0); /* mac_len: unsigned */
}

static int64_t now_us(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_REALTIME, &ts);
    return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

/* Keyed: sign one of our own messages as a client with the key does (its
 * utime now, the mac_len 0 encode_cmd ended it with made 32 and the MAC
 * after it). Nothing without a key. */
static void seal_own(enc *e)
{
    if (!F.keyed || e->n < 4 || e->n + WG_MAC_BYTES > MAXMSG)
        return;
    int64_t t = now_us();
    for (int i = 0; i < 8; i++) /* utime: after the 8-byte fingerprint */
        e->b[8 + i] = (unsigned char)((uint64_t)t >> (56 - 8 * i));
    e->n -= 4;
    put_i32(e, WG_MAC_BYTES);
    memset(e->b + e->n, 0, WG_MAC_BYTES);
    e->n += WG_MAC_BYTES;
    wg_mac_seal(F.key, e->b, e->n);
}

/* Our encoder must agree with lcm-gen's on a plain message. */
static void encoder_self_check(void)
{
    char *names[2] = {"omega", "xi_p"};
    double vals[2] = {1.25, 0.1};
    wormgear_cmd_t m = {.utime = 7, .seq = 9, .client = "me", .op = "set", .nparams = 2,
                        .names = names, .values = vals, .has_from = 1, .from = 0.5,
                        .duration = 2, .unit = "s", .nsteps = 3, .name = "n", .rate = 4,
                        .at_section = 1};
    static unsigned char ref[4096];
    int n = wormgear_cmd_t_encode(ref, 0, sizeof ref, &m);
    cmdspec c = {.utime = 7, .seq = 9, .client = "me", .op = "set", .nparams = 2,
                 .names = {"omega", "xi_p"}, .values = {1.25, 0.1}, .has_from = 1, .from = 0.5,
                 .duration = 2, .unit = "s", .nsteps = 3, .name = "n", .rate = 4,
                 .at_section = 1};
    static enc e;
    encode_cmd(&e, &c);
    if (n < 0 || (size_t)n != e.n || memcmp(ref, e.b, e.n) != 0) {
        fprintf(stderr, "wgfuzz: our cmd_t encoder disagrees with lcm-gen's\n");
        exit(2);
    }
}

/* ---- LCM ------------------------------------------------------------------- */

static void on_ack(const lcm_recv_buf_t *rb, const char *ch, const wormgear_ack_t *m, void *u)
{
    (void)rb, (void)ch, (void)u;
    F.acks_total++;
    F.foreign_acks += strcmp(m->client, "fz-self") != 0;
    if (!strcmp(m->op, "tick")) { /* a tick's, counted apart: commands' seqs are others */
        F.tick_acks++;
        F.tick_ack_seq = m->cmd_seq;
        snprintf(F.tick_ack_code, sizeof F.tick_ack_code, "%s", m->code);
        snprintf(F.tick_ack_client, sizeof F.tick_ack_client, "%s", m->client);
        return;
    }
    F.nwin_total++;
    if (F.nwin == LOGACK)
        return;
    ackrec *a = &F.win[F.nwin++];
    a->client_len = strlen(m->client);
    snprintf(a->client, sizeof a->client, "%s", m->client);
    a->cmd_seq = m->cmd_seq;
    a->accepted = m->accepted;
    a->code = m->status;
    snprintf(a->codename, sizeof a->codename, "%s", m->code);
    snprintf(a->message, sizeof a->message, "%s", m->message);
    a->at_ms = now_ms();
}

static void on_status(const lcm_recv_buf_t *rb, const char *ch, const wormgear_status_t *m,
                      void *u)
{
    (void)rb, (void)ch, (void)u;
    F.st_ticks_lost = (long long)m->ticks_lost;
    F.st_rx_dropped = (long long)m->rx_dropped;
    F.st_cmds_dropped = (long long)m->cmds_dropped;
    F.st_handled = (long long)(m->cmds_accepted + m->cmds_refused);
    F.st_ticks_refused = (long long)m->ticks_refused;
    F.st_steps = (long long)m->steps;
    snprintf(F.st_tick_refusal, sizeof F.st_tick_refusal, "%s", m->tick_refusal);
    F.have_status = 1;
}

static void pump(double ms)
{
    double end = now_ms() + ms;
    int fd = lcm_get_fileno(F.lcm);
    while (now_ms() < end) {
        fd_set s;
        FD_ZERO(&s);
        FD_SET(fd, &s);
        struct timeval tv = {0, 2000};
        if (select(fd + 1, &s, NULL, NULL, &tv) > 0)
            lcm_handle(F.lcm);
    }
}

static void publish(const char *suffix, const void *b, size_t n)
{
    char ch[64];
    snprintf(ch, sizeof ch, "FZ_%s", suffix);
    if (lcm_publish(F.lcm, ch, b, (unsigned)n) != 0)
        fail("lcm_publish on %s (%zu bytes) failed", ch, n);
}

static void mark(void) { F.nwin = F.nwin_total = 0; }

/* Wait until an ACK for (our client, seq) is in the window; its index or -1. */
static int wait_for(int64_t seq, double ms)
{
    double end = now_ms() + ms;
    for (;;) {
        for (int i = 0; i < F.nwin; i++)
            if (F.win[i].cmd_seq == seq && !strcmp(F.win[i].client, "fz-self"))
                return i;
        if (now_ms() > end)
            return -1;
        pump(1);
    }
}

/* One command of ours (save/restore/pause/get...) and its ACK; 0 if accepted. */
static int own(const char *op, const char *name, double wait_ms)
{
    cmdspec c = {.seq = ++F.seq, .client = "fz-self", .op = op, .name = name, .unit = ""};
    static enc e;
    encode_cmd(&e, &c);
    seal_own(&e);
    publish("CMD", e.b, e.n);
    int i = wait_for(c.seq, wait_ms);
    if (i < 0) {
        fail("no ACK to our own %s %s", op, name ? name : "");
        return -1;
    }
    return F.win[i].accepted ? 0 : F.win[i].code ? F.win[i].code : -1;
}

/* ---- the daemon ------------------------------------------------------------- */

/* A get of ours; 1 if its ACK came within ms. */
static int get_answered(double ms)
{
    mark();
    cmdspec c = {.seq = ++F.seq, .client = "fz-self", .op = "get", .unit = "", .name = ""};
    static enc e;
    encode_cmd(&e, &c);
    seal_own(&e);
    publish("CMD", e.b, e.n);
    return wait_for(c.seq, ms) >= 0;
}

static void start_daemon(const char *extra)
{
    F.pid = fork();
    if (F.pid == 0) {
        int fd = open(F.log, O_WRONLY | O_CREAT | O_APPEND, 0644);
        if (fd >= 0)
            dup2(fd, 2);
        /* nothing of ours inherited: LCM's socket among it would be the daemon's too,
         * and its filter (WG_MCAST_WHOLE) would drop the fragments big_messages sends us */
        for (int k = 3; k < 1024; k++)
            close(k);
        execl(F.bin, F.bin, "--url", F.url, "--prefix", "FZ_", "--state-dir", F.dir,
              "--start-paused", "--status-hz", "10", "--state-rate-hz", "0", extra,
              F.keyed ? "--command-key-file" : (char *)NULL, F.keyfile, (char *)NULL);
        _exit(127);
    }
    for (int i = 0; i < 200; i++) /* up when it answers a get */
        if (get_answered(50))
            return;
    fail("the daemon did not answer within 10 s");
    exit(1);
}

/* SIGTERM, exit 0, and no sanitizer report in its log. */
static void stop_daemon(void)
{
    int st = 0;
    kill(F.pid, SIGTERM);
    for (int i = 0; i < 500 && waitpid(F.pid, &st, WNOHANG) == 0; i++)
        usleep(10000);
    if (waitpid(F.pid, &st, WNOHANG) == 0) {
        fail("the daemon did not stop on SIGTERM within 5 s");
        kill(F.pid, SIGKILL);
        waitpid(F.pid, &st, 0);
    } else if (!WIFEXITED(st) || WEXITSTATUS(st) != 0) {
        fail("the daemon ended with %s %d, not exit 0", WIFEXITED(st) ? "exit" : "signal",
             WIFEXITED(st) ? WEXITSTATUS(st) : WTERMSIG(st));
    }
    F.pid = 0;
    FILE *f = fopen(F.log, "r");
    char line[2048];
    while (f && fgets(line, sizeof line, f))
        if (strstr(line, "AddressSanitizer") || strstr(line, "runtime error:") ||
            strstr(line, "LeakSanitizer"))
            fail("sanitizer report in the daemon's log: %s", line);
    if (f)
        fclose(f);
}

/* Bytes of a file in the state directory (NULL if absent); *n its size. */
static unsigned char *slurp(const char *name, size_t *n)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", F.dir, name);
    FILE *f = fopen(path, "rb");
    if (!f)
        return NULL;
    unsigned char *b = malloc(1 << 21);
    *n = b ? fread(b, 1, 1 << 21, f) : 0;
    fclose(f);
    return b;
}

static int same_file(const char *a, const char *b)
{
    size_t na = 0, nb = 0;
    unsigned char *x = slurp(a, &na), *y = slurp(b, &nb);
    int same = x && y && na == nb && memcmp(x, y, na) == 0;
    free(x);
    free(y);
    return same;
}

/* Back to the base state: paused, the base snapshot, pre = base again. */
static void rebase(void)
{
    mark();
    own("pause", "", 3000);
    own("reset", "", 3000); /* cancels a pending step or set */
    own("restore", "fzbase", 3000);
    own("save", "fzpre", 3000);
}

/* ---- one hostile message ------------------------------------------------------ */

typedef struct expect {
    int code;             /* expected status code; 1 = any refusal; 2 = anything */
    const char *has;      /* the message must contain this (NULL: no check) */
    const char *lacks;    /* ... and must not contain this */
    const char *client;   /* expected echo of the client (NULL: don't check) */
    size_t client_len;
} expect;

static void record_latency(double ms, const char *what)
{
    if (F.nlat < (long)(sizeof F.lat / sizeof F.lat[0]))
        F.lat[F.nlat++] = ms;
    if (ms > F.slowest) {
        F.slowest = ms;
        snprintf(F.slowest_what, sizeof F.slowest_what, "%s", what);
    }
    if (ms > ACK_LIMIT_MS)
        fail("%s: ACK after %.0f ms (limit %d ms)", what, ms, ACK_LIMIT_MS);
}

/* Send bytes on CMD, then our own save: exactly one ACK must come before
 * that save's; if refused, the saved state equals the one before. */
static void hostile(const char *what, const void *b, size_t n, const expect *x)
{
    F.commands++;
    mark();
    double t0 = now_ms();
    publish("CMD", b, n);
    int64_t sync = F.seq + 1;
    if (own("save", "fzpost", 5000) != 0 && F.nwin == 0) {
        F.unanswered++;
        fail("%s: no ACK at all, and none to the save after it: the daemon stopped answering",
             what);
        return;
    }
    int k = wait_for(sync, 0);
    if (k < 0)
        return;
    if (k == 0) {
        F.unanswered++;
        fail("%s: no ACK (exactly one expected)", what);
        return;
    }
    if (k > 1) {
        F.extra += k - 1;
        fail("%s: %d ACKs (exactly one expected)", what, k);
    }
    ackrec *a = &F.win[0];
    record_latency(a->at_ms - t0, what);
    a->accepted ? F.accepted++ : F.refused++;
    expect kx = {2, NULL, NULL, x ? x->client : NULL, x ? x->client_len : 0};
    if (F.keyed) { /* an attacker without the key: nothing gets past the door */
        if (a->accepted || (a->code != WG_EAUTH && a->code != WG_EDECODE))
            fail("%s, unsigned to a daemon with a key: %s (%d) '%s', expected EAUTH or EDECODE",
                 what, a->codename, a->code, a->message);
        x = &kx; /* the client echo still checked, the refusal's text is the door's */
    }
    if (x && x->code != 2 && ((x->code == 1 && a->accepted) || (x->code <= 0 && a->code != x->code)))
        fail("%s: %s (%d) '%s', expected code %d", what, a->codename, a->code, a->message,
             x->code);
    if (x && x->has && !strstr(a->message, x->has))
        fail("%s: message '%s' lacks '%s'", what, a->message, x->has);
    if (x && x->lacks && strstr(a->message, x->lacks))
        fail("%s: message '%s' contains '%s'", what, a->message, x->lacks);
    if (x && x->client) {
        size_t want = x->client_len ? x->client_len : strlen(x->client);
        if (a->client_len != want || memcmp(a->client, x->client, want) != 0)
            fail("%s: ACK client (%zu bytes) is not the %zu bytes expected: '%.80s'", what,
                 a->client_len, want, a->client);
    }
    if (!a->accepted && !same_file("fzpre.wgstate", "fzpost.wgstate")) {
        F.changed++;
        fail("%s: refused (%s: %s) but the state changed", what, a->codename, a->message);
        rebase();
    } else if (a->accepted) {
        rebase();
    }
}

static void hostile_cmd(const char *what, cmdspec *c, const expect *x)
{
    static enc e;
    c->seq = c->seq ? c->seq : 1000000 + F.commands;
    if (!c->client)
        c->client = "fz-attacker";
    c->unit = c->unit ? c->unit : "";
    c->name = c->name ? c->name : "";
    encode_cmd(&e, c);
    hostile(what, e.b, e.n, x);
}

/* ---- the classes ------------------------------------------------------------- */

static const expect ANY = {2, NULL, NULL, NULL, 0}, REFUSED = {1, NULL, NULL, NULL, 0};

/* defect 9 first, before the log's rate limit engages: names outside the
 * alphabet, a newline that would forge a log line. */
static void directed_names(void)
{
    /* defect 9: names outside the alphabet, a newline forging a log line */
    static const char *names[] = {"a\n<3>FORGED log line", "../etc/x", ".hidden", "a/b", "",
                                  "m\xc3\xbc", "aaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaaa"};
    for (unsigned i = 0; i < sizeof names / sizeof names[0]; i++) {
        cmdspec s = {.op = i % 2 ? "restore" : "save", .name = names[i]};
        expect x = {-1, "[A-Za-z0-9_.-]", NULL, NULL, 0};
        hostile_cmd("save/restore name outside the alphabet", &s, &x);
    }
}

static void directed_ramps(void)
{
    /* defect 1: a ramp naming two or more parameters */
    for (int n = 2; n <= 40; n += 19) {
        cmdspec c = {.op = "ramp", .nparams = n, .duration = 5, .unit = "tau"};
        for (int i = 0; i < n; i++)
            c.names[i] = i % 2 ? "xi_p" : "omega", c.values[i] = 1.1;
        expect x = {-1, "exactly one", NULL, NULL, 0};
        hostile_cmd("ramp with several names", &c, &x);
    }
    /* defect 2: denormal, zero, huge, non-finite durations; the limits named */
    static const double dur[] = {4.94e-324, 1e-310, 0, -1, 1e300, INFINITY, NAN, 2e15};
    for (unsigned i = 0; i < sizeof dur / sizeof dur[0]; i++) {
        cmdspec c = {.op = "ramp", .nparams = 1, .names = {"xi_p"}, .values = {0.1},
                     .duration = dur[i], .unit = "tau"};
        expect x = {1, "1e+15", NULL, NULL, 0};
        char w[64];
        snprintf(w, sizeof w, "ramp duration %g tau", dur[i]);
        hostile_cmd(w, &c, &x);
        c.unit = "s";
        snprintf(w, sizeof w, "ramp duration %g s", dur[i]);
        hostile_cmd(w, &c, &REFUSED);
    }
    /* a bad `from` is reported as the from */
    cmdspec c = {.op = "ramp", .nparams = 1, .names = {"omega"}, .values = {1.2},
                 .has_from = 1, .from = 99, .duration = 5, .unit = "tau"};
    expect x = {-2, "from", NULL, NULL, 0};
    hostile_cmd("ramp from out of range", &c, &x);
    /* bounds printed so that a value just outside looks outside */
    cmdspec d = {.op = "set", .nparams = 1, .names = {"phi1"}, .values = {6.2831853071795871}};
    expect y = {-2, "6.283185307179586", NULL, NULL, 0};
    hostile_cmd("set phi1 = 2 pi + 1 ulp", &d, &y);
    cmdspec e = {.op = "ramp", .nparams = 0, .duration = 5, .unit = "tau"};
    expect z = {-1, "exactly one", NULL, NULL, 0};
    hostile_cmd("ramp with no name", &e, &z);
}

static void directed_clients(void)
{
    static char big[5001];
    memset(big, 'c', sizeof big - 1);
    static const size_t lens[] = {71, 72, 255, 256};
    for (unsigned i = 0; i < sizeof lens / sizeof lens[0]; i++) {
        cmdspec c = {.op = "get", .client = big, .client_len = lens[i]};
        expect x = {0, NULL, NULL, big, lens[i]};
        hostile_cmd("get with a long client id", &c, &x);
        cmdspec s = {.op = "step", .nsteps = 3, .client = big, .client_len = lens[i]};
        hostile_cmd("step with a long client id", &s, &x);
    }
    static const size_t over[] = {257, 4095, 4096, 5000};
    for (unsigned i = 0; i < sizeof over / sizeof over[0]; i++) {
        cmdspec c = {.op = "get", .client = big, .client_len = over[i]};
        expect x = {1, "256", NULL, big, CLIENT_LIMIT};
        hostile_cmd("get with a client id over the limit", &c, &x);
    }
    static const char *odd[] = {"rig@m\xc3\xbcller", "tab\there", "ctl\x01\x02\x7f", "\xff\xfe"};
    for (unsigned i = 0; i < sizeof odd / sizeof odd[0]; i++) {
        cmdspec c = {.op = "get", .client = odd[i]};
        expect x = {0, NULL, NULL, odd[i], 0};
        hostile_cmd("get with a UTF-8/control client id", &c, &x);
        cmdspec s = {.op = "set", .nparams = 1, .names = {"omega"}, .values = {1.1},
                     .at_section = 1, .client = odd[i]};
        hostile_cmd("set at section with an odd client id", &s, &x);
    }
}

static void directed_misc(void)
{
    cmdspec get = {.op = "get"};
    static enc e;
    encode_cmd(&e, &(cmdspec){.seq = 777, .client = "fz-attacker", .op = "get", .unit = "",
                              .name = ""});
    /* defect 11: trailing bytes; an op with a NUL inside */
    memcpy(e.b + e.n, "junkjunk", 8);
    expect td = {-9, "bytes after the end", NULL, "fz-attacker", 0};
    hostile("get with trailing bytes", e.b, e.n + 8, &td);
    get.op = "get\0junk";
    get.op_len = 8;
    hostile_cmd("op 'get\\0junk'", &get, &REFUSED);
    /* steps and modes at their edges */
    static const int64_t ns[] = {0, -1, INT64_MIN, INT64_MAX, 1000000000001LL};
    for (unsigned i = 0; i < sizeof ns / sizeof ns[0]; i++) {
        cmdspec s = {.op = "step", .nsteps = ns[i]};
        hostile_cmd("step out of range", &s, &REFUSED);
    }
    static const double rates[] = {NAN, -1, 1e-300, 4.94e-324, 1e9, INFINITY};
    for (unsigned i = 0; i < sizeof rates / sizeof rates[0]; i++) {
        cmdspec s = {.op = "mode", .name = "realtime", .rate = rates[i]};
        expect x = {1, "[1e-06, 1000]", NULL, NULL, 0};
        hostile_cmd("mode with a bad rate", &s, &x);
    }
}

/* Values an attacker tries. */
static double hostile_value(void)
{
    static const double v[] = {NAN, INFINITY, -INFINITY, 4.94e-324, -4.94e-324, 1e-310, 0.0,
                               -0.0, 1e308, -1e308, 1e15, 0.01, 10, 2.5, 0.08, 1.0, 6.2831853071795871,
                               -6.2831853071795871, 1e-9, 0.95, 100, 1000};
    return v[rndi(sizeof v / sizeof v[0])];
}

static const char *hostile_name(void)
{
    static const char *n[] = {"omega", "xi_p", "k_a", "phi1", "a1", "mu1", "k1x", "b", "b_j",
                              "f_m", "nope", "", "OMEGA", "omega ", "xi_p\x01", "e_m", "phi",
                              "z1", "z2", "rho1", "j2"}; /* body rows: whole numbers, > 0 */
    return n[rndi(sizeof n / sizeof n[0])];
}

static void random_cmds(long n)
{
    static const char *ops[] = {"set", "ramp", "pause", "reset", "step", "save", "restore",
                                "get", "mode", "", "SET", "resume", "\xc3\xa9", "set ",
                                "contacts"};
    static const char *units[] = {"s", "tau", "", "ms", "S", "tau\n"};
    static const char *modes[] = {"realtime", "fast", "lockstep", "", "warp", "params",
                                  "all", "mesh", "none", "MESH"};
    for (long i = 0; i < n; i++) {
        cmdspec c = {.op = ops[rndi(sizeof ops / sizeof ops[0])], .seq = (int64_t)rnd()};
        c.nparams = rndi(4) == 0 ? rndi(70) - 2 : 1 + rndi(3);
        int np = c.nparams < 0 ? 0 : c.nparams > 64 ? 64 : c.nparams;
        for (int j = 0; j < np; j++)
            c.names[j] = hostile_name(), c.values[j] = hostile_value();
        if (c.nparams > 64)
            c.nparams = 64 + rndi(2); /* 65: over the wire limit, still well-formed */
        c.has_from = (int8_t)rndi(3);
        c.from = hostile_value(), c.duration = hostile_value();
        c.unit = units[rndi(sizeof units / sizeof units[0])];
        c.nsteps = rndi(3) ? 1 + rndi(1000) : (int64_t)rnd();
        c.name = rndi(2) ? modes[rndi(sizeof modes / sizeof modes[0])] : "fzpre";
        c.rate = hostile_value();
        c.at_section = (int8_t)(rndi(4) == 0 ? rnd() : (uint64_t)rndi(2));
        hostile_cmd(c.op, &c, &ANY);
    }
}

/* Every truncation of a few valid messages, bit flips, a wrong fingerprint. */
static void raw_mutations(long flips)
{
    cmdspec base[3] = {
        {.seq = 42, .client = "fz-raw", .op = "set", .nparams = 2, .names = {"omega", "xi_p"},
         .values = {1.3, 0.1}, .unit = "", .name = ""},
        {.seq = 43, .client = "fz-raw", .op = "ramp", .nparams = 1, .names = {"omega"},
         .values = {1.4}, .duration = 10, .unit = "tau", .name = ""},
        {.seq = 44, .client = "fz-raw", .op = "save", .unit = "", .name = "fzpre"}};
    static enc e;
    for (int m = 0; m < 3; m++) {
        encode_cmd(&e, &base[m]);
        for (size_t len = 0; len < e.n; len++)
            hostile("truncated message", e.b, len, &REFUSED);
    }
    for (long i = 0; i < flips; i++) {
        encode_cmd(&e, &base[rndi(3)]);
        size_t at = (size_t)rndi((int)e.n);
        e.b[at] ^= (unsigned char)(1u << rndi(8));
        hostile("bit flip", e.b, e.n, &ANY);
    }
    encode_cmd(&e, &base[0]);
    e.b[3] ^= 0x10;
    expect fp = {-9, "fingerprint", NULL, NULL, 0};
    hostile("wrong fingerprint", e.b, e.n, &fp);
}

/* defect 5: a burst of gets, n in ms milliseconds, all answered (or what
 * the kernel dropped counted on STATUS). */
static void burst(int n, double ms)
{
    static enc e;
    mark();
    pump(300); /* a STATUS before */
    long before = F.acks_total;
    long long handled0 = F.st_handled;
    double t0 = now_ms();
    for (int i = 0; i < n; i++) {
        encode_cmd(&e, &(cmdspec){.seq = 5000000 + i, .client = "fz-burst", .op = "get",
                                  .unit = "", .name = ""});
        publish("CMD", e.b, e.n);
        if (i % 50 == 49) { /* batches of 50, sleeping (not spinning) to keep the pace */
            double wait = t0 + ms * (i + 1) / n - now_ms();
            if (wait > 0)
                usleep((useconds_t)(wait * 1e3));
        }
    }
    double end = now_ms() + 10000;
    while (F.acks_total - before < n && now_ms() < end)
        pump(5);
    pump(600); /* a STATUS after it */
    long got = F.acks_total - before;
    long long handled = F.st_handled - handled0;
    printf("burst: %d get in %.0f ms: the daemon answered %lld, %ld ACKs reached us; STATUS "
           "cmds_dropped %lld, rx_dropped %lld\n", n, ms, handled, got, F.st_cmds_dropped,
           F.st_rx_dropped);
    if (handled != n)
        fail("burst: the daemon answered %lld of %d commands", handled, n);
}

/* defects 3 and 6: hostile ticks; a get answered while a big tick runs.
 * Keyed, every hostile tick is also unsigned: refused, its seq not counted
 * as a gap (a forger's seq says nothing), and only our signed tick runs. */
static void ticks(void)
{
    mark();
    own("mode", "lockstep", 3000);
    own("resume", "", 3000);
    pump(300); /* a STATUS before */
    long long refused0 = F.st_ticks_refused, lost0 = F.st_ticks_lost;
    long acks0 = F.tick_acks;
    static const int64_t seqs[] = {0, INT64_MAX, INT64_MIN, 5, 1000000000005LL, -7, 6};
    int nbad = 0;
    for (unsigned i = 0; i < sizeof seqs / sizeof seqs[0]; i++) {
        wormgear_tick_t t = {.utime = 1, .seq = seqs[i], .nsteps = 1 + (int64_t)i,
                             .client = (char *)"wgfuzz"};
        unsigned char b[64];
        int n = wormgear_tick_t_encode(b, 0, sizeof b, &t);
        publish("TICK", b, (size_t)n);
        nbad += F.keyed;
    }
    pump(700);
    long long lost = F.have_status ? F.st_ticks_lost : -1;
    printf("ticks: STATUS ticks_lost %lld after hostile tick seqs\n", lost);
    if (lost < 0 || lost > 1000)
        fail("hostile tick seqs: ticks_lost %lld (one gap must count at most a bound)", lost);
    if (F.keyed && lost != lost0)
        fail("unsigned ticks' seqs counted as gaps: ticks_lost %lld, was %lld", lost, lost0);
    /* ticks no driver may send, each refused and told (STATUS ticks_refused
     * and tick_refusal) and answered (one ACK, op "tick", each); seqs 7 ...
     * 11 in order, so no gap is counted */
    static const int64_t bad_steps[] = {0, -1, INT64_MIN, INT64_MAX, 10000001};
    unsigned char b[128], cut[128];
    int n = 0;
    for (unsigned i = 0; i < sizeof bad_steps / sizeof bad_steps[0]; i++, nbad++) {
        wormgear_tick_t t = {.utime = 1, .seq = 7 + (int64_t)i, .nsteps = bad_steps[i],
                             .client = (char *)"wgfuzz"};
        n = wormgear_tick_t_encode(b, 0, sizeof b, &t);
        publish("TICK", b, (size_t)n);
    }
    for (int len = 1; len < n; len += 7, nbad++) /* cut short anywhere: undecodable */
        publish("TICK", b, (size_t)len);
    memcpy(cut, b, (size_t)n);
    cut[n] = 0x5a; /* a byte after its end */
    publish("TICK", cut, (size_t)n + 1), nbad++;
    cut[32] ^= 0x80; /* the client's length huge */
    publish("TICK", cut, (size_t)n), nbad++;
    pump(700);
    long long told = F.st_ticks_refused - refused0;
    printf("ticks: %lld of %d hostile ticks refused on STATUS; the last: %s\n", told, nbad,
           F.st_tick_refusal);
    if (told != nbad)
        fail("hostile ticks: STATUS ticks_refused grew by %lld, want %d", told, nbad);
    if (!strstr(F.st_tick_refusal, "undecodable TICK message (47 bytes) ignored: ") ||
        !strstr(F.st_tick_refusal, "client"))
        fail("hostile ticks: STATUS tick_refusal does not say why: '%s'", F.st_tick_refusal);
    long answered = F.tick_acks - acks0;
    printf("ticks: %ld of %d hostile ticks answered on ACK; the last %s, seq %lld, client "
           "'%.20s'\n", answered, nbad, F.tick_ack_code, (long long)F.tick_ack_seq,
           F.tick_ack_client);
    if (answered != nbad)
        fail("hostile ticks: %ld ACKs with op tick, want one each refused: %d", answered, nbad);
    if (strcmp(F.tick_ack_code, "EDECODE") || F.tick_ack_seq != 11 || F.tick_ack_client[0])
        fail("hostile ticks: the last answer is %s for seq %lld, client '%.20s'; want EDECODE "
             "for seq 11, client '' (what its bytes still say: the id's length is negative)",
             F.tick_ack_code, (long long)F.tick_ack_seq, F.tick_ack_client);
    if (F.st_ticks_lost != lost)
        fail("hostile ticks counted as lost ticks: ticks_lost %lld, was %lld", F.st_ticks_lost,
             lost);
    long long steps0 = F.st_steps;
    unsigned char zero[WG_MAC_BYTES] = {0};
    wormgear_tick_t t = {.utime = F.keyed ? now_us() : 1, .seq = F.keyed ? ++F.tick_seq : 12,
                         .nsteps = 10000000, .client = (char *)(F.keyed ? "fz-self" : "wgfuzz"),
                         .mac_len = F.keyed ? WG_MAC_BYTES : 0, .mac = zero};
    n = wormgear_tick_t_encode(b, 0, sizeof b, &t);
    if (F.keyed)
        wg_mac_seal(F.key, b, (size_t)n);
    publish("TICK", b, (size_t)n);
    double worst = 0;
    for (int i = 0; i < 20; i++) { /* rigs poll while the daemon steps */
        mark();
        double t0 = now_ms();
        if (own("get", "", 5000) == 0)
            worst = fmax(worst, F.win[F.nwin - 1].at_ms - t0);
        pump(20);
    }
    printf("ticks: slowest get while a 1e7-step tick runs: %.1f ms; %lld steps run\n", worst,
           F.st_steps - steps0);
    record_latency(worst, "get during a 1e7-step tick");
    if (F.st_steps <= steps0)
        fail("the 1e7-step tick%s ran no step (STATUS steps %lld, was %lld)",
             F.keyed ? ", signed," : "", F.st_steps, steps0);
    if (F.tick_acks != acks0 + answered)
        fail("the 1e7-step tick%s taken, but answered: %s", F.keyed ? ", signed," : "",
             F.tick_ack_code);
    own("pause", "", 3000);
    own("mode", "realtime", 3000);
    rebase();
}

/* ---- snapshot files ------------------------------------------------------------- */

static void put_file(const char *name, const unsigned char *b, size_t n)
{
    char path[256];
    snprintf(path, sizeof path, "%s/%s", F.dir, name);
    FILE *f = fopen(path, "wb");
    if (!f || fwrite(b, 1, n, f) != n)
        fail("cannot write %s", path);
    if (f)
        fclose(f);
}

static void restore_expect_refusal(const char *what, const expect *x)
{
    cmdspec c = {.op = "restore", .name = "fzbad"};
    hostile_cmd(what, &c, x);
}

static void snapshots(void)
{
    size_t n = 0;
    unsigned char *good = slurp("fzbase.wgstate", &n), *b = malloc(n + 16);
    if (!good || !b) {
        fail("no base snapshot");
        return;
    }
    long before = F.failures;
    for (size_t len = 0; len < n; len++) {
        put_file("fzbad.wgstate", good, len);
        restore_expect_refusal("restore of a truncated snapshot", &REFUSED);
    }
    printf("snapshots: %zu truncations, %ld failures\n", n, F.failures - before);
    before = F.failures;
    for (size_t at = 0; at < n; at++) {
        memcpy(b, good, n);
        b[at] ^= (unsigned char)(1u << rndi(8));
        put_file("fzbad.wgstate", b, n);
        restore_expect_refusal("restore of a snapshot with one byte flipped", &REFUSED);
    }
    printf("snapshots: %zu single-byte flips, %ld failures\n", n, F.failures - before);
    put_file("fzbad.wgstate", good, n); /* control: the intact file restores */
    cmdspec c = {.op = "restore", .name = "fzbad"};
    expect ok = {0, NULL, NULL, NULL, 0};
    hostile_cmd("restore of the intact snapshot", &c, &ok);
    free(good);
    free(b);
}

static void special_files(void)
{
    char path[256];
    snprintf(path, sizeof path, "%s/fzbad.wgstate", F.dir);
    unlink(path);
    if (mkfifo(path, 0600) == 0) {
        expect x = {1, "regular file", NULL, NULL, 0};
        restore_expect_refusal("restore of a FIFO", &x);
    }
    unlink(path);
    if (symlink("/etc/passwd", path) == 0) {
        expect x = {1, NULL, "root:", NULL, 0};
        restore_expect_refusal("restore of a symlink to /etc/passwd", &x);
    }
    unlink(path);
    if (mkdir(path, 0700) == 0) {
        expect x = {1, "regular file", "missing parameter", NULL, 0};
        restore_expect_refusal("restore of a directory", &x);
    }
    rmdir(path);
    unsigned char *big = calloc(1, 2 << 20);
    if (big) {
        memset(big, '#', 2 << 20);
        put_file("fzbad.wgstate", big, 2 << 20);
        expect x = {1, "bytes (limit", NULL, NULL, 0};
        restore_expect_refusal("restore of a 2 MB file", &x);
        free(big);
    }
    unlink(path);
}

/* defect 9: nothing the attacker wrote became a line of its own in the log. */
/* The daemon reads the header of every STATUS on its own channel (one it
 * did not send is a second daemon): forged ones of every shape — random
 * bytes, headers cut short, well-formed with absurd seq and utime — are
 * noticed (its warning, rate-limited), change nothing, and it answers on.
 * Our own STATUS handler decodes what is well formed only (a wrong
 * fingerprint or a cut header ends the generated decoder first). */
static void forged_statuses(void)
{
    static const int64_t odd[] = {INT64_MIN, INT64_MAX, -1, 0, 1};
    unsigned char b[512];
    double z[6] = {0};
    for (int i = 0; i < 300; i++) {
        size_t n;
        if (i % 3 == 0) { /* random bytes: another fingerprint */
            n = (size_t)rndi(64);
            for (size_t k = 0; k < n; k++)
                b[k] = (unsigned char)rnd();
            b[0] ^= 0x5a; /* never the status_t fingerprint */
        } else {
            wormgear_status_t m = {.utime = i % 2 ? odd[rndi(5)] : (int64_t)rnd(),
                                   .seq = i % 2 ? (int64_t)rnd() : odd[rndi(5)], .scene = "x",
                                   .mode = "lockstep", .run = "running", .health = "ok",
                                   .fault = "", .tick_refusal = "", .motion = "",
                                   .nbearing = 6, .bearing_impacts_per_period = z,
                                   .bearing_impact_vmax = z, .regime = ""};
            int e = wormgear_status_t_encode(b, 0, sizeof b, &m);
            n = e < 0 ? 0 : i % 3 == 1 ? (size_t)e : (size_t)rndi(24); /* whole, or cut */
        }
        publish("STATUS", b, n);
    }
    pump(300);
    mark();
    if (own("get", "", 3000) != 0)
        fail("after 300 forged STATUS messages the daemon did not answer a get");
    FILE *f = fopen(F.log, "r");
    char line[4096];
    int warned = 0;
    while (f && fgets(line, sizeof line, f))
        warned += strstr(line, "another sender publishes STATUS on FZ_STATUS") != NULL;
    if (f)
        fclose(f);
    printf("forged STATUS: 300 sent, the daemon answered on and warned %d times\n", warned);
    if (warned < 1 || warned > 10)
        fail("forged STATUS messages: %d warnings in the daemon's log (want 1 to 10: noticed, "
             "rate-limited)", warned);
}

static void log_not_forged(void)
{
    FILE *f = fopen(F.log, "r");
    char line[4096];
    while (f && fgets(line, sizeof line, f))
        if (!strncmp(line, "<3>FORGED", 9) || !strncmp(line, "FORGED", 6))
            fail("a forged line reached the daemon's log: %s", line);
    if (f)
        fclose(f);
}

/* ---- SIGKILL during saves ------------------------------------------------------ */

/* Our own one-parameter set (not a hostile command: no rebase after it). */
static void own_set(const char *name, double v)
{
    cmdspec c = {.seq = ++F.seq, .client = "fz-self", .op = "set", .nparams = 1,
                 .names = {name}, .values = {v}, .unit = "", .name = ""};
    static enc e;
    encode_cmd(&e, &c);
    seal_own(&e);
    publish("CMD", e.b, e.n);
    if (wait_for(c.seq, 3000) < 0)
        fail("no ACK to our own set %s", name);
}

static int stale_tmp_files(void)
{
    char cmd[300];
    snprintf(cmd, sizeof cmd, "ls %s | grep -c '\\.tmp\\.' > %s/tmpcount", F.dir, F.dir);
    if (system(cmd) < 0)
        return 0;
    size_t nt = 0;
    unsigned char *t = slurp("tmpcount", &nt);
    int n = t ? atoi((char *)t) : 0;
    free(t);
    return n;
}

/* Each round: the state changes, its snapshot is taken as the reference
 * "new", then a save over the old file is killed at a random moment: the
 * file must be the old one or the new one, whole; a restart leaves no
 * temporary file behind and restores it. */
static void kill_during_saves(int rounds)
{
    int olds = 0, news = 0, absent = 0;
    for (int r = 0; r < rounds; r++) {
        mark();
        own_set("xi_p", 0.05 + 0.001 * r);
        own("save", "fzN", 3000);
        size_t no = 0, nn = 0, nk = 0;
        unsigned char *o = slurp("fzK.wgstate", &no), *nw = slurp("fzN.wgstate", &nn);
        static enc e;
        encode_cmd(&e, &(cmdspec){.seq = 9000000 + r, .client = "fz-kill", .op = "save",
                                  .name = "fzK", .unit = ""});
        publish("CMD", e.b, e.n);
        usleep((useconds_t)rndi(4000));
        kill(F.pid, SIGKILL);
        waitpid(F.pid, NULL, 0);
        unsigned char *k = slurp("fzK.wgstate", &nk);
        if (!k && !o)
            absent++;
        else if (k && o && nk == no && !memcmp(k, o, no))
            olds++;
        else if (k && nw && nk == nn && !memcmp(k, nw, nn))
            news++;
        else
            fail("round %d: after a killed save the file is neither the old nor the new one "
                 "(%zu bytes)", r, nk);
        free(o), free(nw), free(k);
        start_daemon("--verbose=no");
        if (stale_tmp_files())
            fail("round %d: stale *.tmp.* files in the state directory after a restart", r);
        mark();
        if (nk && own("restore", "fzK", 3000) != 0)
            fail("round %d: the file a killed save left does not restore", r);
    }
    printf("kill: %d rounds: file old %d, new %d, absent %d\n", rounds, olds, news, absent);
}

/* ---- main ---------------------------------------------------------------------- */

/* ---- beneath LCM: raw datagrams on the group ------------------------------------ */

enum { LC_SHORT = 0x4c433032, LC_LONG = 0x4c433033 }; /* "LC02", "LC03" (LCM's udpm) */

/* One LC03 fragment: header (seqno, msg_size, offset, no, count), the
 * channel name when no is 0, then len payload bytes. */
static size_t frag(unsigned char *b, uint32_t seqno, uint32_t size, uint32_t off, uint16_t no,
                   uint16_t count, const char *ch, size_t len)
{
    uint32_t h[4] = {htonl(LC_LONG), htonl(seqno), htonl(size), htonl(off)};
    uint16_t k[2] = {htons(no), htons(count)};
    memcpy(b, h, 16), memcpy(b + 16, k, 4);
    size_t n = 20;
    if (!no)
        memcpy(b + n, ch, strlen(ch) + 1), n += strlen(ch) + 1;
    for (size_t i = 0; i < len; i++)
        b[n++] = (unsigned char)rnd();
    return n;
}

/* Whole messages LCM fragments (channel, NUL and data over 65,499 bytes on
 * Linux, in fragments of 65,487) still arrive through wg_mcast_guard's
 * filter, among them one whose first fragment, with its channel, is longer
 * than msg_size, which counts only the data. */
static void on_big(const lcm_recv_buf_t *rb, const char *ch, void *u)
{
    (void)ch;
    ((long *)u)[0]++, ((long *)u)[1] += (long)rb->data_size;
}

static void big_messages(void)
{
    static unsigned char big[200000];
    const unsigned sizes[] = {65483, 65600, 200000}; /* the channel and its NUL: 18 */
    long got[2] = {0, 0}, want = 0;
    lcm_subscription_t *sub = lcm_subscribe(F.lcm, "FZ_BIG_MESSAGES_1", on_big, got);
    for (size_t i = 0; i < sizeof sizes / sizeof sizes[0]; i++)
        publish("BIG_MESSAGES_1", big, sizes[i]), want += sizes[i];
    for (int i = 0; i < 100 && got[0] < 3; i++)
        pump(30);
    lcm_unsubscribe(F.lcm, sub);
    if (got[0] != 3 || got[1] != want)
        fail("wire: %ld of 3 fragmented messages arrived (%ld of %ld bytes)", got[0], got[1],
             want);
}

/* The daemon keeps no fragment (its socket filter is WG_MCAST_WHOLE): a
 * command longer than one datagram holds, sent by LCM in two fragments, is
 * never decoded; nor is a message LCM would count whole from a repeated
 * fragment, its third part never sent (LCM 1.3.1 counts fragments, not
 * which ones came, and hands on the buffer with that part as the heap left
 * it). A daemon that kept checked fragments answered both (2 ACKs). Now
 * neither gets an ACK. */
static void fragmented_cmds(int s, const struct sockaddr_in *to)
{
    static char name[4001];
    memset(name, 'n', sizeof name - 1);
    char *names[17];
    double values[17];
    for (int i = 0; i < 17; i++)
        names[i] = name, values[i] = 1.0;
    wormgear_cmd_t c = {.utime = now_us(), .seq = 7, .client = (char *)"fz-fragmented",
                        .op = (char *)"set", .nparams = 17, .names = names, .values = values,
                        .unit = (char *)"", .name = (char *)""};
    static unsigned char b[80000];
    int n = wormgear_cmd_t_encode(b, 0, sizeof b, &c);
    long a0 = F.acks_total;
    publish("CMD", b, (size_t)n); /* about 68 kB: two fragments */
    size_t m = frag(b, 900, 3000, 0, 0, 3, "FZ_CMD", 1000); /* fragments 0, 1, 1 of 3 */
    sendto(s, b, m, 0, (const struct sockaddr *)to, sizeof *to);
    for (int k = 0; k < 2; k++) {
        m = frag(b, 900, 3000, 1000, 1, 3, "FZ_CMD", 1000);
        sendto(s, b, m, 0, (const struct sockaddr *)to, sizeof *to);
    }
    pump(1500);
    if (F.acks_total != a0)
        fail("wire: %ld ACKs to fragmented commands (a %d-byte set in two fragments, a message "
             "of fragments 0, 1, 1 of 3): the daemon took fragments", F.acks_total - a0, n);
}

static void wire(long n)
{
    big_messages();
    static unsigned char b[65536];
    int port = atoi(strrchr(F.url, ':') + 1), s = socket(AF_INET, SOCK_DGRAM, 0);
    unsigned char ttl = 0, loop = 1;
    struct sockaddr_in to = {.sin_family = AF_INET, .sin_port = htons((uint16_t)port)};
    inet_pton(AF_INET, "239.255.76.67", &to.sin_addr);
    if (s < 0 || setsockopt(s, IPPROTO_IP, IP_MULTICAST_TTL, &ttl, 1) ||
        setsockopt(s, IPPROTO_IP, IP_MULTICAST_LOOP, &loop, 1)) {
        fail("wire: no UDP socket: %s", strerror(errno));
        return;
    }
    fragmented_cmds(s, &to);
#define SEND(len) (sendto(s, b, (len), 0, (struct sockaddr *)&to, sizeof to) >= 0 ? sent++ : 0)
    long sent = 0, rss0 = proc_status_kb(F.pid, "VmRSS"), acks0 = F.foreign_acks;
    uint32_t hs[2] = {htonl(LC_SHORT), htonl(1)};
    /* short messages: cut headers, bad magic, no NUL in the channel, a 60 kB name */
    for (size_t len = 0; len <= 8; len++)
        memcpy(b, hs, 8), SEND(len);
    memcpy(b, hs, 8), memcpy(b + 8, "FZ_CMD", 6), SEND(14);
    b[0] ^= 1, memcpy(b + 8, "FZ_CMD", 7), SEND(60);
    memcpy(b, hs, 8), memset(b + 8, 'A', 60000), b[60008] = 0, SEND(60100);
    memcpy(b, hs, 8), memcpy(b + 8, "FZ_CMD", 7), SEND(15); /* an empty command */
    /* fragments that cannot be: offset past the size, number past the count, a count
     * of 0, a size of 0 and of 4 GB, a second fragment with no first, one that ends
     * past the message */
    const uint32_t bad[][4] = {{100, 200, 1, 2}, {100, 0, 5, 2}, {100, 0, 0, 0}, {0, 0, 0, 1},
                               {0xffffffffu, 0, 0, 65535}, {3000, 1400, 1, 3},
                               {2000, 1500, 1, 2}, {1000, 0, 0, 2}, {0x7fffffffu, 0, 0, 2}};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++)
        SEND(frag(b, 100 + (uint32_t)i, bad[i][0], bad[i][1], (uint16_t)bad[i][2],
                  (uint16_t)bad[i][3], "FZ_CMD", 1300));
    /* fragments whose offset + size wraps 32 bits, which LCM 1.3.1's check lets
     * through to a copy ~4 GB past its buffer (wg_mcast_guard's filter stops them),
     * each after a first fragment that made the message's buffer; then fragments
     * with their header cut short (LCM takes their size as 4 GB less a few bytes) */
    const uint32_t wrap[][3] = {{0xffffff00u, 1, 512}, {0xffffff00u, 0, 512},
                                {0xfffffff0u, 1, 64}, {0x80000000u, 1, 1300}};
    for (size_t i = 0; i < sizeof wrap / sizeof wrap[0]; i++) {
        SEND(frag(b, 200 + (uint32_t)i, 3000, 0, 0, 2, "FZ_CMD", 1300));
        SEND(frag(b, 200 + (uint32_t)i, 3000, wrap[i][0], (uint16_t)wrap[i][1], 2, "FZ_CMD",
                  wrap[i][2]));
    }
    for (size_t len = 8; len < 20; len++) {
        frag(b, 300 + (uint32_t)len, 3000, 0xffffff00u, 1, 2, "FZ_CMD", 0);
        SEND(len);
    }
    /* a flood of first fragments of 16 MB .. 256 MB messages that never end. LCM
     * allocates each message's size at its first fragment: glibc maps it lazily, but
     * AddressSanitizer's allocator maps and unmaps its shadow too (about 25 ms a
     * fragment here, the daemon's receive thread busy in it), so the ASan build sends
     * a thirtieth of them */
#if defined(__SANITIZE_ADDRESS__)
    long nflood = n / 3;
#else
    long nflood = 10 * n;
#endif
    for (long i = 0; i < nflood; i++) {
        uint32_t size = 1u << (24 + rndi(5));
        SEND(frag(b, 1000 + (uint32_t)i, size, 0, 0, (uint16_t)((size + 1399) / 1400),
                  rndi(2) ? "FZ_CMD" : "FZ_TICK", 1300));
    }
    /* random datagrams, half with a magic of LCM's */
    for (long i = 0; i < 10 * n; i++) {
        size_t len = (size_t)rndi(1500);
        for (size_t k = 0; k < len; k++)
            b[k] = (unsigned char)rnd();
        if (len >= 4 && rndi(2))
            memcpy(b, rndi(2) ? &hs[0] : &(uint32_t){htonl(LC_LONG)}, 4);
        SEND(len);
    }
#undef SEND
    close(s);
    /* Answered again: a get every 0.5 s until one is (while the daemon works through
     * what its socket holds, the kernel drops what does not fit, a get of ours too:
     * counted on STATUS as rx_dropped), within 20 s. */
    double t0 = now_ms(), back = -1;
    for (int i = 0; i < 40 && back < 0; i++)
        if (get_answered(500))
            back = now_ms() - t0;
    long rss1 = proc_status_kb(F.pid, "VmRSS"), acks = F.foreign_acks - acks0;
    if (back < 0) {
        fail("wire: the daemon answered no get within 20 s of the datagrams");
        return;
    }
    if (acks < 1) /* the empty command at least: the datagrams reached the daemon */
        fail("wire: no refusal came back: the datagrams did not reach the daemon");
    mark();
    if (own("save", "fzpost", 3000) != 0)
        fail("wire: our own save after the datagrams was not accepted");
    else if (!same_file("fzpre.wgstate", "fzpost.wgstate")) {
        F.changed++;
        fail("wire: the raw datagrams changed the state");
    }
    printf("wire: %ld datagrams sent (%ld flood fragments, %ld random), %ld refused with an "
           "ACK; the daemon's memory %ld -> %ld kB; a get answered %.0f ms after the last "
           "datagram\n", sent, nflood, 10 * n, acks, rss0, rss1, back);
    if (rss0 < 0 || rss1 < 0 || rss1 - rss0 > 65536)
        fail("wire: the daemon's memory grew from %ld to %ld kB (limit 64 MB)", rss0, rss1);
}

static int cmp_d(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

static void figures(void)
{
    qsort(F.lat, (size_t)F.nlat, sizeof F.lat[0], cmp_d);
    double p50 = F.nlat ? F.lat[F.nlat / 2] : 0, p99 = F.nlat ? F.lat[F.nlat * 99 / 100] : 0;
    printf("wgfuzz: %ld hostile messages, %ld accepted, %ld refused, %ld unanswered, %ld extra "
           "ACKs, %ld state changes by refused commands; ACK p50 %.2f ms, p99 %.2f ms, slowest "
           "%.1f ms (%s); %ld failures\n",
           F.commands, F.accepted, F.refused, F.unanswered, F.extra, F.changed, p50, p99,
           F.slowest, F.slowest_what, F.failures);
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        fprintf(stderr, "usage: wgfuzz WORMGEARD commands|commands-keyed|snapshots|kill|wire "
                "[SEED [N]]\n");
        return 2;
    }
    F.bin = argv[1];
    uint64_t seed = argc > 3 && strcmp(argv[3], "-") ? strtoull(argv[3], NULL, 0)
                                                    : (uint64_t)time(NULL) ^ (uint64_t)getpid();
    long n = argc > 4 ? atol(argv[4]) : 1500;
    F.rng = seed ? seed : 1;
    printf("wgfuzz %s: seed %llu (rerun: wgfuzz WORMGEARD %s %llu %ld)\n", argv[2],
           (unsigned long long)seed, argv[2], (unsigned long long)seed, n);
    encoder_self_check();
    snprintf(F.url, sizeof F.url, "udpm://239.255.76.67:%d?ttl=0", 20000 + getpid() % 20000);
    snprintf(F.dir, sizeof F.dir, "/tmp/wgfuzz-XXXXXX");
    if (!mkdtemp(F.dir))
        return 1;
    snprintf(F.log, sizeof F.log, "%s/daemon.log", F.dir);
    if (!strcmp(argv[2], "commands-keyed")) {
        snprintf(F.keyfile, sizeof F.keyfile, "%s/key", F.dir);
        char why[300];
        if (wg_key_create(F.keyfile, why, sizeof why) ||
            wg_key_load(F.keyfile, F.key, why, sizeof why)) {
            fprintf(stderr, "wgfuzz: %s\n", why);
            return 1;
        }
        F.keyed = 1;
    }
    char lurl[160]; /* our receive buffer sized for the burst's ACKs and PARAMS */
    snprintf(lurl, sizeof lurl, "%s&recv_buf_size=8388608", F.url);
    F.lcm = lcm_create(lurl);
    if (!F.lcm)
        return 1;
    wormgear_ack_t_subscription_t *as = wormgear_ack_t_subscribe(F.lcm, "FZ_ACK", on_ack, NULL);
    wormgear_ack_t_subscription_set_queue_capacity(as, 20000); /* a burst's ACKs */
    char gwhy[300];
    /* the filter wg_mcast.c's bind put there: the kernel never saw the socket unfiltered */
    int at_bind = wg_mcast_filtered(F.url);
    printf("wgfuzz: LCM's receive socket had a filter of %d instructions from its bind, before "
           "wg_mcast_guard\n", at_bind);
    if (at_bind <= 0)
        fail("LCM's receive socket had no filter before wg_mcast_guard: datagrams that came "
             "before it were read unfiltered");
    /* wire's datagrams reach us too; big_messages needs fragments */
    if (wg_mcast_guard(F.url, WG_MCAST_FRAGMENTS, gwhy, sizeof gwhy)) {
        fprintf(stderr, "wgfuzz: %s\n", gwhy);
        return 1;
    }
    wormgear_status_t_subscription_t *ss =
        wormgear_status_t_subscribe(F.lcm, "FZ_STATUS", on_status, NULL);
    start_daemon("--verbose=no");
    own("save", "fzbase", 3000);
    own("save", "fzpre", 3000);
    if (!strcmp(argv[2], "commands") || F.keyed) {
        directed_names();
        directed_ramps();
        directed_clients();
        directed_misc();
        raw_mutations(n / 3);
        random_cmds(n);
        burst(2000, 60);
        ticks();
        forged_statuses();
        log_not_forged();
    } else if (!strcmp(argv[2], "snapshots")) {
        snapshots();
        special_files();
    } else if (!strcmp(argv[2], "wire")) {
        wire(n);
    } else if (!strcmp(argv[2], "kill")) {
        kill_during_saves((int)(n > 40 ? 40 : n));
    }
    stop_daemon();
    figures();
    char cmd[160];
    snprintf(cmd, sizeof cmd, "rm -rf %s", F.dir);
    if (!g_failed && system(cmd) != 0)
        fprintf(stderr, "cannot remove %s\n", F.dir);
    else if (g_failed)
        fprintf(stderr, "daemon log and files kept in %s\n", F.dir);
    wormgear_ack_t_unsubscribe(F.lcm, as);
    wormgear_status_t_unsubscribe(F.lcm, ss);
    lcm_destroy(F.lcm);
    return g_failed;
}

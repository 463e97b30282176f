/* wgd_bench - figures for docs/daemon.md, not a pass/fail test:
 * command->ACK latency (p50/p99/max; get, set xi_p, a set of every parameter
 * in turn) and the daemon's CPU share at physical real time (table3,
 * omega = 2.5, N = 128, publishing on).
 * usage: netns.sh wgd_bench WORMGEARD [SECONDS] [NCMDS] [DAEMON OPTION]...
 * (the options are appended to the daemon's command line: --rt-priority 10;
 * --help: what the operands allow). A daemon that exits, or sends no
 * STATUS in its first 3 s, ends the benchmark with a message and exit 1. */
#include "bench_args.h"
#include "bus.h"

#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "wormgear/wg_param.h"

#include <errno.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

typedef struct bench {
    bus c;
    wg_params cur; /* the daemon's parameters (from PARAMS) */
    int have_params;
    wormgear_status_t last;
    int nstatus;
    char health[16];
    pid_t daemon; /* the daemon this benchmark started */
} bench;

static bench B;

static void on_status(const lcm_recv_buf_t *r, const char *ch, const wormgear_status_t *m,
                      void *u)
{
    (void)r, (void)ch, (void)u;
    B.last = *m;
    snprintf(B.health, sizeof B.health, "%s", m->health);
    B.last.scene = B.last.mode = B.last.run = B.last.health = B.last.fault = B.last.motion =
        B.last.regime = B.last.tick_refusal = NULL;
    B.nstatus++;
}

static const char *set_name(const char *op) { return !strcmp(op, "set") ? "set xi_p" : op; }

static double cpu_ticks(pid_t pid)
{
    char path[64], buf[1024];
    snprintf(path, sizeof path, "/proc/%d/stat", (int)pid);
    FILE *f = fopen(path, "r");
    if (!f || !fgets(buf, sizeof buf, f)) {
        if (f)
            fclose(f);
        return -1;
    }
    fclose(f);
    char *p = strrchr(buf, ')');
    unsigned long ut = 0, st = 0;
    /* fields after the comm: state(3) ... utime(14) stime(15) */
    if (!p || sscanf(p + 2, "%*c %*d %*d %*d %*d %*d %*u %*u %*u %*u %*u %lu %lu", &ut, &st) != 2)
        return -1;
    return (double)(ut + st) / (double)sysconf(_SC_CLK_TCK);
}

static int cmp(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Sorted copy's p50 / p99 / max of n values (n > 0), into out. */
static void pcts(double *v, int n, double out[3])
{
    qsort(v, (size_t)n, sizeof *v, cmp);
    out[0] = v[n / 2], out[1] = v[(int)(n * 0.99)], out[2] = v[n - 1];
}

/* The daemon's parameter values, from its PARAMS (each get brings one). */
static void on_params(const lcm_recv_buf_t *r, const char *ch, const wormgear_params_t *m,
                      void *u)
{
    (void)r, (void)ch, (void)u;
    for (int i = 0; i < m->n; i++) {
        int id = wg_param_lookup(m->name[i]);
        if (id >= 0)
            B.cur.v[id] = m->value[i];
    }
    B.have_params = 1;
}

/* The value command i of the "every parameter" pass sets parameter id to:
 * its current value moved by a relative 1e-6 up, then back (a zero moves to
 * 1e-6 of its range and back; a whole number, a tooth count, by one), so
 * every set is a change and in range. */
static double next_value(int id, int i)
{
    const wg_param_info *r = wg_param_info_get(id);
    double v = B.cur.v[id];
    int up = i / WG_NPARAM % 2 == 0;
    double w = r->flags & WG_PF_INT ? (up ? v + 1 : v - 1)
               : v != 0.0        ? v * (up ? 1 + 1e-6 : 1 / (1 + 1e-6))
               : up              ? 1e-6 * r->max
                                 : 0.0;
    return w < r->min ? r->min : w > r->max ? r->max : w;
}

/* Has the daemon exited? Then say how, once, and return 1. */
static int daemon_gone(void)
{
    int st;
    if (waitpid(B.daemon, &st, WNOHANG) != B.daemon)
        return 0;
    if (WIFEXITED(st))
        fprintf(stderr, "wgd_bench: the daemon exited with status %d (its messages are above)\n",
                WEXITSTATUS(st));
    else
        fprintf(stderr, "wgd_bench: the daemon was killed by signal %d\n",
                WIFSIGNALED(st) ? WTERMSIG(st) : 0);
    B.daemon = 0;
    return 1;
}

/* n commands 5 ms apart: op "get" (transport and loop only), "set" of xi_p
 * (through wg_sim_set_params and its RK4 stability check) or, with every,
 * a set of each parameter in turn. Prints the command -> ACK latency and
 * its two halves on the one wall clock of this host: client send -> the
 * daemon's ACK send (the forward path and the daemon's work), and that ->
 * this client has it (the return path). */
static int latency(const char *op, int every, int n)
{
    double *lat = calloc((size_t)n * 3, sizeof *lat);
    if (!lat) {
        fprintf(stderr, "wgd_bench: out of memory for %d latencies\n", n);
        return 1;
    }
    double *fwd = lat + n, *back = lat + 2 * n;
    int got = 0, refused = 0;
    char *name[1] = {"xi_p"}, refused_names[256] = "";
    for (int i = 0; i < n; i++) {
        int id = every ? i % WG_NPARAM : WG_P_XI_P;
        double v = every ? next_value(id, i) : i % 2 ? 0.08 : 0.0800001;
        int set = !strcmp(op, "set");
        name[0] = (char *)wg_param_info_get(id)->name;
        wormgear_cmd_t c = {.op = (char *)op, .nparams = set, .names = name, .values = &v,
                            .unit = "", .name = ""};
        double t0 = cli_mono_ns() * 1e-3;
        bus_send(&B.c, &c);
        int acked = bus_wait_ack(&B.c, 1000) == 0;
        if (acked && B.c.ack.accepted) {
            double t1 = cli_mono_ns() * 1e-3;
            int64_t wall = cli_wall_us();
            lat[got] = t1 - t0;
            fwd[got] = (double)(B.c.ack.utime - c.utime);
            back[got++] = (double)(wall - B.c.ack.utime);
            if (set)
                B.cur.v[id] = v;
        } else if (!acked && daemon_gone()) {
            free(lat);
            return 1;
        } else if (acked) { /* a refusal: counted, not timed */
            size_t k = strlen(refused_names);
            refused++;
            if (!strstr(refused_names, name[0]))
                snprintf(refused_names + k, sizeof refused_names - k, "%s%s", k ? " " : "",
                         name[0]);
        }
        bus_wait(&B.c, 5, NULL, NULL); /* 5 ms apart */
    }
    double a[3], f[3], b[3];
    if (got) {
        pcts(lat, got, a), pcts(fwd, got, f), pcts(back, got, b);
        printf("command->ACK latency (%s, %d of %d accepted): p50 %.0f us, p99 %.0f us, "
               "max %.0f us\n  send->daemon's ACK p50 %.0f / p99 %.0f us; ACK->client p50 %.0f "
               "/ p99 %.0f us\n", every ? "set, every parameter in turn" : set_name(op), got, n,
               a[0], a[1], a[2], f[0], f[1], b[0], b[1]);
        if (refused || got + refused < n)
            printf("  %d refused (%s), %d unanswered within 1 s\n", refused,
                   refused ? refused_names : "none", n - got - refused);
    }
    free(lat);
    return 0;
}

int main(int argc, char **argv)
{
    const char *daemon = NULL;
    double nsec = 10, nc = 500;
    bench_arg args[] = {
        {"WORMGEARD", "the daemon's executable (build/release/daemon/wormgeard)", 0, 0, NULL,
         &daemon, 1},
        {"SECONDS", "seconds the CPU share is measured over, 1 to 3600 (default 10)", 1, 3600,
         &nsec, NULL, 0},
        {"NCMDS", "commands each latency pass sends, 5 ms apart, 1 to 100000 (default 500)", 1,
         1e5, &nc, NULL, 0}};
    int rest = argc, rc = bench_args("wgd_bench", "The daemon at physical real time (table3, omega 2.5, "
                              "N 128, publishing): its CPU share, and command -> ACK latency of "
                              "get, set xi_p and a set of every parameter. Run it through "
                              "tests/netns.sh. DAEMON OPTIONs go on the daemon's command line "
                              "(--rt-priority 10).", " [DAEMON OPTION]...", argc, argv, args, 3,
                              &rest);
    if (rc >= 0)
        return rc;
    if (access(daemon, X_OK) != 0)
        return cli_usage_error("wgd_bench", "WORMGEARD '%s': %s (the daemon's executable)",
                               daemon, strerror(errno));
    int secs = (int)nsec, ncmd = (int)nc;
    char url[96], why[128];
    snprintf(url, sizeof url, "udpm://239.255.76.67:%d?ttl=0", 20000 + getpid() % 20000);
    pid_t pid = fork();
    if (pid < 0) {
        perror("wgd_bench: fork");
        return 1;
    }
    if (pid == 0) {
        char *dargv[64] = {(char *)daemon, "--url", url, "--prefix", "BENCH_", "--set", "omega=2.5",
                           "--steps-per-period", "128", "--mode", "realtime", "--rate", "1",
                           "--status-hz", "1"};
        int k = 15;
        for (int i = rest; i < argc && k < 63; i++) /* the daemon's own options */
            dargv[k++] = argv[i];
        dargv[k] = NULL;
        execv(daemon, dargv);
        fprintf(stderr, "wgd_bench: cannot run %s: %s\n", daemon, strerror(errno));
        _exit(127);
    }
    B.daemon = pid;
    if (bus_open(&B.c, url, "BENCH_", "wgd_bench", why, sizeof why)) {
        kill(pid, SIGTERM);
        return 1;
    }
    wormgear_status_t_subscription_t *s =
        wormgear_status_t_subscribe(B.c.lcm, "BENCH_STATUS", on_status, NULL);
    bus_wait(&B.c, 3000, NULL, NULL); /* start-up and grace */
    if (daemon_gone())
        return 1;
    if (B.nstatus == 0) {
        fprintf(stderr, "wgd_bench: no STATUS from the daemon in its first 3 s (at 1 Hz): "
                "stopped it\n");
        kill(pid, SIGTERM);
        waitpid(pid, NULL, 0);
        return 1;
    }
    printf("wormgeard benchmark: table3, omega 2.5, N 128, realtime rate 1 (physical real "
           "time), STATE 2000 samples/s + POINCARE + CONTACT published; %ld CPUs, load %s",
           sysconf(_SC_NPROCESSORS_ONLN), "");
    FILE *la = fopen("/proc/loadavg", "r");
    char lbuf[64] = "?\n";
    if (la) {
        if (!fgets(lbuf, sizeof lbuf, la))
            snprintf(lbuf, sizeof lbuf, "?\n");
        fclose(la);
    }
    printf("%s", lbuf);
    double c0 = cpu_ticks(pid), t0 = cli_mono_ns() * 1e-3;
    bus_wait(&B.c, secs * 1000, NULL, NULL);
    double c1 = cpu_ticks(pid), t1 = cli_mono_ns() * 1e-3;
    printf("CPU share over %d s: %.1f%% of one core (/proc utime+stime, all threads)\n", secs,
           100.0 * (c1 - c0) / ((t1 - t0) * 1e-6));
    printf("last STATUS: %.4g steps/s, rtf %.4f, lag %.3f ms, overruns %lld, loop %.0f us mean "
           "/ %.0f us max, cpu_share %.3f, health %s, dropped %lld\n", B.last.steps_per_s,
           B.last.rtf, B.last.lag_s * 1e3, (long long)B.last.overruns, B.last.loop_mean_us,
           B.last.loop_max_us, B.last.cpu_share, B.health, (long long)B.last.msgs_dropped);
    wormgear_params_t_subscription_t *sp =
        wormgear_params_t_subscribe(B.c.lcm, "BENCH_PARAMS", on_params, NULL);
    if (daemon_gone() || latency("get", 0, ncmd) || latency("set", 0, ncmd))
        return 1;
    if (B.have_params && latency("set", 1, ncmd))
        return 1;
    if (!B.have_params)
        printf("no PARAMS came: the every-parameter pass is skipped\n");
    wormgear_params_t_unsubscribe(B.c.lcm, sp);
    wormgear_status_t_unsubscribe(B.c.lcm, s);
    bus_close(&B.c);
    kill(pid, SIGTERM);
    int st;
    waitpid(pid, &st, 0);
    printf("daemon exit status %d\n", WIFEXITED(st) ? WEXITSTATUS(st) : -1);
    return 0;
}

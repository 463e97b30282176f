/* wgd_bench - figures for docs/daemon.md, not a pass/fail test:
 * command->ACK latency (p50/p99/max) and the daemon's CPU share at physical
 * real time (table3, omega = 2.5, N = 128, publishing on).
 * usage: netns.sh wgd_bench WORMGEARD [SECONDS] [NCMDS] */
#include "cli.h"
#include "bus.h"

#include "lcmtypes/wormgear_status_t.h"

#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/wait.h>
#include <unistd.h>

typedef struct bench {
    bus c;
    wormgear_status_t last;
    int nstatus;
    char health[16];
} bench;

static bench B;

static void on_status(const lcm_recv_buf_t *r, const char *ch, const wormgear_status_t *m,
                      void *u)
{
    (void)r, (void)ch, (void)u;
    B.last = *m;
    snprintf(B.health, sizeof B.health, "%s", m->health);
    B.last.scene = B.last.mode = B.last.run = B.last.health = B.last.fault = B.last.motion =
        B.last.regime = NULL;
    B.nstatus++;
}

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

/* n commands 5 ms apart: op "get" (transport and loop only) or "set" (one
 * parameter, through wg_sim_set_params and its RK4 stability check). */
static void latency(const char *op, int n)
{
    double *lat = calloc((size_t)n, sizeof *lat);
    int got = 0;
    char *name[1] = {"xi_p"};
    for (int i = 0; i < n; i++) {
        double v = i % 2 ? 0.08 : 0.0800001;
        int set = !strcmp(op, "set");
        wormgear_cmd_t c = {.op = (char *)op, .nparams = set, .names = name, .values = &v,
                            .unit = "", .name = ""};
        double t0 = cli_mono_ns() * 1e-3;
        bus_send(&B.c, &c);
        if (bus_wait_ack(&B.c, 1000) == 0 && B.c.ack.accepted)
            lat[got++] = cli_mono_ns() * 1e-3 - t0;
        bus_wait(&B.c, 5, NULL, NULL); /* 5 ms apart */
    }
    qsort(lat, (size_t)got, sizeof *lat, cmp);
    if (got)
        printf("command->ACK latency (%s, %d of %d answered): p50 %.0f us, p99 %.0f us, "
               "max %.0f us\n", !strcmp(op, "set") ? "set xi_p" : op, got, n, lat[got / 2],
               lat[(int)(got * 0.99)], lat[got - 1]);
    free(lat);
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        fprintf(stderr, "usage: wgd_bench WORMGEARD [SECONDS] [NCMDS]\n");
        return 2;
    }
    int secs = argc > 2 ? atoi(argv[2]) : 10, ncmd = argc > 3 ? atoi(argv[3]) : 500;
    char url[96], why[128];
    snprintf(url, sizeof url, "udpm://239.255.76.67:%d?ttl=0", 20000 + getpid() % 20000);
    pid_t pid = fork();
    if (pid == 0) {
        execl(argv[1], argv[1], "--url", url, "--prefix", "BENCH_", "--set", "omega=2.5",
              "--steps-per-period", "128", "--mode", "realtime", "--rate", "1", "--status-hz",
              "1", (char *)NULL);
        _exit(127);
    }
    if (bus_open(&B.c, url, "BENCH_", "wgd_bench", why, sizeof why))
        return 1;
    wormgear_status_t_subscription_t *s =
        wormgear_status_t_subscribe(B.c.lcm, "BENCH_STATUS", on_status, NULL);
    bus_wait(&B.c, 3000, NULL, NULL); /* start-up and grace */
    printf("wormgeard benchmark: table3, omega 2.5, N 128, realtime rate 1 (physical real "
           "time), STATE 2000 samples/s + POINCARE + CONTACT published; %ld CPUs, load %s",
           sysconf(_SC_NPROCESSORS_ONLN), "");
    FILE *la = fopen("/proc/loadavg", "r");
    char lbuf[64] = "?\n";
    if (la && fgets(lbuf, sizeof lbuf, la))
        fclose(la);
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
    latency("get", ncmd);
    latency("set", ncmd);
    wormgear_status_t_unsubscribe(B.c.lcm, s);
    bus_close(&B.c);
    kill(pid, SIGTERM);
    int st;
    waitpid(pid, &st, 0);
    printf("daemon exit status %d\n", WIFEXITED(st) ? WEXITSTATUS(st) : -1);
    return 0;
}

/* wgtap - test helper: print what a subscriber receives on <prefix>STATE and
 * <prefix>POINCARE for SEC seconds, one line per sample:
 *   STATE,seq,i,tau,xn      POINCARE,seq,i,period,xn
 * in the shortest form that reads back exactly (wg_num_format: the text
 * wglog writes to its CSV).
 * usage: wgtap URL PREFIX SEC */
#include "cli.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "wormgear/wg_mcast.h"
#include "wormgear/wg_param.h"

#include <lcm/lcm.h>
#include <stdio.h>
#include <stdlib.h>
#include <sys/select.h>

static void on_state(const lcm_recv_buf_t *rb, const char *ch, const wormgear_state_t *m, void *u)
{
    (void)rb, (void)ch, (void)u;
    char a[40], b[40];
    for (int i = 0; i < m->n; i++)
        printf("STATE,%lld,%d,%s,%s\n", (long long)m->seq, i, wg_num_format(m->tau[i], a, 40),
               wg_num_format(m->xn[i], b, 40));
}

static void on_pc(const lcm_recv_buf_t *rb, const char *ch, const wormgear_poincare_t *m, void *u)
{
    (void)rb, (void)ch, (void)u;
    char a[40];
    for (int i = 0; i < m->n; i++)
        printf("POINCARE,%lld,%d,%lld,%s\n", (long long)m->seq, i, (long long)m->period[i],
               wg_num_format(m->xn[i], a, sizeof a));
}

int main(int argc, char **argv)
{
    if (argc != 4) {
        fprintf(stderr, "usage: wgtap URL PREFIX SEC\n");
        return 2;
    }
    lcm_t *l = lcm_create(argv[1]);
    if (!l)
        return 1;
    char ch[128];
    snprintf(ch, sizeof ch, "%sSTATE", argv[2]);
    wormgear_state_t_subscription_t *s1 = wormgear_state_t_subscribe(l, ch, on_state, NULL);
    snprintf(ch, sizeof ch, "%sPOINCARE", argv[2]);
    wormgear_poincare_t_subscription_t *s2 = wormgear_poincare_t_subscribe(l, ch, on_pc, NULL);
    char why[512] = ""; /* LCM's socket filtered, as every client's (wg_mcast.h) */
    if (wg_mcast_guard(argv[1], WG_MCAST_WHOLE, why, sizeof why)) {
        fprintf(stderr, "wgtap: %s\n", why);
        return 1;
    }
    double end = cli_mono_s() + atof(argv[3]);
    for (double left; (left = end - cli_mono_s()) > 0;) {
        int fd = lcm_get_fileno(l);
        fd_set s;
        FD_ZERO(&s);
        FD_SET(fd, &s);
        struct timeval tv = {(long)left, (long)((left - (long)left) * 1e6)};
        if (select(fd + 1, &s, NULL, NULL, &tv) > 0)
            lcm_handle(l);
    }
    wormgear_state_t_unsubscribe(l, s1);
    wormgear_poincare_t_unsubscribe(l, s2);
    lcm_destroy(l);
    return 0;
}

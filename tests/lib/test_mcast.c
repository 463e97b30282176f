/* test_mcast.c - a udpm:// URL's multicast group as LCM 1.3.1 reads it
 * (lib/wg_mcast.c): no group is LCM's default one, the port and the options
 * do not matter, inet_aton's forms count; anything else (another provider,
 * a unicast or unreadable address, no address before the port) is left to
 * LCM, and wg_mcast_route then tries no socket. The route itself is
 * sys.wgctl's: in a network namespace with no route, and with one. */
#include "test.h"
#include "wormgear/wg_mcast.h"
#include "wormgear/wg_status.h"

static void test_groups(void)
{
    static const struct {
        const char *url, *group; /* NULL: not one of LCM's multicast groups */
    } c[] = {
        {"udpm://239.255.76.67:7667?ttl=0", "239.255.76.67"},
        {"udpm://", WG_LCM_DEFAULT_GROUP},
        {"udpm://?ttl=1", WG_LCM_DEFAULT_GROUP},
        {"udpm://239.1.2.3", "239.1.2.3"},
        {"udpm://239.1.2.3?ttl=0&recv_buf_size=2097152", "239.1.2.3"},
        {"udpm://239.1.2.3:0", "239.1.2.3"},
        {"udpm://239.1.2.3:99999", "239.1.2.3"}, /* LCM refuses the port, not the route */
        {"udpm://0xef010203:7667", "239.1.2.3"},  /* inet_aton's forms */
        {"udpm://224.0.0.1:1", "224.0.0.1"},
        {"udpm://10.0.0.1:7667?ttl=0", NULL},
        {"udpm://240.0.0.1:7667", NULL},
        {"udpm://:7667", NULL},
        {"udpm://bogus:1", NULL},
        {"udpm://239.1.2.3.4:7667", NULL},
        {"udpm://[ff02::1]:7667", NULL},
        {"udpm://2391111111111111111111111111111111111111111111111111111111111111111111:1", NULL},
        {"UDPM://239.1.2.3:7667", NULL},
        {"memq://", NULL},
        {"file:///tmp/x.lcmlog?mode=r", NULL},
        {"tcpq://127.0.0.1:7700", NULL},
        {"", NULL},
        {NULL, NULL},
    };
    for (size_t i = 0; i < sizeof c / sizeof c[0]; i++) {
        char name[WG_MCAST_NAME] = "", why[300] = "";
        int got = wg_mcast_group(c[i].url, name);
        printf("%-75s -> %s\n", c[i].url ? c[i].url : "(null)", got ? name : "(LCM judges)");
        ASSERT_EQ_INT(got, c[i].group != NULL);
        if (c[i].group)
            ASSERT_STR(name, c[i].group);
        else /* no group: no socket, no refusal */
            ASSERT_EQ_INT(wg_mcast_route(c[i].url, why, sizeof why), WG_OK);
    }
}

TEST_MAIN(TEST(test_groups))

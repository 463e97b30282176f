/* test_webcore.c - wgweb's transport-independent core: the JSON buffer,
 * drop-oldest queues, scope decimation and rate caps, JSON commands, and
 * the Foxglove protocol engine against a fake transport: every class of
 * bad client input gets a status error on that client only. */
#include <cjson/cJSON.h>

#include "test.h"
#include "web_cmd.h"
#include "web_fox.h"
#include "web_json.h"
#include "web_queue.h"
#include "web_thin.h"
#include "wormgear/wg_sim.h"

/* ---- a fake transport and daemon */
typedef struct fake {
    int wakes, kicks, cmds;
    wormgear_cmd_t last; /* shallow: valid during the hook only */
    char last_op[16], last_name0[48];
    double last_v0;
    int last_n, last_at_section;
    const char *refuse; /* the transport's reason when it cannot send */
} fake;

static void f_wake(void *ctx, void *conn) { (void)conn, ((fake *)ctx)->wakes++; }
static void f_kick(void *ctx, void *conn) { (void)conn, ((fake *)ctx)->kicks++; }
static int64_t f_cmd(void *ctx, wormgear_cmd_t *c, char *why, size_t whylen)
{
    fake *k = ctx;
    if (k->refuse) {
        snprintf(why, whylen, "%s", k->refuse);
        return -1;
    }
    snprintf(k->last_op, sizeof k->last_op, "%s", c->op);
    k->last_n = c->nparams;
    k->last_at_section = c->at_section;
    snprintf(k->last_name0, sizeof k->last_name0, "%s", c->nparams ? c->names[0] : "");
    k->last_v0 = c->nparams ? c->values[0] : 0;
    c->utime = 1700000000000000 + 1000 * (k->cmds + 1); /* as bus_send stamps it */
    return ++k->cmds;
}

static msg_schemas schemas;
static fox F;
static fake K;

static void setup(int allow)
{
    memset(&K, 0, sizeof K);
    ASSERT_EQ_INT(msg_schemas_init(&schemas), 0);
    fox_conf c = {.name = "test", .prefix = "T_", .url = "memq://", .allow_commands = allow,
                  .max_clients = 2, .queue_len = 8, .queue_bytes = 1 << 20, .ack_timeout_s = 1,
                  .schemas = &schemas};
    fox_hooks h = {.ctx = &K, .wake = f_wake, .kick = f_kick, .command = f_cmd};
    ASSERT_EQ_INT(fox_init(&F, &c, &h), 0);
}

static void teardown(void)
{
    fox_fini(&F);
    msg_schemas_fini(&schemas);
}

/* Drain client ci's frames; returns the concatenated text frames (static). */
static const char *drain(int ci, int *nbinary)
{
    static jbuf all;
    jbuf out;
    int bin, nb = 0;
    jb_free(&all);
    jb_init_pre(&out, 16);
    while (fox_frame(&F, ci, &out, &bin)) {
        if (bin)
            nb++;
        else
            jb_raw(&all, jb_text(&out)), jb_raw(&all, "\n");
    }
    jb_free(&out);
    if (nbinary)
        *nbinary = nb;
    return jb_text(&all);
}

static void rx(int ci, const char *text) { fox_rx(&F, ci, (const unsigned char *)text, strlen(text), 0); }

/* ---- tests */

static void test_jbuf(void)
{
    jbuf b;
    jb_init_pre(&b, 8);
    jb_raw(&b, "{");
    jb_key(&b, "a"), jb_num(&b, 0.1);
    jb_key(&b, "s"), jb_str(&b, "q\"\\\n");
    jb_key(&b, "n"), jb_num(&b, NAN);
    jb_key(&b, "l"), jb_raw(&b, "[");
    jb_item(&b), jb_int(&b, 1);
    jb_item(&b), jb_bool(&b, 0);
    jb_raw(&b, "]}");
    ASSERT_STR(jb_text(&b), "{\"a\":0.10000000000000001,\"s\":\"q\\\"\\\\\\u000a\",\"n\":null,\"l\":[1,false]}");
    cJSON *j = cJSON_Parse(jb_text(&b));
    ASSERT_TRUE(j != NULL);
    cJSON_Delete(j);
    /* strings off the bus: well-formed UTF-8 (2, 3, 4 bytes, C1 U+009B
     * included) kept; a stray byte, a truncated sequence, an overlong form,
     * a surrogate and a lead byte past U+10FFFF become U+FFFD; DEL escaped */
    jb_reset(&b);
    jb_str(&b, "a\xff" "b \xc2\x9b \xe2\x82\xac \xf0\x9f\x98\x80 \xe2\x82 \xc0\xaf \xed\xa0\x80 "
               "\xf5\x80\x80\x80 \x7f");
    ASSERT_STR(jb_text(&b), "\"a\\ufffdb \xc2\x9b \xe2\x82\xac \xf0\x9f\x98\x80 \\ufffd\\ufffd "
                            "\\ufffd\\ufffd \\ufffd\\ufffd\\ufffd \\ufffd\\ufffd\\ufffd\\ufffd \\u007f\"");
    jb_free(&b);
}

static void test_queue_drops_oldest(void)
{
    wq q;
    ASSERT_EQ_INT(wq_init(&q, 4, 1000), 0);
    size_t dropped = 0;
    for (int i = 0; i < 10; i++) {
        char t[8];
        snprintf(t, sizeof t, "%d", i);
        wq_msg *m = wq_msg_new(t, strlen(t));
        dropped += wq_push(&q, (wq_item){.m = m, .kind = WQ_DATA});
        wq_msg_unref(m);
    }
    ASSERT_EQ_INT(dropped, 6);
    ASSERT_EQ_INT(q.dropped, 6);
    wq_item it;
    ASSERT_TRUE(wq_pop(&q, &it));
    ASSERT_STR((const char *)it.m->data, "6"); /* the newest four kept */
    wq_msg_unref(it.m);
    wq_fini(&q);
    ASSERT_EQ_INT(wq_init(&q, 100, 10), 0); /* the byte bound */
    wq_msg *big = wq_msg_new("0123456789ab", 12);
    ASSERT_EQ_INT(wq_push(&q, (wq_item){.m = big, .kind = WQ_DATA}), 1);
    ASSERT_EQ_INT(q.count, 0);
    wq_msg_unref(big);
    wq_fini(&q);
}

static void test_thin_scope_stride(void)
{
    thin_scope t;
    thin_scope_init(&t, 300);
    int kept = 0;
    for (int i = 0; i < 2000; i++) /* one second at 2000 samples/s, decimation 800 */
        kept += thin_scope_keep(&t, 800LL * i, 800);
    ASSERT_EQ_INT(kept, 2000); /* no rate known yet: everything */
    thin_scope_second(&t, 1.0);
    ASSERT_EQ_INT(t.stride_steps, 7 * 800);
    kept = 0;
    for (int i = 2000; i < 4000; i++)
        kept += thin_scope_keep(&t, 800LL * i, 800);
    ASSERT_TRUE(kept <= 300 && kept >= 280);
    ASSERT_EQ_INT(thin_scope_keep(&t, 0, 800), 1); /* step going back: restart */
}

static void test_thin_rate_cap(void)
{
    thin_rate t;
    thin_rate_init(&t, 500, 1);
    for (int s = 0; s < 3; s++) {
        for (int i = 0; i < 5000; i++)
            thin_rate_keep(&t, s + i / 5000.0);
        thin_rate_second(&t, 1.0);
    }
    ASSERT_TRUE(t.kept > 1000 && t.kept < 1700); /* ~500/s after the first second */
    ASSERT_EQ_INT(t.kept + t.thinned, 15000);
}

static void test_cmd_json(void)
{
    web_cmd c;
    char why[256];
    cJSON *j = cJSON_Parse("{\"op\":\"ramp\",\"param\":\"omega\",\"to\":1.5,\"duration\":2,\"from\":0.5}");
    ASSERT_EQ_INT(web_cmd_from_json(&c, j, why, sizeof why), 0);
    ASSERT_STR(c.cmd.op, "ramp");
    ASSERT_STR(c.cmd.names[0], "omega");
    ASSERT_NEAR(c.cmd.values[0], 1.5, 0);
    ASSERT_EQ_INT(c.cmd.has_from, 1);
    ASSERT_STR(c.cmd.unit, "s");
    cJSON_Delete(j);
    /* contacts, as wgctl's: which, and every N (absent: 0, the daemon's default) */
    j = cJSON_Parse("{\"op\":\"contacts\",\"which\":\"mesh\",\"every\":4}");
    ASSERT_EQ_INT(web_cmd_from_json(&c, j, why, sizeof why), 0);
    ASSERT_STR(c.cmd.op, "contacts");
    ASSERT_STR(c.cmd.name, "mesh");
    ASSERT_TRUE(c.cmd.nsteps == 4);
    cJSON_Delete(j);
    /* mode: the rate, when given, in the daemon's range; absent: 0 on the
     * wire, "keep" (an explicit 0 went out as that, and was answered OK) */
    j = cJSON_Parse("{\"op\":\"mode\",\"mode\":\"realtime\"}");
    ASSERT_EQ_INT(web_cmd_from_json(&c, j, why, sizeof why), 0);
    ASSERT_TRUE(c.cmd.rate == 0);
    cJSON_Delete(j);
    static const char *const rates[] = {"0", "-0", "5e-7", "1000.5", "-1", "\"fast\""};
    for (size_t i = 0; i < sizeof rates / sizeof rates[0]; i++) {
        char text[80];
        snprintf(text, sizeof text, "{\"op\":\"mode\",\"mode\":\"realtime\",\"rate\":%s}",
                 rates[i]);
        j = cJSON_Parse(text);
        why[0] = '\0';
        ASSERT_EQ_INT(web_cmd_from_json(&c, j, why, sizeof why), -1);
        ASSERT_STR(why, "mode: 'rate' must be a number in [1e-06, 1000] (the realtime factor, "
                   "1 = physical; leave it out to keep the current one)");
        cJSON_Delete(j);
    }
    static const double ok_rates[] = {WG_RATE_MIN, 1, WG_RATE_MAX};
    for (size_t i = 0; i < sizeof ok_rates / sizeof ok_rates[0]; i++) {
        char text[80];
        snprintf(text, sizeof text, "{\"op\":\"mode\",\"mode\":\"fast\",\"rate\":%.17g}",
                 ok_rates[i]);
        j = cJSON_Parse(text);
        ASSERT_EQ_INT(web_cmd_from_json(&c, j, why, sizeof why), 0);
        ASSERT_TRUE(c.cmd.rate == ok_rates[i]);
        cJSON_Delete(j);
    }
    const char *bad[] = {"[]", "{}", "{\"op\":7}", "{\"op\":\"fly\"}", "{\"op\":\"set\"}",
                         "{\"op\":\"step\",\"nsteps\":1.5}", "{\"op\":\"contacts\"}",
                         "{\"op\":\"contacts\",\"which\":\"all\",\"every\":0.5}",
                         "{\"op\":\"set\",\"params\":{\"omega\":\"x\"}}",
                         "{\"op\":\"ramp\",\"param\":\"omega\"}", "{\"op\":\"step\",\"nsteps\":0}",
                         "{\"op\":\"save\"}", "{\"op\":\"set\",\"params\":{\"omega\":1},\"at_section\":3}"};
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        j = cJSON_Parse(bad[i]);
        why[0] = '\0';
        ASSERT_EQ_INT(web_cmd_from_json(&c, j, why, sizeof why), -1);
        ASSERT_TRUE(why[0] != '\0');
        cJSON_Delete(j);
    }
}

/* What a client sends must be UTF-8: cJSON took \xff\xfe in an id, the
 * set ran and the answer's id was "\ufffd\ufffd" (a review). */
static void test_utf8(void)
{
    static const struct {
        const char *s;
        long bad_at;
    } cases[] = {{"ascii", -1}, {"\xe2\x82\xac \xf0\x9f\x98\x80 \xc2\xa0", -1},
                 {"a\xff\xfe", 1}, {"\xc0\xaf", 0}, {"xx\xed\xa0\x80", 2},
                 {"\xf4\x90\x80\x80", 0}, {"ok\xe2\x82", 2}, {"\x80", 0}};
    for (size_t i = 0; i < sizeof cases / sizeof cases[0]; i++)
        ASSERT_EQ_INT(web_utf8_bad_at(cases[i].s, strlen(cases[i].s)), cases[i].bad_at);
    setup(1);
    int a = fox_open(&F, (void *)1);
    drain(a, NULL);
    rx(a, "{\"op\":\"setParameters\",\"parameters\":[{\"name\":\"xi_p\",\"value\":0.082}],"
          "\"id\":\"\xff\xfe\"}");
    ASSERT_CONTAINS(drain(a, NULL), "a text frame refused: invalid UTF-8 at byte 73 (JSON text "
                    "must be UTF-8)");
    unsigned char fr[64] = {0x01, 5, 0, 0, 0};
    const char *body = "{\"op\":\"pause\",\"id\":\"\xc0\xaf\"}";
    rx(a, "{\"op\":\"advertise\",\"channels\":[{\"id\":5,\"topic\":\"/cmd\","
          "\"encoding\":\"json\"}]}");
    memcpy(fr + 5, body, strlen(body));
    fox_rx(&F, a, fr, 5 + strlen(body), 1);
    ASSERT_CONTAINS(drain(a, NULL), "/cmd: invalid UTF-8 at byte 20");
    ASSERT_EQ_INT(K.cmds, 0); /* nothing reached the daemon */
    teardown();
}

static void test_open_info_advertise(void)
{
    setup(0);
    int ci = fox_open(&F, (void *)1);
    ASSERT_EQ_INT(ci, 0);
    const char *t = drain(ci, NULL);
    ASSERT_CONTAINS(t, "\"op\":\"serverInfo\"");
    ASSERT_CONTAINS(t, "\"capabilities\":[\"parameters\",\"parametersSubscribe\",\"time\"]");
    ASSERT_CONTAINS(t, "\"topic\":\"/scope\"");
    ASSERT_CONTAINS(t, "\"schemaEncoding\":\"jsonschema\"");
    ASSERT_TRUE(fox_open(&F, (void *)2) == 1);
    ASSERT_TRUE(fox_open(&F, (void *)3) == -1); /* max_clients 2 */
    teardown();
}

/* Each bad input: a status error on that client, the other one untouched. */
static void test_bad_inputs(void)
{
    static const char *const bad[] = {
        "not json at all", "[1,2]", "{\"op\":3}", "{\"nop\":\"x\"}", "{\"op\":\"dance\"}",
        "{\"op\":\"subscribe\",\"subscriptions\":[{\"id\":1,\"channelId\":99}]}",
        "{\"op\":\"subscribe\",\"subscriptions\":[{\"id\":-1,\"channelId\":3}]}",
        "{\"op\":\"subscribe\",\"subscriptions\":\"x\"}",
        "{\"op\":\"unsubscribe\",\"subscriptionIds\":[42]}",
        "{\"op\":\"setParameters\",\"parameters\":[{\"name\":\"omega\",\"value\":1.3}]}",
        "{\"op\":\"advertise\",\"channels\":[{\"id\":1,\"topic\":\"/cmd\",\"encoding\":\"json\"}]}",
        "{\"op\":\"getParameters\",\"parameterNames\":7}"};
    setup(0);
    int a = fox_open(&F, (void *)1), b = fox_open(&F, (void *)2);
    drain(a, NULL), drain(b, NULL);
    for (size_t i = 0; i < sizeof bad / sizeof bad[0]; i++) {
        rx(a, bad[i]);
        const char *t = drain(a, NULL);
        if (!strstr(t, "\"level\":2"))
            TEST_FAIL_("no status error for %s: %s", bad[i], t);
    }
    const unsigned char garbage[] = {0x01, 0, 0, 0, 9, '{', '}'}, svc[] = {0x02, 1, 2}, odd[] = {0x7f};
    fox_rx(&F, a, garbage, sizeof garbage, 1);
    fox_rx(&F, a, svc, sizeof svc, 1);
    fox_rx(&F, a, odd, sizeof odd, 1);
    fox_rx(&F, a, odd, 0, 1);
    const char *t = drain(a, NULL);
    ASSERT_CONTAINS(t, "clientPublish needs wgweb --allow-commands");
    ASSERT_CONTAINS(t, "services are not supported");
    ASSERT_CONTAINS(t, "unknown opcode");
    ASSERT_CONTAINS(t, "empty");
    ASSERT_EQ_INT(K.cmds, 0); /* nothing reached the daemon */
    ASSERT_STR(drain(b, NULL), ""); /* the other client saw nothing */
    teardown();
}

static void test_subscribe_publish_drop(void)
{
    int nb;
    setup(0);
    int a = fox_open(&F, (void *)1), b = fox_open(&F, (void *)2);
    drain(a, NULL), drain(b, NULL);
    rx(a, "{\"op\":\"subscribe\",\"subscriptions\":[{\"id\":7,\"channelId\":3}]}");
    rx(a, "{\"op\":\"subscribe\",\"subscriptions\":[{\"id\":7,\"channelId\":4}]}"); /* id reused */
    ASSERT_CONTAINS(drain(a, NULL), "already in use");
    ASSERT_TRUE(fox_wanted(&F, CHAN_SCOPE) && !fox_wanted(&F, CHAN_POINCARE));
    for (int i = 0; i < 20; i++)
        fox_publish(&F, CHAN_SCOPE, "{\"x_n\":1}", 9, 1000 + i);
    ASSERT_EQ_INT(F.queue_drops, 12); /* queue_len 8: a stalled reader keeps the newest 8 */
    jbuf out;
    int bin;
    jb_init_pre(&out, 16);
    ASSERT_TRUE(fox_frame(&F, a, &out, &bin) && bin);
    const unsigned char *p = (const unsigned char *)jb_text(&out);
    ASSERT_EQ_INT(p[0], 1);
    ASSERT_EQ_INT(p[1], 7);          /* subscription id, little-endian */
    ASSERT_EQ_INT(p[5] | p[6] << 8, 1000 + 12); /* timestamp of the oldest kept */
    ASSERT_EQ_INT(jb_len(&out), 13 + 9);
    jb_free(&out);
    drain(a, &nb);
    ASSERT_EQ_INT(nb, 7);
    ASSERT_STR(drain(b, &nb), ""); /* b never subscribed */
    ASSERT_EQ_INT(nb, 0);
    rx(a, "{\"op\":\"unsubscribe\",\"subscriptionIds\":[7]}");
    ASSERT_TRUE(!fox_wanted(&F, CHAN_SCOPE));
    teardown();
}

static wormgear_params_t *params_msg(double omega)
{
    static char *names[] = {"omega", "xi_p"}, *units[] = {"1", "1"};
    static double value[2], mn[] = {0.01, 0}, mx[] = {10, 2}, def[] = {1, 0.08};
    static int8_t ramp[] = {1, 0};
    static wormgear_params_t m;
    value[0] = omega, value[1] = 0.08;
    m.n = 2, m.name = names, m.unit = units, m.value = value, m.min = mn, m.max = mx;
    m.def = def, m.rampable = ramp;
    return &m;
}

/* One message with 1,100 bad entries gets 8 statuses and a line counting
 * the rest, and the client stays (each entry's status filled the control
 * queue, and the client was dropped without a word: a review). */
static void test_many_refusals_one_message(void)
{
    setup(1);
    int a = fox_open(&F, (void *)1);
    drain(a, NULL);
    static char big[40000];
    size_t n = (size_t)snprintf(big, sizeof big, "{\"op\":\"subscribe\",\"subscriptions\":[");
    for (int i = 0; i < 1100; i++)
        n += (size_t)snprintf(big + n, sizeof big - n, "%s{\"id\":%d,\"channelId\":999}",
                              i ? "," : "", i);
    snprintf(big + n, sizeof big - n, "]}");
    rx(a, big);
    const char *t = drain(a, NULL);
    int lines = 0;
    for (const char *q = t; (q = strchr(q, '\n')); q++)
        lines++;
    ASSERT_EQ_INT(lines, 9);
    ASSERT_CONTAINS(t, "subscribe: unknown channel id 999");
    ASSERT_CONTAINS(t, "... and 1092 more refusals of that message, not shown (at most 8 "
                    "statuses a message)");
    ASSERT_TRUE(F.cl[a].used && F.kicked == 0);
    rx(a, "{\"op\":\"getParameters\",\"parameterNames\":[],\"id\":\"g\"}");
    ASSERT_TRUE(strstr(drain(a, NULL), "parameterValues") != NULL); /* still served */
    teardown();
}

static void test_parameters(void)
{
    setup(1);
    int a = fox_open(&F, (void *)1);
    ASSERT_CONTAINS(drain(a, NULL), "\"clientPublish\"],\"supportedEncodings\":[\"json\"]");
    fox_params(&F, params_msg(1.0));
    rx(a, "{\"op\":\"getParameters\",\"parameterNames\":[],\"id\":\"g\"}");
    ASSERT_CONTAINS(drain(a, NULL), "{\"name\":\"omega\",\"value\":1,\"type\":\"float64\"}");
    rx(a, "{\"op\":\"subscribeParameterUpdates\",\"parameterNames\":[\"omega\"]}");
    rx(a, "{\"op\":\"setParameters\",\"parameters\":[{\"name\":\"omega\",\"value\":12}],\"id\":\"s\"}");
    ASSERT_STR(K.last_op, "set");
    ASSERT_STR(K.last_name0, "omega");
    wormgear_ack_t ack = {.client = "me", .cmd_seq = K.cmds, .op = "set", .accepted = 0,
                          .code = "ERANGE", .message = "omega = 12 out of range [0.01, 10]"};
    char id[64];
    ack.cmd_utime = 1700000000000000 + 1000 * K.cmds - 1; /* another command's (same seq) */
    ASSERT_EQ_INT(fox_ack_owner(&F, &ack, "me", id, sizeof id), 0);
    ack.cmd_utime += 1; /* this one's: client, seq and utime */
    ASSERT_EQ_INT(fox_ack_owner(&F, &ack, "me", id, sizeof id), F.cl[a].id);
    ASSERT_STR(id, "s");
    fox_ack(&F, &ack, "me");
    const char *t = drain(a, NULL);
    ASSERT_CONTAINS(t, "ERANGE omega = 12 out of range [0.01, 10]");
    ASSERT_CONTAINS(t, "\"value\":1,\"type\":\"float64\"}],\"id\":\"s\"");
    fox_params(&F, params_msg(1.3)); /* pushed to the subscriber */
    ASSERT_CONTAINS(drain(a, NULL), "{\"name\":\"omega\",\"value\":1.3");
    fox_params(&F, params_msg(1.3)); /* unchanged: nothing */
    ASSERT_STR(drain(a, NULL), "");
    rx(a, "{\"op\":\"setParameters\",\"parameters\":[{\"name\":\"omega\",\"value\":2}],\"id\":\"t\"}");
    fox_tick(&F, 5.0); /* no ACK: a status error and the current value */
    ASSERT_CONTAINS(drain(a, NULL), "no ACK from the daemon");
    /* an answer the bridge's key did not verify: not taken, and the timeout says what it was */
    rx(a, "{\"op\":\"setParameters\",\"parameters\":[{\"name\":\"omega\",\"value\":2}],\"id\":\"u\"}");
    wormgear_ack_t forged = {.client = "me", .cmd_seq = K.cmds, .op = "set", .accepted = 1,
                             .code = "OK", .message = "forged",
                             .cmd_utime = 1700000000000000 + 1000 * K.cmds};
    fox_ack_unverified(&F, &forged, "me");
    ASSERT_STR(drain(a, NULL), "");
    fox_tick(&F, 10.0);
    t = drain(a, NULL);
    ASSERT_CONTAINS(t, "an answer came that is not signed with the bridge's key (OK: forged)");
    ASSERT_CONTAINS(t, "\"value\":1.3,\"type\":\"float64\"}],\"id\":\"u\""); /* not applied */
    teardown();
}

static void test_client_publish(void)
{
    setup(1);
    int a = fox_open(&F, (void *)1);
    drain(a, NULL);
    rx(a, "{\"op\":\"advertise\",\"channels\":[{\"id\":5,\"topic\":\"/cmd\",\"encoding\":\"json\",\"schemaName\":\"c\"}]}");
    rx(a, "{\"op\":\"advertise\",\"channels\":[{\"id\":6,\"topic\":\"/other\",\"encoding\":\"json\"}]}");
    ASSERT_CONTAINS(drain(a, NULL), "only topic '/cmd'");
    unsigned char fr[128] = {0x01, 5, 0, 0, 0};
    const char *body = "{\"op\":\"set\",\"params\":{\"omega\":1.2},\"at_section\":true,\"id\":\"x\"}";
    memcpy(fr + 5, body, strlen(body));
    fox_rx(&F, a, fr, 5 + strlen(body), 1);
    ASSERT_STR(K.last_op, "set");
    ASSERT_EQ_INT(K.last_at_section, 1);
    ASSERT_NEAR(K.last_v0, 1.2, 0);
    memcpy(fr + 5, "{oops", 5);
    fox_rx(&F, a, fr, 10, 1);
    /* parsed strictly: text after the value, a key twice, a NUL in a
     * string are refused (cJSON ran the get, the first "op", "omega") */
    static const char *const bent[] = {"{\"op\":\"get\"}garbage", "{\"op\":\"get\",\"op\":\"pause\"}",
                                       "{\"op\":\"set\",\"params\":{\"omega\\u0000x\":0.6}}"};
    for (int i = 0; i < 3; i++) {
        memcpy(fr + 5, bent[i], strlen(bent[i]));
        fox_rx(&F, a, fr, 5 + strlen(bent[i]), 1);
    }
    /* a raw NUL (not the escape): cJSON took it as the string's end and
     * set omega (a hostile-input review) */
    static const char raw[] = "{\"op\":\"set\",\"params\":{\"omega\0zzz\":1.5}}";
    memcpy(fr + 5, raw, sizeof raw - 1);
    fox_rx(&F, a, fr, 5 + sizeof raw - 1, 1);
    fr[1] = 9; /* unknown client channel */
    fox_rx(&F, a, fr, 10, 1);
    const char *t = drain(a, NULL);
    ASSERT_CONTAINS(t, "a control byte 0x00 at byte 28");
    ASSERT_CONTAINS(t, "/cmd: not JSON (at byte");
    ASSERT_CONTAINS(t, "text after the JSON value, at byte 12 of 19");
    ASSERT_CONTAINS(t, "the key 'op' twice in one object");
    ASSERT_CONTAINS(t, "a string with a NUL");
    ASSERT_CONTAINS(t, "unknown client channel id");
    ASSERT_EQ_INT(K.cmds, 1);
    /* the transport cannot send: the client is told why, as an error */
    K.refuse = "LCM could not send it on T_CMD: Network is unreachable";
    fr[1] = 5;
    memcpy(fr + 5, "{\"op\":\"pause\"}", 14);
    fox_rx(&F, a, fr, 19, 1);
    t = drain(a, NULL);
    ASSERT_CONTAINS(t, "\"level\":2");
    ASSERT_CONTAINS(t, "pause: not sent to the daemon: LCM could not send it on T_CMD: Network is "
                       "unreachable");
    ASSERT_EQ_INT(K.cmds, 1);
    teardown();
}

/* A step is answered when its steps are done: after the timeout the client
 * was told "no ACK ... is wormgeard running?" and the ACK that came later
 * was dropped (its slot freed). Now the status names op and id and says it
 * may still run, and the late ACK is a second, final status for that id. */
static void test_late_ack(void)
{
    setup(1);
    int a = fox_open(&F, (void *)1);
    rx(a, "{\"op\":\"advertise\",\"channels\":[{\"id\":5,\"topic\":\"/cmd\","
          "\"encoding\":\"json\"}]}");
    drain(a, NULL);
    unsigned char fr[128] = {0x01, 5, 0, 0, 0};
    const char *step = "{\"op\":\"step\",\"nsteps\":100000000000,\"id\":\"s1\"}";
    memcpy(fr + 5, step, strlen(step));
    fox_rx(&F, a, fr, 5 + strlen(step), 1);
    int64_t step_seq = K.cmds, step_utime = 1700000000000000 + 1000 * K.cmds;
    const char *pause = "{\"op\":\"pause\"}";
    memcpy(fr + 5, pause, strlen(pause));
    fox_rx(&F, a, fr, 5 + strlen(pause), 1);
    fox_tick(&F, 5.0);
    const char *t = drain(a, NULL);
    ASSERT_CONTAINS(t, "{\"op\":\"status\",\"level\":1,\"message\":\"step (id \\\"s1\\\"): no "
                    "ACK within 1 s, but the daemon answers it only when done, so it may still be "
                    "running it (pause cancels a step)");
    ASSERT_CONTAINS(t, "\"level\":2,\"message\":\"pause (no id): no ACK from the daemon within "
                    "1 s (is wormgeard running on T_?)\"");
    fox_tick(&F, 10.0); /* said once */
    ASSERT_STR(drain(a, NULL), "");
    wormgear_ack_t ack = {.client = "me", .cmd_seq = step_seq, .cmd_utime = step_utime,
                          .op = "step", .accepted = 1, .code = "OK",
                          .message = "100000000000 steps done"};
    char id[64];
    ASSERT_EQ_INT(fox_ack_owner(&F, &ack, "me", id, sizeof id), F.cl[a].id);
    ASSERT_STR(id, "s1"); /* so /ack carries request_id s1 */
    fox_ack(&F, &ack, "me");
    ASSERT_CONTAINS(drain(a, NULL), "\"level\":0,\"message\":\"step (id \\\"s1\\\"): the "
                    "daemon's ACK came after all: OK 100000000000 steps done\"");
    fox_ack(&F, &ack, "me"); /* final: the slot is free */
    ASSERT_STR(drain(a, NULL), "");
    teardown();
}

/* An object's members are counted before its keys are compared: each of
 * the first 1024 was compared with all (~1024 n strcmp), so one 64 KiB
 * frame of 6,663 keys cost 0.08-0.19 s (a review). The limit is what a
 * message can need (a set's params); a key twice is still refused. */
static void test_members_limit(void)
{
    static char big[70000];
    char why[200];
    size_t n = (size_t)snprintf(big, sizeof big, "{");
    int k = 0;
    while (n < 65536 - 20)
        n += (size_t)snprintf(big + n, sizeof big - n, "%s\"k%d\":1", k ? "," : "", k), k++;
    n += (size_t)snprintf(big + n, sizeof big - n, "}");
    ASSERT_TRUE(web_json_parse(big, n, why, sizeof why) == NULL);
    char want[200];
    snprintf(want, sizeof want, "an object with %d members: at most 64 (the most any message "
             "has: a set's 'params', 64 parameters)", k);
    ASSERT_STR(why, want);
    for (int members = 64; members <= 65; members++) { /* the limit, and one more */
        n = (size_t)snprintf(big, sizeof big, "{\"op\":\"set\",\"params\":{");
        for (int i = 0; i < members; i++)
            n += (size_t)snprintf(big + n, sizeof big - n, "%s\"p%d\":1", i ? "," : "", i);
        n += (size_t)snprintf(big + n, sizeof big - n, "}}");
        cJSON *j = web_json_parse(big, n, why, sizeof why);
        ASSERT_EQ_INT(j != NULL, members == 64);
        if (j) {
            web_cmd c;
            ASSERT_EQ_INT(web_cmd_from_json(&c, j, why, sizeof why), 0); /* a legitimate set */
            ASSERT_EQ_INT(c.cmd.nparams, 64);
        } else {
            ASSERT_CONTAINS(why, "an object with 65 members: at most 64");
        }
        cJSON_Delete(j);
    }
    n = (size_t)snprintf(big, sizeof big, "{\"op\":\"set\",\"params\":{");
    for (int i = 0; i < 63; i++)
        n += (size_t)snprintf(big + n, sizeof big - n, "\"p%d\":1,", i);
    n += (size_t)snprintf(big + n, sizeof big - n, "\"p7\":2}}"); /* 64 members, p7 twice */
    ASSERT_TRUE(web_json_parse(big, n, why, sizeof why) == NULL);
    ASSERT_STR(why, "the key 'p7' twice in one object (each key once)");
}

TEST_MAIN(TEST(test_jbuf), TEST(test_many_refusals_one_message), TEST(test_queue_drops_oldest),
          TEST(test_thin_scope_stride),
          TEST(test_thin_rate_cap), TEST(test_cmd_json), TEST(test_open_info_advertise),
          TEST(test_bad_inputs), TEST(test_subscribe_publish_drop), TEST(test_parameters),
          TEST(test_client_publish), TEST(test_utf8),
          TEST(test_late_ack), TEST(test_members_limit))

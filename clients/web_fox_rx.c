/* web_fox_rx.c - Foxglove protocol: what a client sends. Each malformed
 * request is answered with a status error on that client only. */
#include <cjson/cJSON.h>
#include <math.h>
#include <stdio.h>
#include <string.h>

#include "msg_check.h"
#include "web_cmd.h"
#include "web_fox_int.h"

/* A JSON number that is an integer in [0, 2^32). */
static int get_u32(const cJSON *v, int64_t *out)
{
    if (!cJSON_IsNumber(v) || !(v->valuedouble >= 0 && v->valuedouble < 4294967296.0) ||
        v->valuedouble != floor(v->valuedouble))
        return -1;
    *out = (int64_t)v->valuedouble;
    return 0;
}

static int sub_in_use(const fox_client *c, int64_t id)
{
    for (int k = 1; k < CHAN_N; k++)
        if (c->sub[k] == id)
            return k;
    return 0;
}

static void subscribe_one(fox *f, int ci, const cJSON *s)
{
    fox_client *c = &f->cl[ci];
    int64_t id, ch;
    if (get_u32(cJSON_GetObjectItemCaseSensitive(s, "id"), &id) ||
        get_u32(cJSON_GetObjectItemCaseSensitive(s, "channelId"), &ch)) {
        fox_status(f, ci, 2, "subscribe: each subscription needs integer 'id' and 'channelId'");
    } else if (ch < 1 || ch >= CHAN_N) {
        fox_status(f, ci, 2, "subscribe: unknown channel id %lld", (long long)ch);
    } else if (sub_in_use(c, id)) {
        fox_status(f, ci, 2, "subscribe: subscription id %lld is already in use", (long long)id);
    } else if (c->sub[ch] >= 0) {
        fox_status(f, ci, 2, "subscribe: channel %lld (%s) is already subscribed", (long long)ch,
                   msg_topic((int)ch));
    } else {
        c->sub[ch] = id;
    }
}

static void op_subscribe(fox *f, int ci, const cJSON *j)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(j, "subscriptions"), *s;
    if (!cJSON_IsArray(a)) {
        fox_status(f, ci, 2, "subscribe: 'subscriptions' must be an array");
        return;
    }
    cJSON_ArrayForEach(s, a) subscribe_one(f, ci, s);
}

static void op_unsubscribe(fox *f, int ci, const cJSON *j)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(j, "subscriptionIds"), *s;
    int64_t id;
    if (!cJSON_IsArray(a)) {
        fox_status(f, ci, 2, "unsubscribe: 'subscriptionIds' must be an array");
        return;
    }
    cJSON_ArrayForEach(s, a)
    {
        int ch = get_u32(s, &id) ? 0 : sub_in_use(&f->cl[ci], id);
        if (ch)
            f->cl[ci].sub[ch] = -1;
        else
            fox_status(f, ci, 2, "unsubscribe: unknown subscription id %s",
                       cJSON_IsNumber(s) ? "(number)" : "(not a number)");
    }
}

/* Client advertise: only the /cmd topic, JSON encoded. */
static void advertise_one(fox *f, int ci, const cJSON *ch)
{
    fox_client *c = &f->cl[ci];
    int64_t id;
    const cJSON *t = cJSON_GetObjectItemCaseSensitive(ch, "topic");
    const cJSON *e = cJSON_GetObjectItemCaseSensitive(ch, "encoding");
    if (get_u32(cJSON_GetObjectItemCaseSensitive(ch, "id"), &id)) {
        fox_status(f, ci, 2, "advertise: each channel needs an integer 'id'");
        return;
    }
    if (!cJSON_IsString(t) || strcmp(t->valuestring, "/cmd") != 0 || !cJSON_IsString(e) ||
        strcmp(e->valuestring, "json") != 0) {
        fox_status(f, ci, 2, "advertise: only topic '/cmd' with encoding 'json' can be published");
        return;
    }
    int free_k = -1;
    for (int k = 0; k < FOX_MAX_CCHAN; k++) {
        if (c->cchan[k] == id) {
            fox_status(f, ci, 2, "advertise: client channel %lld already advertised", (long long)id);
            return;
        }
        if (c->cchan[k] < 0 && free_k < 0)
            free_k = k;
    }
    if (free_k < 0)
        fox_status(f, ci, 2, "advertise: at most %d client channels", FOX_MAX_CCHAN);
    else
        c->cchan[free_k] = id;
}

static void op_advertise(fox *f, int ci, const cJSON *j)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(j, "channels"), *ch;
    if (!f->conf.allow_commands) {
        fox_status(f, ci, 2, "advertise refused: clientPublish needs wgweb --allow-commands");
        return;
    }
    if (!cJSON_IsArray(a)) {
        fox_status(f, ci, 2, "advertise: 'channels' must be an array");
        return;
    }
    cJSON_ArrayForEach(ch, a) advertise_one(f, ci, ch);
}

static int cchan_index(const fox_client *c, int64_t id)
{
    for (int k = 0; k < FOX_MAX_CCHAN; k++)
        if (c->cchan[k] == id)
            return k;
    return -1;
}

static void op_unadvertise(fox *f, int ci, const cJSON *j)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(j, "channelIds"), *s;
    int64_t id;
    if (!cJSON_IsArray(a)) {
        fox_status(f, ci, 2, "unadvertise: 'channelIds' must be an array");
        return;
    }
    cJSON_ArrayForEach(s, a)
    {
        int k = get_u32(s, &id) ? -1 : cchan_index(&f->cl[ci], id);
        if (k >= 0)
            f->cl[ci].cchan[k] = -1;
        else
            fox_status(f, ci, 2, "unadvertise: unknown client channel id");
    }
}

/* Optional string member "id" (at most 63 characters), or NULL. */
static const char *request_id(fox *f, int ci, const cJSON *j, int *bad)
{
    const cJSON *id = cJSON_GetObjectItemCaseSensitive(j, "id");
    *bad = 0;
    if (!id)
        return NULL;
    if (!cJSON_IsString(id) || strlen(id->valuestring) > 63) {
        fox_status(f, ci, 2, "'id' must be a string of at most 63 characters");
        *bad = 1;
        return NULL;
    }
    return id->valuestring;
}

/* The snapshot mask of a parameterNames array (all: empty or absent). */
static int names_mask(fox *f, int ci, const cJSON *j, uint64_t *mask, int *all)
{
    const cJSON *a = cJSON_GetObjectItemCaseSensitive(j, "parameterNames"), *s;
    *mask = 0;
    *all = !a || (cJSON_IsArray(a) && !a->child);
    if (a && !cJSON_IsArray(a)) {
        fox_status(f, ci, 2, "'parameterNames' must be an array of strings");
        return -1;
    }
    cJSON_ArrayForEach(s, a)
    {
        int i = cJSON_IsString(s) ? fox_param_index(f, s->valuestring) : -1;
        if (i < 0)
            fox_status(f, ci, 1, "unknown parameter %s", cJSON_IsString(s) ? s->valuestring : "(not a string)");
        else
            *mask |= 1ull << i;
    }
    return 0;
}

static void op_get_parameters(fox *f, int ci, const cJSON *j)
{
    uint64_t mask;
    int all, bad;
    const char *id = request_id(f, ci, j, &bad);
    if (!bad && names_mask(f, ci, j, &mask, &all) == 0)
        fox_param_values(f, ci, all, mask, id ? id : "");
}

static void op_param_updates(fox *f, int ci, const cJSON *j, int subscribe)
{
    uint64_t mask;
    int all;
    fox_client *c = &f->cl[ci];
    if (names_mask(f, ci, j, &mask, &all) != 0)
        return;
    if (subscribe) {
        c->psub_all |= all;
        c->psub_mask |= mask;
    } else if (all) {
        c->psub_all = 0;
        c->psub_mask = 0;
    } else {
        c->psub_mask &= ~mask;
    }
}

/* Send a command for client ci and remember it until its ACK. */
static void send_command(fox *f, int ci, web_cmd *wc, const char *id, int setparams)
{
    char why[320] = "no command hook";
    int64_t seq = f->hooks.command ? f->hooks.command(f->hooks.ctx, &wc->cmd, why, sizeof why) : -1;
    if (seq < 0) {
        fox_status(f, ci, 2, "%s: not sent to the daemon: %s", wc->op, why);
        return;
    }
    fox_pending *p = fox_pending_new(f);
    p->used = 1;
    p->seq = seq;
    p->utime = wc->cmd.utime; /* set by the hook as it sent it */
    p->client = f->cl[ci].id;
    p->setparams = setparams;
    p->deadline_s = f->now_s + f->conf.ack_timeout_s;
    snprintf(p->id, sizeof p->id, "%s", id ? id : "");
    snprintf(p->op, sizeof p->op, "%s", setparams ? "setParameters" : wc->op);
    p->late = !setparams && msg_cmd_late(wc->cmd.op, wc->cmd.at_section);
    for (int k = 0; setparams && k < wc->cmd.nparams && k < FOX_MAX_PARAMS; k++) {
        snprintf(p->name[k], sizeof p->name[k], "%s", wc->names[k]);
        p->value[k] = wc->values[k];
        p->n = k + 1;
    }
}

static void op_set_parameters(fox *f, int ci, const cJSON *j)
{
    web_cmd wc;
    char why[256];
    int bad;
    const char *id = request_id(f, ci, j, &bad);
    if (bad)
        return;
    if (!f->conf.allow_commands) {
        fox_status(f, ci, 2, "setParameters refused: wgweb runs without --allow-commands");
        fox_param_values(f, ci, 1, 0, id);
        return;
    }
    if (web_cmd_from_setparams(&wc, cJSON_GetObjectItemCaseSensitive(j, "parameters"), why,
                               sizeof why) != 0) {
        fox_status(f, ci, 2, "%s", why);
        return;
    }
    send_command(f, ci, &wc, id, 1);
}

typedef void (*op_fn)(fox *, int, const cJSON *);
static void op_sub_params(fox *f, int ci, const cJSON *j) { op_param_updates(f, ci, j, 1); }
static void op_unsub_params(fox *f, int ci, const cJSON *j) { op_param_updates(f, ci, j, 0); }

static const struct {
    const char *op;
    op_fn fn;
} ops[] = {
    {"subscribe", op_subscribe},
    {"unsubscribe", op_unsubscribe},
    {"advertise", op_advertise},
    {"unadvertise", op_unadvertise},
    {"getParameters", op_get_parameters},
    {"setParameters", op_set_parameters},
    {"subscribeParameterUpdates", op_sub_params},
    {"unsubscribeParameterUpdates", op_unsub_params},
};

static void rx_text(fox *f, int ci, const unsigned char *p, size_t len)
{
    char why[160];
    cJSON *j = web_json_parse(p, len, why, sizeof why);
    const cJSON *op = cJSON_GetObjectItemCaseSensitive(j, "op");
    if (!cJSON_IsObject(j) || !cJSON_IsString(op)) {
        f->bad_frames++;
        if (j)
            fox_status(f, ci, 2, "a text frame must be a JSON object with a string 'op'");
        else
            fox_status(f, ci, 2, "a text frame refused: %s", why);
        cJSON_Delete(j);
        return;
    }
    size_t k = 0;
    while (k < sizeof ops / sizeof ops[0] && strcmp(ops[k].op, op->valuestring) != 0)
        k++;
    if (k < sizeof ops / sizeof ops[0]) {
        ops[k].fn(f, ci, j);
    } else {
        f->bad_frames++;
        fox_status(f, ci, 2, "unknown op '%.64s'", op->valuestring);
    }
    cJSON_Delete(j);
}

static uint32_t get_le32(const unsigned char *p)
{
    return (uint32_t)p[0] | (uint32_t)p[1] << 8 | (uint32_t)p[2] << 16 | (uint32_t)p[3] << 24;
}

/* Client Message Data (0x01) on an advertised /cmd channel. */
static void rx_publish(fox *f, int ci, const unsigned char *p, size_t len)
{
    web_cmd wc;
    char why[256];
    if (len < 5 || cchan_index(&f->cl[ci], get_le32(p + 1)) < 0) {
        fox_status(f, ci, 2, "message data: %s", len < 5 ? "frame shorter than 5 bytes"
                                                          : "unknown client channel id");
        return;
    }
    cJSON *j = web_json_parse(p + 5, len - 5, why, sizeof why);
    if (!j || web_cmd_from_json(&wc, j, why, sizeof why) != 0)
        fox_status(f, ci, 2, "/cmd: %s", why);
    else
        send_command(f, ci, &wc, wc.id, 0);
    cJSON_Delete(j);
}

static void rx_frame(fox *f, int ci, const unsigned char *p, size_t len, int binary);

/* One client message, answered with at most FOX_RX_SAID_MAX statuses and a
 * line counting the rest. */
void fox_rx(fox *f, int ci, const unsigned char *p, size_t len, int binary)
{
    if (ci < 0 || ci >= FOX_MAX_CLIENTS || !f->cl[ci].used)
        return;
    f->rx_in = 1, f->rx_ci = ci, f->rx_said = f->rx_unsaid = 0;
    rx_frame(f, ci, p, len, binary);
    f->rx_in = 0;
    if (f->rx_unsaid)
        fox_status(f, ci, 2, "... and %d more refusals of that message, not shown (at most %d "
                   "statuses a message)", f->rx_unsaid, FOX_RX_SAID_MAX);
}

static void rx_frame(fox *f, int ci, const unsigned char *p, size_t len, int binary)
{
    if (!binary) {
        rx_text(f, ci, p, len);
    } else if (len >= 1 && p[0] == 0x01 && f->conf.allow_commands) {
        rx_publish(f, ci, p, len);
    } else {
        f->bad_frames++;
        fox_status(f, ci, 2, "binary frame refused: %s",
                   len < 1             ? "empty"
                   : p[0] == 0x01      ? "clientPublish needs wgweb --allow-commands"
                   : p[0] == 0x02      ? "services are not supported"
                                       : "unknown opcode");
    }
}

/* web_fox.c - Foxglove protocol: clients, queues, frames, parameters. */
#include "web_fox_int.h"

#include "wormgear/wg_key.h"

#include <stdarg.h>
#include <stdio.h>
#include <string.h>
#include <time.h>

static void build_advertise(fox *f, jbuf *b)
{
    jb_raw(b, "{\"op\":\"advertise\",\"channels\":[");
    for (int c = 1; c < CHAN_N; c++) {
        jb_item(b);
        jb_fmt(b, "{\"id\":%d,\"topic\":", c);
        jb_str(b, msg_topic(c));
        jb_raw(b, ",\"encoding\":\"json\",\"schemaName\":");
        jb_str(b, msg_schema_name(c));
        jb_raw(b, ",\"schemaEncoding\":\"jsonschema\",\"schema\":");
        jb_str(b, msg_schema(f->conf.schemas, c));
        jb_raw(b, "}");
    }
    jb_raw(b, "]}");
}

int fox_init(fox *f, const fox_conf *conf, const fox_hooks *hooks)
{
    memset(f, 0, sizeof *f);
    f->conf = *conf;
    snprintf(f->name, sizeof f->name, "%s", conf->name);
    snprintf(f->prefix, sizeof f->prefix, "%s", conf->prefix);
    snprintf(f->url, sizeof f->url, "%s", conf->url);
    f->conf.name = f->name;
    f->conf.prefix = f->prefix;
    f->conf.url = f->url;
    f->hooks = *hooks;
    f->next_id = 1;
    snprintf(f->session, sizeof f->session, "%lld", (long long)time(NULL));
    jb_init(&f->tmp);
    build_advertise(f, &f->tmp);
    f->advertise = f->tmp.oom ? NULL : wq_msg_new(jb_text(&f->tmp), jb_len(&f->tmp));
    jb_reset(&f->tmp);
    return f->advertise ? 0 : -1;
}

void fox_fini(fox *f)
{
    for (int ci = 0; ci < FOX_MAX_CLIENTS; ci++)
        if (f->cl[ci].used)
            fox_close(f, ci);
    wq_msg_unref(f->advertise);
    f->advertise = NULL;
    jb_free(&f->tmp);
}

static void wake(fox *f, int ci)
{
    if (f->hooks.wake)
        f->hooks.wake(f->hooks.ctx, f->cl[ci].conn);
}

void fox_ctrl(fox *f, int ci, const char *text, size_t len)
{
    fox_client *c = &f->cl[ci];
    wq_msg *m = wq_msg_new(text, len);
    wq_item it = {.m = m, .kind = WQ_TEXT};
    if (!m)
        return;
    if (!wq_fits(&c->ctrl, &it)) { /* never drop control: drop the client */
        f->kicked++;
        if (f->hooks.kick)
            f->hooks.kick(f->hooks.ctx, c->conn);
    } else {
        wq_push(&c->ctrl, it);
        wake(f, ci);
    }
    wq_msg_unref(m);
}

static void send_server_info(fox *f, int ci)
{
    jbuf *b = &f->tmp;
    jb_reset(b);
    jb_raw(b, "{\"op\":\"serverInfo\",\"name\":");
    jb_str(b, f->conf.name);
    jb_raw(b, ",\"capabilities\":[\"parameters\",\"parametersSubscribe\",\"time\"");
    if (f->conf.allow_commands)
        jb_raw(b, ",\"clientPublish\"],\"supportedEncodings\":[\"json\"");
    jb_raw(b, "],\"metadata\":{\"prefix\":");
    jb_str(b, f->conf.prefix);
    jb_raw(b, ",\"url\":");
    jb_str(b, f->conf.url);
    jb_fmt(b, ",\"commands\":\"%s\",\"cmdTopic\":\"/cmd\",\"cmdSchema\":\"wormgear.Command\"}",
           f->conf.allow_commands ? "allowed" : "refused");
    jb_raw(b, ",\"sessionId\":");
    jb_str(b, f->session);
    jb_raw(b, "}");
    fox_ctrl(f, ci, jb_text(b), jb_len(b));
}

int fox_open(fox *f, void *conn)
{
    int ci = -1, used = fox_nclients(f);
    for (int i = 0; i < FOX_MAX_CLIENTS && ci < 0 && used < f->conf.max_clients; i++)
        if (!f->cl[i].used)
            ci = i;
    if (ci < 0)
        return -1;
    fox_client *c = &f->cl[ci];
    memset(c, 0, sizeof *c);
    if (wq_init(&c->ctrl, 1024, 8u << 20) != 0 ||
        wq_init(&c->data, f->conf.queue_len, f->conf.queue_bytes) != 0) {
        wq_fini(&c->ctrl);
        return -1;
    }
    c->used = 1;
    c->id = f->next_id++;
    c->conn = conn;
    for (int k = 0; k < CHAN_N; k++)
        c->sub[k] = -1;
    for (int k = 0; k < FOX_MAX_CCHAN; k++)
        c->cchan[k] = -1;
    send_server_info(f, ci);
    fox_ctrl(f, ci, (const char *)f->advertise->data, f->advertise->len);
    return ci;
}

void fox_close(fox *f, int ci)
{
    if (ci < 0 || ci >= FOX_MAX_CLIENTS || !f->cl[ci].used)
        return;
    fox_client *c = &f->cl[ci];
    for (int k = 0; k < FOX_MAX_PENDING; k++)
        if (f->pend[k].used && f->pend[k].client == c->id)
            f->pend[k].client = 0; /* the ACK still goes to /ack */
    wq_fini(&c->ctrl);
    wq_fini(&c->data);
    memset(c, 0, sizeof *c);
}

void fox_status(fox *f, int ci, int level, const char *fmt, ...)
{
    char msg[1024];
    va_list ap;
    if (f->rx_in && ci == f->rx_ci && f->rx_said++ >= FOX_RX_SAID_MAX) {
        f->rx_unsaid++; /* one message with 1,100 bad entries: as many statuses filled */
        f->cl[ci].errors += level == 2; /* the control queue, and the client was dropped */
        return;
    }
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    jbuf *b = &f->tmp;
    jb_reset(b);
    jb_fmt(b, "{\"op\":\"status\",\"level\":%d,\"message\":", level);
    jb_str(b, msg);
    jb_raw(b, "}");
    for (int i = 0; i < FOX_MAX_CLIENTS; i++)
        if (f->cl[i].used && (ci < 0 || i == ci)) {
            if (level == 2)
                f->cl[i].errors++;
            fox_ctrl(f, i, jb_text(b), jb_len(b));
        }
}

static void put_u32(unsigned char *p, uint32_t v)
{
    for (int i = 0; i < 4; i++)
        p[i] = (unsigned char)(v >> (8 * i));
}

static void put_u64(unsigned char *p, uint64_t v)
{
    for (int i = 0; i < 8; i++)
        p[i] = (unsigned char)(v >> (8 * i));
}

int fox_frame(fox *f, int ci, jbuf *out, int *binary)
{
    fox_client *c = &f->cl[ci];
    wq_item it;
    unsigned char h[13];
    jb_reset(out);
    if (wq_pop(&c->ctrl, &it) || wq_pop(&c->data, &it)) {
        *binary = it.kind != WQ_TEXT;
        if (it.kind == WQ_DATA) {
            h[0] = 0x01;
            put_u32(h + 1, it.sub_id);
            put_u64(h + 5, it.ts_ns);
            jb_mem(out, h, 13);
        } else if (it.kind == WQ_TIME) {
            h[0] = 0x02;
            put_u64(h + 1, it.ts_ns);
            jb_mem(out, h, 9);
        }
        if (it.m)
            jb_mem(out, it.m->data, it.m->len);
        wq_msg_unref(it.m);
        c->sent++;
        return !out->oom;
    }
    return 0;
}

int fox_has_frames(const fox *f, int ci)
{
    return f->cl[ci].used && (f->cl[ci].ctrl.count || f->cl[ci].data.count);
}

int fox_wanted(const fox *f, int c)
{
    for (int i = 0; i < FOX_MAX_CLIENTS; i++)
        if (f->cl[i].used && f->cl[i].sub[c] >= 0)
            return 1;
    return 0;
}

static void push_data(fox *f, int ci, wq_item it)
{
    fox_client *c = &f->cl[ci];
    int was_empty = c->data.count == 0 && c->ctrl.count == 0;
    f->queue_drops += wq_push(&c->data, it);
    if (was_empty)
        wake(f, ci);
}

void fox_publish(fox *f, int c, const char *json, size_t len, uint64_t ts_ns)
{
    if (c <= 0 || c >= CHAN_N || !fox_wanted(f, c))
        return;
    wq_msg *m = wq_msg_new(json, len);
    if (!m)
        return;
    for (int i = 0; i < FOX_MAX_CLIENTS; i++)
        if (f->cl[i].used && f->cl[i].sub[c] >= 0) {
            wq_item it = {.m = m, .ts_ns = ts_ns, .sub_id = (uint32_t)f->cl[i].sub[c],
                          .kind = WQ_DATA};
            push_data(f, i, it);
        }
    wq_msg_unref(m);
}

void fox_time(fox *f, uint64_t ts_ns)
{
    wq_item it = {.ts_ns = ts_ns, .kind = WQ_TIME};
    for (int i = 0; i < FOX_MAX_CLIENTS; i++)
        if (f->cl[i].used)
            push_data(f, i, it);
}

void fox_readvertise(fox *f)
{
    for (int i = 0; i < FOX_MAX_CLIENTS; i++)
        if (f->cl[i].used)
            fox_ctrl(f, i, (const char *)f->advertise->data, f->advertise->len);
}

int fox_param_index(const fox *f, const char *name)
{
    for (int i = 0; i < f->np; i++)
        if (!strcmp(f->pname[i], name))
            return i;
    return -1;
}

void fox_param_values(fox *f, int ci, int all, uint64_t mask, const char *id)
{
    jbuf *b = &f->tmp;
    jb_reset(b);
    jb_raw(b, "{\"op\":\"parameterValues\",\"parameters\":[");
    for (int i = 0; i < f->np; i++)
        if (all || (mask >> i & 1)) {
            jb_item(b);
            jb_raw(b, "{\"name\":");
            jb_str(b, f->pname[i]);
            jb_raw(b, ",\"value\":");
            jb_num(b, f->pvalue[i]);
            jb_raw(b, ",\"type\":\"float64\"}");
        }
    jb_raw(b, "]");
    if (id) {
        jb_raw(b, ",\"id\":");
        jb_str(b, id);
    }
    jb_raw(b, "}");
    fox_ctrl(f, ci, jb_text(b), jb_len(b));
}

/* Take the table of a PARAMS message; the mask of what changed. */
static uint64_t take_params(fox *f, const wormgear_params_t *m)
{
    uint64_t changed = 0;
    int n = m->n < FOX_MAX_PARAMS ? m->n : FOX_MAX_PARAMS;
    int same_table = n == f->np;
    for (int i = 0; i < n && same_table; i++)
        same_table = !strcmp(f->pname[i], m->name[i]);
    for (int i = 0; i < n; i++) {
        if (!same_table || f->pvalue[i] != m->value[i])
            changed |= 1ull << i;
        snprintf(f->pname[i], sizeof f->pname[i], "%s", m->name[i]);
        f->pvalue[i] = m->value[i];
    }
    f->np = n;
    return changed;
}

void fox_params(fox *f, const wormgear_params_t *m)
{
    uint64_t changed = take_params(f, m);
    if (!changed)
        return;
    for (int i = 0; i < FOX_MAX_CLIENTS; i++) {
        fox_client *c = &f->cl[i];
        uint64_t want = changed & (c->psub_all ? ~0ull : c->psub_mask);
        if (c->used && want)
            fox_param_values(f, i, 0, want, NULL);
    }
}

static fox_pending *pending_of(const fox *f, const wormgear_ack_t *a, const char *client_id)
{
    if (strcmp(a->client, client_id) != 0)
        return NULL;
    for (int k = 0; k < FOX_MAX_PENDING; k++)
        if (f->pend[k].used && f->pend[k].seq == a->cmd_seq && f->pend[k].utime == a->cmd_utime)
            return (fox_pending *)&f->pend[k];
    return NULL;
}

unsigned fox_ack_owner(const fox *f, const wormgear_ack_t *a, const char *client_id, char *id,
                       size_t idlen)
{
    const fox_pending *p = pending_of(f, a, client_id);
    snprintf(id, idlen, "%s", p ? p->id : "");
    return p ? p->client : 0;
}

static int client_index(const fox *f, unsigned id)
{
    for (int i = 0; i < FOX_MAX_CLIENTS; i++)
        if (f->cl[i].used && f->cl[i].id == id)
            return i;
    return -1;
}

/* Answer a setParameters: the values asked for when applied, else the
 * daemon's current ones. The table itself follows PARAMS alone: the ACK
 * comes before the PARAMS the set causes, and that PARAMS is what pushes
 * the change to the parameter subscribers. */
static void answer_setparams(fox *f, int ci, const fox_pending *p, int applied)
{
    uint64_t mask = 0;
    double kept[FOX_MAX_PARAMS];
    memcpy(kept, f->pvalue, sizeof kept);
    for (int k = 0; k < p->n; k++) {
        int i = fox_param_index(f, p->name[k]);
        if (i >= 0) {
            mask |= 1ull << i;
            if (applied)
                f->pvalue[i] = p->value[k];
        }
    }
    fox_param_values(f, ci, 0, mask, p->id);
    memcpy(f->pvalue, kept, sizeof kept);
}

/* "step (id "s1")" or "step (no id)": what a status about a request names. */
static const char *label(const fox_pending *p, char *buf, size_t len)
{
    if (p->id[0])
        snprintf(buf, len, "%s (id \"%s\")", p->op, p->id);
    else
        snprintf(buf, len, "%s (no id)", p->op);
    return buf;
}

void fox_ack(fox *f, const wormgear_ack_t *a, const char *client_id)
{
    char what[100];
    fox_pending *p = pending_of(f, a, client_id);
    if (!p)
        return;
    int ci = client_index(f, p->client);
    if (ci >= 0 && p->overdue)
        fox_status(f, ci, a->accepted ? 0 : 2, "%s: the daemon's ACK came after all: %s %s",
                   label(p, what, sizeof what), a->code, a->message);
    else if (ci >= 0 && !a->accepted)
        fox_status(f, ci, 2, "%s refused by the daemon: %s %s", p->setparams ? "setParameters" : a->op,
                   a->code, a->message);
    if (ci >= 0 && p->setparams)
        answer_setparams(f, ci, p, a->accepted);
    p->used = 0;
}

void fox_ack_unverified(fox *f, const wormgear_ack_t *a, const char *client_id)
{
    fox_pending *p = pending_of(f, a, client_id);
    if (p)
        snprintf(p->unverified, sizeof p->unverified, "%s: %s", a->code, a->message);
}

fox_pending *fox_pending_new(fox *f)
{
    fox_pending *oldest = &f->pend[0];
    for (int k = 0; k < FOX_MAX_PENDING; k++) {
        if (!f->pend[k].used) {
            memset(&f->pend[k], 0, sizeof f->pend[k]);
            return &f->pend[k];
        }
        if (f->pend[k].deadline_s < oldest->deadline_s)
            oldest = &f->pend[k];
    }
    memset(oldest, 0, sizeof *oldest);
    return oldest;
}

void fox_tick(fox *f, double now_s)
{
    char what[100];
    f->now_s = now_s;
    for (int k = 0; k < FOX_MAX_PENDING; k++) {
        fox_pending *p = &f->pend[k];
        if (!p->used || p->overdue || now_s < p->deadline_s)
            continue;
        int ci = client_index(f, p->client);
        label(p, what, sizeof what);
        if (ci >= 0 && p->unverified[0])
            fox_status(f, ci, 2, "%s: no signed ACK within %g s: an answer came that is not "
                       "signed with the bridge's key (%s), and was not taken: "
                       WG_KEY_UNSIGNED_WHO, what, f->conf.ack_timeout_s, p->unverified);
        else if (ci >= 0 && p->late)
            fox_status(f, ci, 1, "%s: no ACK within %g s, but the daemon answers it only when "
                       "done, so it may still be running it (pause cancels a step); its ACK, "
                       "when it comes, follows as a status for this id", what,
                       f->conf.ack_timeout_s);
        else if (ci >= 0)
            fox_status(f, ci, 2, "%s: no ACK from the daemon within %g s (is wormgeard running "
                       "on %s?)", what, f->conf.ack_timeout_s, f->conf.prefix);
        if (ci >= 0 && p->setparams)
            answer_setparams(f, ci, p, 0);
        if (p->late && !p->unverified[0] && ci >= 0)
            p->overdue = 1; /* kept for its ACK (a slot reused first when all are taken) */
        else
            p->used = 0;
    }
}

int fox_nclients(const fox *f)
{
    int n = 0;
    for (int i = 0; i < FOX_MAX_CLIENTS; i++)
        n += f->cl[i].used;
    return n;
}

void fox_stats(const fox *f, jbuf *b)
{
    jb_key(b, "per_client");
    jb_raw(b, "[");
    for (int i = 0; i < FOX_MAX_CLIENTS; i++) {
        const fox_client *c = &f->cl[i];
        if (!c->used)
            continue;
        jb_item(b);
        jb_fmt(b,
               "{\"id\":%u,\"queue\":%zu,\"queue_bytes\":%zu,\"ctrl\":%zu,\"drops\":%llu,"
               "\"sent\":%llu,\"errors\":%llu}",
               c->id, c->data.count, c->data.bytes, c->ctrl.count,
               (unsigned long long)c->data.dropped, (unsigned long long)c->sent,
               (unsigned long long)c->errors);
    }
    jb_raw(b, "]");
}

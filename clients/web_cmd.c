/* web_cmd.c - JSON commands to cmd_t. */
#include "web_cmd.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "cli.h"
#include "wormgear/wg_sim.h"

static void cmd_clear(web_cmd *c)
{
    memset(c, 0, sizeof *c);
    c->cmd.op = c->op;
    c->cmd.name = c->name;
    c->cmd.unit = c->unit;
    c->cmd.client = (char *)"";
    c->cmd.names = c->name_ptr;
    c->cmd.values = c->values;
    for (int i = 0; i < WEB_CMD_MAX_PARAMS; i++)
        c->name_ptr[i] = c->names[i];
}

/* Copy string member key of j into dst (required or optional). */
static int get_str(const cJSON *j, const char *key, char *dst, size_t len, int required,
                   char *why, size_t whylen)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(j, key);
    if (!v && !required)
        return 0;
    if (!cJSON_IsString(v) || strlen(v->valuestring) >= len) {
        snprintf(why, whylen, "'%s' must be a string of at most %zu characters", key, len - 1);
        return -1;
    }
    snprintf(dst, len, "%s", v->valuestring);
    return 0;
}

/* Read number member key of j into *dst (required or optional). */
static int get_num(const cJSON *j, const char *key, double *dst, int required, char *why,
                   size_t whylen)
{
    const cJSON *v = cJSON_GetObjectItemCaseSensitive(j, key);
    if (!v && !required)
        return 0;
    if (!cJSON_IsNumber(v) || !isfinite(v->valuedouble)) {
        snprintf(why, whylen, "'%s' must be a number", key);
        return -1;
    }
    *dst = v->valuedouble;
    return 0;
}

/* Append name = value to a set command. */
static int add_param(web_cmd *c, const char *name, const cJSON *v, char *why, size_t whylen)
{
    if (c->cmd.nparams >= WEB_CMD_MAX_PARAMS) {
        snprintf(why, whylen, "at most %d parameters at once", WEB_CMD_MAX_PARAMS);
        return -1;
    }
    if (!name || !*name || strlen(name) >= sizeof c->names[0]) {
        snprintf(why, whylen, "a parameter name must be 1-%zu characters", sizeof c->names[0] - 1);
        return -1;
    }
    if (!cJSON_IsNumber(v)) {
        snprintf(why, whylen, "parameter '%s': value must be a number", name);
        return -1;
    }
    snprintf(c->names[c->cmd.nparams], sizeof c->names[0], "%s", name);
    c->values[c->cmd.nparams++] = v->valuedouble;
    return 0;
}

static int set_from_json(web_cmd *c, const cJSON *j, char *why, size_t whylen)
{
    const cJSON *p = cJSON_GetObjectItemCaseSensitive(j, "params"), *e;
    if (!cJSON_IsObject(p) || !p->child) {
        snprintf(why, whylen, "set: 'params' must be an object {name: value, ...}");
        return -1;
    }
    cJSON_ArrayForEach(e, p)
    {
        if (add_param(c, e->string, e, why, whylen) != 0)
            return -1;
    }
    const cJSON *at = cJSON_GetObjectItemCaseSensitive(j, "at_section");
    if (at && !cJSON_IsBool(at)) {
        snprintf(why, whylen, "set: 'at_section' must be true or false");
        return -1;
    }
    c->cmd.at_section = cJSON_IsTrue(at) ? 1 : 0;
    return 0;
}

static int ramp_from_json(web_cmd *c, const cJSON *j, char *why, size_t whylen)
{
    double from = 0;
    if (get_str(j, "param", c->names[0], sizeof c->names[0], 1, why, whylen) ||
        get_num(j, "to", &c->values[0], 1, why, whylen) ||
        get_num(j, "duration", &c->cmd.duration, 1, why, whylen))
        return -1;
    snprintf(c->unit, sizeof c->unit, "s");
    if (get_str(j, "unit", c->unit, sizeof c->unit, 0, why, whylen))
        return -1;
    if (cJSON_GetObjectItemCaseSensitive(j, "from")) {
        if (get_num(j, "from", &from, 1, why, whylen))
            return -1;
        c->cmd.has_from = 1;
        c->cmd.from = from;
    }
    c->cmd.nparams = 1;
    return 0;
}

/* mode: a rate, when given, in the daemon's range. On the wire rate 0
 * means "keep the current rate", so an explicit 0 (or -0) was taken as
 * that and answered OK; leaving it out keeps the rate. */
static int mode_from_json(web_cmd *c, const cJSON *j, char *why, size_t whylen)
{
    if (get_str(j, "mode", c->name, sizeof c->name, 1, why, whylen))
        return -1;
    const cJSON *r = cJSON_GetObjectItemCaseSensitive(j, "rate");
    if (!r)
        return 0;
    double v = cJSON_IsNumber(r) ? r->valuedouble : NAN;
    if (!(v >= WG_RATE_MIN && v <= WG_RATE_MAX)) {
        snprintf(why, whylen, "mode: 'rate' must be a number in [%g, %g] (the realtime factor, "
                 "1 = physical; leave it out to keep the current one)", WG_RATE_MIN, WG_RATE_MAX);
        return -1;
    }
    c->cmd.rate = v;
    return 0;
}

/* The op-specific fields of ops other than set and ramp. */
static int other_from_json(web_cmd *c, const cJSON *j, char *why, size_t whylen)
{
    double v = 0;
    if (!strcmp(c->op, "reset"))
        return get_str(j, "what", c->name, sizeof c->name, 0, why, whylen);
    if (!strcmp(c->op, "save") || !strcmp(c->op, "restore"))
        return get_str(j, "name", c->name, sizeof c->name, 1, why, whylen);
    if (!strcmp(c->op, "mode"))
        return mode_from_json(c, j, why, whylen);
    if (!strcmp(c->op, "step")) {
        if (get_num(j, "nsteps", &v, 1, why, whylen))
            return -1;
        if (!(v >= 1 && v <= 1e12) || v != floor(v)) { /* 1.5 went on as 1 */
            snprintf(why, whylen, "step: 'nsteps' must be a whole number in [1, 1e12]");
            return -1;
        }
        c->cmd.nsteps = (int64_t)v;
        return 0;
    }
    if (!strcmp(c->op, "contacts")) { /* wgctl contacts all|mesh|none [N] */
        if (get_str(j, "which", c->name, sizeof c->name, 1, why, whylen) ||
            get_num(j, "every", &v, 0, why, whylen))
            return -1;
        if (cJSON_GetObjectItemCaseSensitive(j, "every") &&
            (!(v >= 1 && v <= 9.007199254740992e15) || v != floor(v))) {
            snprintf(why, whylen, "contacts: 'every' must be a whole number >= 1");
            return -1;
        }
        c->cmd.nsteps = (int64_t)v;
        return 0;
    }
    if (!strcmp(c->op, "pause") || !strcmp(c->op, "resume") || !strcmp(c->op, "get"))
        return 0;
    snprintf(why, whylen,
             "unknown command op '%s' (set ramp pause resume reset step save restore get mode "
             "contacts)",
             c->op);
    return -1;
}

int web_cmd_from_json(web_cmd *c, const cJSON *j, char *why, size_t whylen)
{
    cmd_clear(c);
    if (!cJSON_IsObject(j)) {
        snprintf(why, whylen, "a command must be a JSON object with an 'op'");
        return -1;
    }
    if (get_str(j, "op", c->op, sizeof c->op, 1, why, whylen) ||
        get_str(j, "id", c->id, sizeof c->id, 0, why, whylen))
        return -1;
    if (!strcmp(c->op, "set"))
        return set_from_json(c, j, why, whylen);
    if (!strcmp(c->op, "ramp"))
        return ramp_from_json(c, j, why, whylen);
    return other_from_json(c, j, why, whylen);
}

int web_cmd_from_setparams(web_cmd *c, const cJSON *params, char *why, size_t whylen)
{
    const cJSON *e;
    cmd_clear(c);
    snprintf(c->op, sizeof c->op, "set");
    if (!cJSON_IsArray(params) || !params->child) {
        snprintf(why, whylen, "setParameters: 'parameters' must be a non-empty array");
        return -1;
    }
    cJSON_ArrayForEach(e, params)
    {
        const cJSON *n = cJSON_GetObjectItemCaseSensitive(e, "name");
        const cJSON *v = cJSON_GetObjectItemCaseSensitive(e, "value");
        if (!cJSON_IsString(n)) {
            snprintf(why, whylen, "setParameters: each parameter needs a string 'name'");
            return -1;
        }
        if (add_param(c, n->valuestring, v, why, whylen) != 0)
            return -1;
    }
    return 0;
}

/* A \u0000 escape in the text (a literal backslash, "\\", skipped). */
static long nul_escape_at(const char *p, size_t len)
{
    for (size_t i = 0; i + 1 < len; i++)
        if (p[i] == '\\') {
            if (p[i + 1] == 'u' && i + 5 < len && !strncmp(p + i + 2, "0000", 4))
                return (long)i;
            i++;
        }
    return -1;
}

/* The first object in v (depth first) with a key twice or too many
 * members: 1 with why, else 0. */
static int bad_object(const cJSON *v, char *why, size_t whylen)
{
    for (const cJSON *c = v ? v->child : NULL; c; c = c->next)
        if (bad_object(c, why, whylen))
            return 1;
    if (!cJSON_IsObject(v))
        return 0;
    long n = 0; /* counted before any key is compared: n*n strcmp cost 0.1 s a frame */
    for (const cJSON *a = v->child; a; a = a->next)
        n++;
    if (n > WEB_JSON_MEMBERS_MAX) {
        snprintf(why, whylen, "an object with %ld members: at most %d (the most any message "
                 "has: a set's 'params', %d parameters)", n, WEB_JSON_MEMBERS_MAX,
                 WEB_CMD_MAX_PARAMS);
        return 1;
    }
    for (const cJSON *a = v->child; a; a = a->next) {
        for (const cJSON *b = a->next; b; b = b->next)
            if (a->string && b->string && !strcmp(a->string, b->string)) {
                snprintf(why, whylen, "the key '%.40s' twice in one object (each key once)",
                         a->string);
                return 1;
            }
    }
    return 0;
}

long web_utf8_bad_at(const void *p, size_t len)
{
    const unsigned char *s = p;
    for (size_t i = 0; i < len;) {
        char seq[5] = {0}; /* cli_utf8_len reads up to 4 bytes: never past len */
        memcpy(seq, s + i, len - i < 4 ? len - i : 4);
        int n = s[i] < 0x80 ? 1 : cli_utf8_len(seq);
        if (n == 0 || (size_t)n > len - i)
            return (long)i;
        i += (size_t)n;
    }
    return -1;
}

cJSON *web_json_parse(const void *p, size_t len, char *why, size_t whylen)
{
    const char *s = p, *end = NULL;
    long at = web_utf8_bad_at(s, len);
    if (at >= 0) { /* cJSON took it, and our replies carried U+FFFD */
        snprintf(why, whylen, "invalid UTF-8 at byte %ld (JSON text must be UTF-8)", at);
        return NULL;
    }
    at = nul_escape_at(s, len);
    if (at >= 0) {
        snprintf(why, whylen, "a string with a NUL (\\u0000) at byte %ld", at);
        return NULL;
    }
    for (size_t i = 0; i < len; i++) { /* raw: cJSON took a NUL as a string's end */
        unsigned char c = (unsigned char)s[i];
        if (c < 0x20 && c != ' ' && c != '\t' && c != '\n' && c != '\r') {
            snprintf(why, whylen, "a control byte 0x%02x at byte %zu (JSON escapes them in "
                     "strings: \\u00%02x)", c, i, c);
            return NULL;
        }
    }
    cJSON *j = cJSON_ParseWithLengthOpts(s, len, &end, 0);
    if (!j) {
        snprintf(why, whylen, "not JSON (at byte %ld of %zu)", end ? (long)(end - s) : 0L, len);
        return NULL;
    }
    size_t k = (size_t)(end - s);
    while (k < len && (s[k] == ' ' || s[k] == '\t' || s[k] == '\n' || s[k] == '\r'))
        k++;
    if (k < len) {
        snprintf(why, whylen, "text after the JSON value, at byte %zu of %zu (one value a "
                 "message)", k, len);
    } else if (!bad_object(j, why, whylen)) {
        return j;
    }
    cJSON_Delete(j);
    return NULL;
}

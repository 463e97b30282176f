/* wg_snapshot.c - the snapshot file format (format 3; 2 read), text <-> wg_snapshot.
 *
 * One walk over the fields (walk()) defines the order and the keys; the
 * writer and the reader are two visitors of it, so they cannot disagree. */
#include "wormgear/wg_snapshot.h"
#include "wormgear/wg_file.h"
#include "wormgear/wg_status.h"

#include <math.h>
#include <sodium.h>
#include <stdarg.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#define HEAD "# wormgeard snapshot, format "
#define SUMKEY "blake2b-256 = "
enum { SUMLEN = 32, SUMHEX = 2 * SUMLEN, SUMLINE = sizeof SUMKEY - 1 + SUMHEX + 1,
       LINE_MAX_ = 128 };

/* What a field holds, and how it reads. */
enum kind { K_SCENE, K_MODEL, K_STEPPER, K_INT, K_U32, K_U64, K_REAL, K_MOTION, K_RAMP };

static const char *const kind_text[] = {
    [K_SCENE] = "1-63 printable ASCII characters",
    [K_MODEL] = "consistent or printed",
    [K_STEPPER] = "rk4 or rk4-event",
    [K_INT] = "an integer in [0, 2147483647]",
    [K_U32] = "an integer in [0, 4294967295]",
    [K_U64] = "an integer in [0, 18446744073709551615]",
    [K_REAL] = "a finite hex float as %a writes it",
    [K_MOTION] = "no_impact, single_sided or double_sided",
    [K_RAMP] = "none or a parameter name",
};

/* A visitor: called once per field, in file order. */
typedef struct visit {
    int (*field)(struct visit *v, const char *key, int kind, void *at);
} visit;

static int walk_period(visit *v, const char *name, wg_period *p, int fmt)
{
    char k[5][24], b[32];
    static const char *const part[] = {"period", "min_xn", "max_xn", "motion", "impacts"};
    for (int i = 0; i < 5; i++)
        snprintf(k[i], sizeof k[i], "%s.%s", name, part[i]);
    if (v->field(v, k[0], K_U64, &p->period) || v->field(v, k[1], K_REAL, &p->min_xn) ||
        v->field(v, k[2], K_REAL, &p->max_xn) || v->field(v, k[3], K_MOTION, &p->motion))
        return 1;
    for (int j = 0; j < WG_NBEARING && fmt >= 3; j++) { /* format 2: none (read as 0) */
        const char *c = wg_contact_name(WG_C_X1 + j);
        snprintf(b, sizeof b, "%s.%s.impacts", name, c);
        if (v->field(v, b, K_INT, &p->bimpacts[j]))
            return 1;
        snprintf(b, sizeof b, "%s.%s.vmax", name, c);
        if (v->field(v, b, K_REAL, &p->bvmax[j]))
            return 1;
    }
    return v->field(v, k[4], K_INT, &p->impacts);
}

static int walk_ramp(visit *v, wg_ramp *r)
{
    if (v->field(v, "ramp", K_RAMP, r))
        return 1;
    return r->active && (v->field(v, "ramp.from", K_REAL, &r->v0) ||
                         v->field(v, "ramp.to", K_REAL, &r->v1) ||
                         v->field(v, "ramp.tau0", K_REAL, &r->tau0) ||
                         v->field(v, "ramp.duration", K_REAL, &r->dur));
}

/* Every field after the first line of a format `fmt` file, in order: 0,
 * or 1 at the first the visitor refused. */
static int walk(visit *v, wg_snapshot *w, char *scene, int fmt)
{
    if (v->field(v, "scene", K_SCENE, scene) || v->field(v, "model", K_MODEL, &w->model) ||
        v->field(v, "stepper", K_STEPPER, &w->stepper) ||
        v->field(v, "steps_per_period", K_INT, &w->steps_per_period))
        return 1;
    char key[32];
    int np = fmt >= 3 ? WG_NPARAM : WG_NPARAM_DYN; /* format 2: no body rows */
    for (int i = 0; i < np; i++) {
        snprintf(key, sizeof key, "param %s", wg_param_info_get(i)->name);
        if (v->field(v, key, K_REAL, &w->p.v[i]))
            return 1;
    }
    for (int i = 0; i < wg_model_nstate(w->model); i++) {
        snprintf(key, sizeof key, "y %d", i);
        if (v->field(v, key, K_REAL, &w->y[i]))
            return 1;
    }
    return v->field(v, "k", K_U32, &w->k) || v->field(v, "tau", K_REAL, &w->tau) ||
           v->field(v, "tau_c", K_REAL, &w->tau_c) || v->field(v, "period", K_U64, &w->period) ||
           v->field(v, "steps", K_U64, &w->steps) || walk_ramp(v, &w->ramp) ||
           walk_period(v, "cur", &w->cur, fmt) || walk_period(v, "last", &w->last, fmt);
}

/* ---- values as text --------------------------------------------------------- */

static void value_text(int kind, const void *at, char *out, size_t len)
{
    const wg_ramp *r = at;
    switch (kind) {
    case K_SCENE: snprintf(out, len, "%s", (const char *)at); break;
    case K_MODEL: snprintf(out, len, "%s", wg_model_name(*(const int *)at)); break;
    case K_STEPPER: snprintf(out, len, "%s", wg_stepper_name(*(const int *)at)); break;
    case K_INT: snprintf(out, len, "%d", *(const int *)at); break;
    case K_U32: snprintf(out, len, "%lu", (unsigned long)*(const uint32_t *)at); break;
    case K_U64: snprintf(out, len, "%llu", (unsigned long long)*(const uint64_t *)at); break;
    case K_REAL: snprintf(out, len, "%a", *(const double *)at); break;
    case K_MOTION: snprintf(out, len, "%s", wg_motion_name(*(const int *)at)); break;
    default: /* K_RAMP */
        snprintf(out, len, "%s", r->active == 0 ? "none"
                 : r->active == 1 && wg_param_info_get(r->id) ? wg_param_info_get(r->id)->name
                 : "?");
    }
}

/* ---- reading ------------------------------------------------------------------ */

typedef struct reader {
    visit v;
    const char *p, *end; /* the lines still to read (the checksum line excluded) */
    int line;
    char *why;
    size_t whylen;
} reader;

static int fail(reader *r, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static int fail(reader *r, const char *fmt, ...)
{
    char msg[200];
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(msg, sizeof msg, fmt, ap);
    va_end(ap);
    snprintf(r->why, r->whylen, "line %d: %s", r->line, msg);
    return 1;
}

/* Decimal digits, no sign, no leading zero, at most max. */
static int read_count(const char *s, uint64_t max, uint64_t *out)
{
    uint64_t u = 0;
    if (!*s || (s[0] == '0' && s[1]))
        return 0;
    for (; *s; s++) {
        unsigned d = (unsigned)(*s - '0');
        if (d > 9 || u > (max - d) / 10)
            return 0;
        u = u * 10 + d;
    }
    *out = u;
    return 1;
}

/* A model, stepper (rk4, rk4-event: never "default") or motion by name. */
static int read_name(const char *s, int kind, int *out)
{
    int n = kind == K_MOTION ? 3 : 2;
    for (int id = 0; id < n; id++) {
        const char *name = kind == K_MODEL ? wg_model_name(id)
                           : kind == K_STEPPER ? wg_stepper_name(id) : wg_motion_name(id);
        if (strcmp(s, name) == 0) {
            *out = id;
            return 1;
        }
    }
    return 0;
}

static int read_scene(const char *s, char *out)
{
    size_t n = strlen(s);
    for (size_t i = 0; i < n; i++)
        if (s[i] < 0x20 || s[i] > 0x7e)
            return 0;
    if (n < 1 || n >= WG_SNAPSHOT_SCENE_MAX)
        return 0;
    memcpy(out, s, n + 1);
    return 1;
}

static int read_ramp(const char *s, wg_ramp *r)
{
    memset(r, 0, sizeof *r);
    if (strcmp(s, "none") == 0)
        return 1;
    r->id = wg_param_lookup(s);
    r->active = r->id >= 0;
    return r->active;
}

/* A finite real exactly as %a writes it. */
static int read_real(const char *s, double *out)
{
    char *end, again[LINE_MAX_];
    double x = strtod(s, &end);
    snprintf(again, sizeof again, "%a", x);
    if (end == s || *end || !isfinite(x) || strcmp(again, s) != 0)
        return 0;
    *out = x;
    return 1;
}

/* The value s of a field of this kind, canonical: exactly what the writer
 * writes for what it reads as. */
static int read_value(const char *s, int kind, void *at)
{
    uint64_t u;
    switch (kind) {
    case K_SCENE: return read_scene(s, at);
    case K_MODEL: case K_STEPPER: case K_MOTION: return read_name(s, kind, at);
    case K_RAMP: return read_ramp(s, at);
    case K_REAL: return read_real(s, at);
    case K_U64: return read_count(s, UINT64_MAX, at);
    case K_U32:
        if (!read_count(s, UINT32_MAX, &u))
            return 0;
        *(uint32_t *)at = (uint32_t)u;
        return 1;
    default: /* K_INT */
        if (!read_count(s, INT32_MAX, &u))
            return 0;
        *(int *)at = (int)u;
        return 1;
    }
}

static int read_field(visit *v, const char *key, int kind, void *at)
{
    reader *r = (reader *)v;
    char buf[LINE_MAX_];
    r->line++;
    const char *nl = memchr(r->p, '\n', (size_t)(r->end - r->p));
    size_t n = nl ? (size_t)(nl - r->p) : 0, klen = strlen(key);
    if (!nl || n >= sizeof buf || memchr(r->p, '\0', n))
        return fail(r, "expected '%s = <%s>'", key, kind_text[kind]);
    memcpy(buf, r->p, n);
    buf[n] = '\0';
    r->p = nl + 1;
    if (strncmp(buf, key, klen) != 0 || strncmp(buf + klen, " = ", 3) != 0)
        return fail(r, "expected '%s = <%s>'", key, kind_text[kind]);
    return read_value(buf + klen + 3, kind, at) ? 0
           : fail(r, "%s must be %s", key, kind_text[kind]);
}

/* ---- the frame: first line and checksum ------------------------------------------ */

static int checksum_hex(const char *text, size_t n, char hex[SUMHEX + 1])
{
    unsigned char h[SUMLEN];
    if (sodium_init() < 0)
        return WG_EUNSUPPORTED;
    crypto_generichash(h, sizeof h, (const unsigned char *)text, n, NULL, 0);
    sodium_bin2hex(hex, SUMHEX + 1, h, sizeof h);
    return WG_OK;
}

static int say(char *why, size_t whylen, int rc, const char *msg)
{
    snprintf(why, whylen, "%s", msg);
    return rc;
}

/* The first line: format 3 or 2 (*fmt), or why not. */
static int check_head(const char *text, size_t len, int *fmt, char *why, size_t whylen)
{
    static const char want[] = HEAD "3\n", two[] = HEAD "2\n", old[] = HEAD "1\n";
    size_t hl = sizeof HEAD - 1;
    if (len >= sizeof want - 1 && memcmp(text, want, sizeof want - 1) == 0)
        return *fmt = 3, WG_OK;
    if (len >= sizeof two - 1 && memcmp(text, two, sizeof two - 1) == 0)
        return *fmt = 2, WG_OK;
    if (len >= sizeof old - 1 && memcmp(text, old, sizeof old - 1) == 0)
        return say(why, whylen, WG_EINVAL,
                   "a format 1 snapshot (an earlier wormgeard's, without a checksum): it "
                   "cannot be verified, so it is not restored; set its parameters again (its "
                   "'param' lines) and save a new snapshot");
    if (len >= hl && memcmp(text, HEAD, hl) == 0)
        return say(why, whylen, WG_EINVAL,
                   "a snapshot of an unknown format: this build reads formats 3 and 2");
    return say(why, whylen, WG_EINVAL,
               "not a wormgeard snapshot: the first line is not '" HEAD "3'");
}

/* The last line is the checksum of every byte before it; *body its start. */
static int check_sum(const char *text, size_t len, size_t *body, char *why, size_t whylen)
{
    char hex[SUMHEX + 1];
    size_t at = len >= SUMLINE ? len - SUMLINE : 0;
    if (len < SUMLINE || text[len - 1] != '\n' || (at > 0 && text[at - 1] != '\n') ||
        memcmp(text + at, SUMKEY, sizeof SUMKEY - 1) != 0)
        return say(why, whylen, WG_EINVAL,
                   "the last line is not its checksum ('" SUMKEY "<64 hex digits>'): the "
                   "file is truncated or not a snapshot");
    int rc = checksum_hex(text, at, hex);
    if (rc)
        return say(why, whylen, rc, "libsodium failed to initialise");
    if (memcmp(hex, text + at + sizeof SUMKEY - 1, SUMHEX) != 0)
        return say(why, whylen, WG_EINVAL,
                   "checksum mismatch: the file was changed or damaged after it was written");
    *body = at;
    return WG_OK;
}

int wg_snapshot_parse(const char *text, size_t len, wg_snapshot *snap, char *scene,
                      size_t scenelen, char *why, size_t whylen)
{
    char sc[WG_SNAPSHOT_SCENE_MAX];
    size_t body = 0;
    if (len == 0)
        return say(why, whylen, WG_EINVAL, "empty: not a snapshot");
    if (len > WG_SNAPSHOT_MAX) {
        snprintf(why, whylen, "longer than any snapshot (%d bytes)", WG_SNAPSHOT_MAX);
        return WG_EINVAL;
    }
    int fmt = 0, rc = check_head(text, len, &fmt, why, whylen);
    if (rc || (rc = check_sum(text, len, &body, why, whylen)))
        return rc;
    wg_snapshot w;
    memset(&w, 0, sizeof w);
    wg_params_default(&w.p); /* format 2's body rows */
    const char *first = memchr(text, '\n', len) + 1; /* check_head saw it */
    reader r = {{read_field}, first, text + body, 1, why, whylen};
    if (first > r.end)
        return say(why, whylen, WG_EINVAL, "no fields between the first and the last line");
    if (walk(&r.v, &w, sc, fmt))
        return WG_EINVAL;
    if (r.p != r.end) {
        r.line++;
        fail(&r, "expected the checksum line '" SUMKEY "...' after last.impacts");
        return WG_EINVAL;
    }
    *snap = w;
    snprintf(scene, scenelen, "%s", sc);
    return WG_OK;
}

/* ---- writing --------------------------------------------------------------------- */

typedef struct writer {
    visit v;
    char *buf;
    size_t cap, n;
} writer;

static void put(writer *o, const char *fmt, ...) __attribute__((format(printf, 2, 3)));

static void put(writer *o, const char *fmt, ...)
{
    va_list ap;
    va_start(ap, fmt);
    int k = vsnprintf(o->buf + o->n, o->n < o->cap ? o->cap - o->n : 0, fmt, ap);
    va_end(ap);
    o->n += k > 0 ? (size_t)k : 0;
}

static int write_field(visit *v, const char *key, int kind, void *at)
{
    writer *o = (writer *)v;
    char val[LINE_MAX_];
    value_text(kind, at, val, sizeof val);
    put(o, "%s = %s\n", key, val);
    return 0;
}

/* The scene name as the format allows it. */
static void scene_text(const char *scene, char out[WG_SNAPSHOT_SCENE_MAX])
{
    size_t i;
    for (i = 0; scene[i] && i < WG_SNAPSHOT_SCENE_MAX - 1; i++)
        out[i] = scene[i] >= 0x20 && scene[i] <= 0x7e ? scene[i] : '?';
    out[i] = '\0';
    if (i == 0)
        snprintf(out, WG_SNAPSHOT_SCENE_MAX, "?");
}

int wg_snapshot_format(const wg_snapshot *snap, const char *scene, char *buf, size_t cap,
                       char *why, size_t whylen)
{
    wg_snapshot w = *snap;
    char sc[WG_SNAPSHOT_SCENE_MAX], hex[SUMHEX + 1], msg[200];
    scene_text(scene, sc);
    writer o = {{write_field}, buf, cap, 0};
    put(&o, HEAD "%d\n", WG_SNAPSHOT_FORMAT);
    walk(&o.v, &w, sc, WG_SNAPSHOT_FORMAT);
    if (o.n + SUMLINE >= cap || o.n + SUMLINE > WG_SNAPSHOT_MAX)
        return say(why, whylen, WG_ERANGE, "snapshot longer than the buffer given");
    int rc = checksum_hex(buf, o.n, hex);
    if (rc)
        return say(why, whylen, rc, "libsodium failed to initialise");
    put(&o, SUMKEY "%s\n", hex);
    wg_snapshot back;
    if ((rc = wg_snapshot_parse(buf, o.n, &back, sc, sizeof sc, msg, sizeof msg))) {
        snprintf(why, whylen, "cannot save this state: %s", msg);
        return rc;
    }
    return (int)o.n;
}

/* ---- reading a file --------------------------------------------------------------- */

int wg_snapshot_load(const char *path, wg_snapshot *snap, char *scene, size_t scenelen,
                     char *why, size_t whylen)
{
    char text[WG_SNAPSHOT_MAX + 1], msg[400];
    long n = wg_file_read(path, NULL, WG_FILE_NOFOLLOW, text, WG_SNAPSHOT_MAX, why, whylen);
    if (n < 0)
        return WG_EIO;
    int rc = wg_snapshot_parse(text, (size_t)n, snap, scene, scenelen, msg, sizeof msg);
    if (rc)
        snprintf(why, whylen, "%s: %s", path, msg);
    return rc;
}

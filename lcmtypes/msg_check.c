/* msg_check.c - every message's layout, and the checked walk over it
 * (msg_check.h). */
#include "msg_check.h"

#include <stdio.h>
#include <string.h>

/* A field: what the walk reads there. */
enum {
    F_SKIP, /* a scalar of a bytes */
    F_N32,  /* an int32 count into slot a, at most max (0: what the bytes allow);
             * c = 1: 0 or max, nothing else (a MAC's length) */
    F_N8,   /* an int8 count into slot a */
    F_STR,  /* a string of at most max bytes (0: what the bytes allow) */
    F_ARR,  /* a bytes x count[b] */
    F_ARR2, /* a bytes x count[b] x count[c] */
    F_STRS, /* count[b] strings of at most max bytes */
    F_END
};
typedef struct fld {
    unsigned char kind, a, b, c;
    int32_t max;
    const char *name;
} fld;

#define SKIP(n, nm) {F_SKIP, n, 0, 0, 0, nm}
#define I64(nm) SKIP(8, nm)
#define F64(nm) SKIP(8, nm)
#define I32(nm) SKIP(4, nm)
#define I8(nm) SKIP(1, nm)
#define N32(s, mx, nm) {F_N32, s, 0, 0, mx, nm}
#define N8(s, mx, nm) {F_N8, s, 0, 0, mx, nm}
#define MACLEN(s, bytes, nm) {F_N32, s, 0, 1, bytes, nm}
#define STR(mx, nm) {F_STR, 0, 0, 0, mx, nm}
#define ARR(n, s, nm) {F_ARR, n, s, 0, 0, nm}
#define ARR2(n, s, t, nm) {F_ARR2, n, s, t, 0, nm}
#define STRS(s, mx, nm) {F_STRS, 0, s, 0, mx, nm}
#define END {F_END, 0, 0, 0, 0, NULL}
#define D(s, nm) ARR(8, s, nm) /* double nm[count s] */

/* The layouts of the .lcm files here after the 8-byte fingerprint, field
 * by field, with their names (count slots: 0 n, 1 nstate, 2 nbearing; a
 * MAC's length in slot 1 once nothing after it reads nstate). */
static const fld ACK[] = {I64("utime"), I64("seq"), STR(0, "client"), I64("cmd_seq"),
                          I64("cmd_utime"), STR(0, "op"), I8("accepted"), I32("status"),
                          STR(0, "code"), STR(0, "message"), F64("tau"), F64("t_s"),
                          I64("steps"),
                          MACLEN(0, MSG_CMD_MAC_BYTES, "mac_len"), ARR(1, 0, "mac"), END};
static const fld STATE[] = {
    I64("utime"), I64("seq"), I64("step0"), I32("decimation"), N32(0, 0, "n"),
    D(0, "tau"), D(0, "t_s"), D(0, "omega"), D(0, "xn"), D(0, "dxn"), D(0, "force"),
    D(0, "fb_x1"), D(0, "fb_y1"), D(0, "fb_z1"), D(0, "fb_x2"), D(0, "fb_y2"), D(0, "fb_z2"),
    D(0, "theta1"), D(0, "theta2"), MACLEN(1, MSG_CMD_MAC_BYTES, "mac_len"), ARR(1, 1, "mac"), END};
static const fld POINCARE[] = {
    I64("utime"), I64("seq"), N32(1, MSG_NSTATE_MAX, "nstate"), N32(0, 0, "n"), ARR(8, 0, "period"),
    D(0, "tau"), D(0, "t_s"), D(0, "omega"), D(0, "xn"), D(0, "dxn"), D(0, "force"),
    D(0, "min_xn"), D(0, "max_xn"), ARR(1, 0, "motion"), ARR(4, 0, "impacts"),
    ARR2(8, 0, 1, "y"), N32(2, MSG_NBEARING_MAX, "nbearing"), ARR2(4, 0, 2, "bearing_impacts"),
    ARR2(8, 0, 2, "bearing_vmax"), MACLEN(1, MSG_CMD_MAC_BYTES, "mac_len"), ARR(1, 1, "mac"), END};
static const fld CONTACT[] = {I64("utime"), I64("seq"), I32("bearing_every"), N32(0, 0, "n"),
                              D(0, "tau"), D(0, "t_s"), D(0, "velocity"), ARR(8, 0, "period"),
                              ARR(1, 0, "contact"), ARR(1, 0, "kind"),
                              MACLEN(1, MSG_CMD_MAC_BYTES, "mac_len"), ARR(1, 1, "mac"), END};
static const fld STATUS[] = {
    I64("utime"), I64("seq"), STR(0, "scene"), STR(0, "mode"), F64("rate"), STR(0, "run"),
    STR(0, "health"), STR(0, "fault"), F64("tau"), F64("t_s"), F64("omega"), I64("steps"),
    I64("period"), I32("steps_per_period"), F64("rtf"), F64("lag_s"), I64("overruns"),
    F64("loop_mean_us"), F64("loop_max_us"), F64("steps_per_s"), F64("cpu_share"),
    I64("msgs_dropped"), I64("cmds_accepted"), I64("cmds_refused"), I64("cmds_dropped"),
    I64("rx_dropped"), I64("ticks_refused"), STR(0, "tick_refusal"), I64("ticks_lost"),
    STR(0, "motion"),
    F64("impacts_per_period"), N8(2, MSG_NBEARING_MAX, "nbearing"),
    D(2, "bearing_impacts_per_period"), D(2, "bearing_impact_vmax"), STR(0, "regime"),
    I8("ramp_active"), F64("uptime_s"), MACLEN(0, MSG_CMD_MAC_BYTES, "mac_len"), ARR(1, 0, "mac"),
    END};
static const fld PARAMS[] = {
    I64("utime"), I64("seq"), STR(0, "reason"), STR(0, "cmd_client"), I64("cmd_seq"),
    I64("cmd_utime"), STR(0, "scene"), STR(0, "model"), STR(0, "stepper"), I32("steps_per_period"),
    F64("omega_n_rad_s"), F64("length_m"), F64("mesh_stiffness_N_m"), F64("tau"),
    N32(0, 0, "n"), STRS(0, 0, "name"), STRS(0, 0, "unit"), D(0, "value"), D(0, "min"),
    D(0, "max"), D(0, "def"), ARR(1, 0, "rampable"), I8("ramp_active"), STR(0, "ramp_param"),
    F64("ramp_from"), F64("ramp_to"), F64("ramp_tau0"), F64("ramp_duration_tau"),
    MACLEN(1, MSG_CMD_MAC_BYTES, "mac_len"), ARR(1, 1, "mac"), END};
static const fld CMD[] = {
    I64("utime"), I64("seq"), STR(MSG_CMD_MAX_CLIENT, "client"), STR(MSG_CMD_MAX_STRING, "op"),
    N32(0, MSG_CMD_MAX_PARAMS, "nparams"), STRS(0, MSG_CMD_MAX_STRING, "names"),
    D(0, "values"), I8("has_from"), F64("from"), F64("duration"),
    STR(MSG_CMD_MAX_STRING, "unit"), I64("nsteps"), STR(MSG_CMD_MAX_STRING, "name"),
    F64("rate"), I8("at_section"), MACLEN(1, MSG_CMD_MAC_BYTES, "mac_len"), ARR(1, 1, "mac"),
    END};
static const fld TICK[] = {I64("utime"), I64("seq"), I64("nsteps"),
                           STR(MSG_CMD_MAX_CLIENT, "client"),
                           MACLEN(1, MSG_CMD_MAC_BYTES, "mac_len"), ARR(1, 1, "mac"), END};
static const fld SCOPE[] = {I64("utime"), I64("seq"), F64("t_s"), F64("tau"), F64("omega"),
                            F64("xn"), F64("dxn"), F64("force"),
                            MACLEN(1, MSG_CMD_MAC_BYTES, "mac_len"), ARR(1, 1, "mac"), END};

static const fld *const LAYOUT[MSG_NTYPE] = {ACK,    STATE, POINCARE, CONTACT, STATUS,
                                             PARAMS, CMD,   TICK,     SCOPE};

uint64_t msg_be(const unsigned char *p, int n)
{
    uint64_t v = 0;
    for (int i = 0; i < n; i++)
        v = v << 8 | p[i];
    return v;
}

typedef struct walk {
    const unsigned char *b;
    int64_t len, pos;
    msg_walk *w;
} walk;

/* Note what was wrong where (the first fault only); -1. */
static int fault(walk *k, const fld *f, int index, const char *fmt, long long v, long long lim)
{
    msg_walk *w = k->w;
    w->end = -1;
    w->field = f->name;
    w->index = index;
    w->at = (long)k->pos;
    snprintf(w->what, sizeof w->what, fmt, v, lim);
    return -1;
}

static int skip(walk *k, const fld *f, int index, int64_t n)
{
    if (n > k->len - k->pos)
        return fault(k, f, index, "truncated", 0, 0);
    k->pos += n;
    return 0;
}

static int i32(walk *k, const fld *f, int index, int64_t *v)
{
    if (skip(k, f, index, 4))
        return -1;
    *v = (int32_t)(uint32_t)msg_be(k->b + k->pos - 4, 4);
    return 0;
}

/* A string: its int32 length with the NUL, the bytes, the last a NUL and
 * no other. */
static int str(walk *k, const fld *f, int index)
{
    int64_t n;
    if (i32(k, f, index, &n))
        return -1;
    if (n < 1)
        return fault(k, f, index, "string length %lld (with its NUL, at least 1)", n, 0);
    if (f->max && n - 1 > f->max)
        return fault(k, f, index, "a string of %lld bytes, the limit is %lld", n - 1, f->max);
    if (skip(k, f, index, n))
        return -1;
    const unsigned char *s = k->b + k->pos - n;
    if (s[n - 1] != 0)
        return fault(k, f, index, "string not NUL-terminated", 0, 0);
    if (memchr(s, 0, (size_t)(n - 1)))
        return fault(k, f, index, "a NUL byte inside the string", 0, 0);
    return 0;
}

static int step(walk *k, const fld *f)
{
    int64_t *cnt = k->w->count, n = 0;
    switch (f->kind) {
    case F_SKIP: return skip(k, f, -1, f->a);
    case F_N32:
    case F_N8:
        if (f->kind == F_N32 ? i32(k, f, -1, &n) : skip(k, f, -1, 1))
            return -1;
        if (f->kind == F_N8)
            n = (int8_t)k->b[k->pos - 1];
        cnt[f->a] = n; /* one too large for the bytes left fails where they run out */
        if (f->c && n != 0 && n != f->max)
            return fault(k, f, -1, "%lld, allowed 0 (unsigned) or %lld", n, f->max);
        if (n < 0 || (f->max && n > f->max))
            return fault(k, f, -1, f->max ? "%lld, allowed 0 to %lld" : "%lld, negative", n,
                         f->max);
        return 0;
    case F_STR: return str(k, f, -1);
    case F_ARR:
    case F_ARR2:
        n = f->a; /* grown by each count while it fits in what is left */
        for (int j = 0; j < (f->kind == F_ARR2 ? 2 : 1); j++) {
            int64_t c = cnt[j ? f->c : f->b];
            if (c && n > (k->len - k->pos) / c)
                return fault(k, f, -1, "truncated", 0, 0);
            n *= c;
        }
        return skip(k, f, -1, n);
    case F_STRS:
        for (int64_t i = 0; i < cnt[f->b]; i++)
            if (str(k, f, (int)i))
                return -1;
        return 0;
    }
    return -1;
}

long msg_check(int type, const void *buf, long len, msg_walk *w)
{
    msg_walk own;
    if (!w)
        w = &own;
    memset(w, 0, sizeof *w);
    w->index = -1;
    walk k = {buf, len, 0, w};
    static const fld fp = SKIP(8, "fingerprint");
    if (type < 0 || type >= MSG_NTYPE || !buf || len < 0)
        return fault(&k, &fp, -1, "not a message type or no bytes", 0, 0);
    if (len > MSG_MAX_BYTES) /* LCM's length of a short datagram it misread, say */
        return fault(&k, &fp, -1, "a message of %lld bytes, the limit is %lld", len,
                     MSG_MAX_BYTES);
    if (skip(&k, &fp, -1, 8))
        return -1;
    for (const fld *f = LAYOUT[type]; f->kind != F_END; f++)
        if (step(&k, f))
            return -1;
    return w->end = (long)k.pos;
}

int msg_cmd_late(const char *op, int at_section)
{
    return !strcmp(op, "step") || (!strcmp(op, "set") && at_section);
}

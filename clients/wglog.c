/* wglog - summarise an LCM log of wormgeard, or export its channels to CSV.
 *
 * Reads the log with LCM's eventlog API; each message's type is found from
 * its fingerprint (the first 8 bytes), so any prefix works. `summary` lists
 * channels, types, message and sample counts, rates, seq gaps (dropped
 * messages), restarts and senders (bus.h: seq lines and their send clocks,
 * so a log played into a live bus is one more sender, not thousands of gaps
 * and restarts); `export` writes one CSV per
 * channel with the type's fields as columns, one row per sample for the
 * batched types (STATE, POINCARE, CONTACT). Numbers are written in the
 * shortest form that reads back exactly (0.08, not 0.080000000000000002):
 * the CSV holds exactly what was published. --units physical converts the
 * samples with the scale of the log's PARAMS (s, Hz, um, m/s, N).
 * Exit 0, 1 unreadable log, unwritable output or no channel matching --channel,
 * 2 usage error. */
#include "bus.h"
#include "bus_msg.h"
#include "cli.h"
#include "logrd.h"
#include "lcmtypes/wormgear_ack_t.h"
#include "lcmtypes/wormgear_cmd_t.h"
#include "lcmtypes/wormgear_contact_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "lcmtypes/wormgear_scope_t.h"
#include "lcmtypes/wormgear_tick_t.h"
#include "units.h"
#include "wormgear/wg_model.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_status.h"

#include <errno.h>
#include <limits.h>
#include <getopt.h>
#include <lcm/eventlog.h>
#include <math.h>
#include <regex.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/resource.h>
#include <sys/stat.h>

enum { T_UNKNOWN = -1 };

typedef struct chan {
    char *name;
    char shown[96];           /* the name as text for the terminal (cli_text) */
    int type;                 /* index in types[], or T_UNKNOWN */
    int64_t hash;
    long msgs, samples, bad;
    long long bytes;
    int64_t t0, t1;           /* log timestamps, us */
    bus_streams seq;          /* senders: gaps, missing (messages lost), restarts */
    char notes[600];          /* the senders after the first, as they appeared */
    FILE *csv;
    char *file;               /* its CSV's path (export) */
    int ncols;                /* params_t / poincare_t: columns fixed by the first message */
} chan;

/* Export: at most this many CSVs open at once (and half the descriptors the
 * process may have). One per channel ran out of descriptors (1,024) in a log
 * of more channels; past it, all are closed and each reopened (appending)
 * at its channel's next message. */
enum { CSV_OPEN_MAX = 256 };

typedef struct log_run {
    const char *path, *out, *pattern;
    int export_, quiet, also_summary;
    int physical;             /* --units physical */
    units_scale scale;        /* of the latest PARAMS (the first one before it) */
    regex_t re;
    int has_re;
    chan *ch;
    int nch, cap;
    int *hix, hcap;           /* the channels by name: open addressing, index + 1 (0: empty) */
    long events;
    int64_t t0, t1;
    int damaged;              /* the log stopped being readable before its end: exit 1 */
    char others[64][96];      /* the first channels --channel left out, as text */
    int nothers, more;        /* how many; more: others past those */
    int open_ix[CSV_OPEN_MAX]; /* export: the channels whose CSV is open now */
    int nopen, open_max;      /* how many; the most at once (csv_open_max) */
    int wfail;                /* a CSV's write failed (said): exit 1 */
} log_run;

/* ---- CSV helpers ------------------------------------------------------------- */

static void cs(FILE *f, const char *s) /* a string cell, quoted when needed */
{
    if (!s)
        s = "";
    if (!strpbrk(s, ",\"\n\r")) {
        fputs(s, f);
        return;
    }
    fputc('"', f);
    for (; *s; s++) {
        if (*s == '"')
            fputc('"', f);
        fputc(*s, f);
    }
    fputc('"', f);
}

static void cd(FILE *f, double v)
{
    char b[40];
    fputc(',', f);
    fputs(wg_num_format(v, b, sizeof b), f);
}
static void ci(FILE *f, long long v) { fprintf(f, ",%lld", v); }
static void csc(FILE *f, const char *s) { fputc(',', f), cs(f, s); }

static void head(FILE *f, const char *cols) { fprintf(f, "log_utime,utime,seq,%s\n", cols); }

static void lead(FILE *f, int64_t ts, int64_t utime, int64_t seq)
{
    fprintf(f, "%lld,%lld,%lld", (long long)ts, (long long)utime, (long long)seq);
}


/* ---- one row writer per type: decode, write, return samples (-1 bad) -------- */

/* No message of c has decoded yet: the header (and PARAMS's and POINCARE's
 * columns) come with the first that does. With c->msgs == 0, a first
 * message that failed the check left the CSV without a header. */
static int first_good(const chan *c) { return c->msgs == c->bad; }

#define DECODE_OR_FAIL(T, TYPE, msg, ev) /* bytes checked first: bus_msg.h */             \
    T msg;                                                                                 \
    if (!bus_msg_ok((TYPE), (ev)->data, (ev)->datalen) ||                                  \
        T##_decode((ev)->data, 0, (ev)->datalen, &msg) < 0)                                \
        return -1;

/* Factors of the sample columns: 1, or the physical ones of the latest
 * PARAMS (--units physical). */
typedef struct fx {
    double w, x, v, f;        /* Hz per omega, um per x, m/s per x', N per F */
} fx;

static fx factors(const log_run *r)
{
    if (!r->physical)
        return (fx){1, 1, 1, 1};
    const units_scale *s = &r->scale;
    return (fx){units_hz_per_omega(s), units_um_per_x(s), units_m_s_per_v(s), units_n_per_f(s)};
}

static int rows_state(log_run *r, chan *c, const lcm_eventlog_event_t *ev)
{
    DECODE_OR_FAIL(wormgear_state_t, BUS_STATE, m, ev);
    FILE *f = c->csv;
    fx k = factors(r);
    if (f && first_good(c))
        head(f, r->physical ? "step0,decimation,i,tau,t_s,f_mesh_hz,x_n_um,dx_n_m_s,F_N,fb_x1_N,"
                              "fb_y1_N,fb_z1_N,fb_x2_N,fb_y2_N,fb_z2_N,theta1_rad,theta2_rad"
                            : "step0,decimation,i,tau,t_s,omega,xn,dxn,force,fb_x1,fb_y1,fb_z1,"
                              "fb_x2,fb_y2,fb_z2,theta1,theta2");
    for (int i = 0; f && i < m.n; i++) {
        lead(f, ev->timestamp, m.utime, m.seq);
        ci(f, m.step0), ci(f, m.decimation), ci(f, i);
        cd(f, m.tau[i]), cd(f, m.t_s[i]), cd(f, m.omega[i] * k.w), cd(f, m.xn[i] * k.x);
        cd(f, m.dxn[i] * k.v), cd(f, m.force[i] * k.f), cd(f, m.fb_x1[i] * k.f);
        cd(f, m.fb_y1[i] * k.f), cd(f, m.fb_z1[i] * k.f), cd(f, m.fb_x2[i] * k.f);
        cd(f, m.fb_y2[i] * k.f), cd(f, m.fb_z2[i] * k.f);
        cd(f, m.theta1[i]), cd(f, m.theta2[i]);
        fputc('\n', f);
    }
    int n = m.n;
    wormgear_state_t_decode_cleanup(&m);
    return n;
}

/* The POINCARE header: the state by its names (x1 ... ds; the printed
 * form's th1, th2), with units when physical. */
static void poincare_head(const log_run *r, FILE *f, int nstate)
{
    int model = nstate == wg_model_nstate(WG_MODEL_PRINTED) ? WG_MODEL_PRINTED
                                                            : WG_MODEL_CONSISTENT;
    fprintf(f, "log_utime,utime,seq,i,period,tau,t_s,%s,motion,impacts",
            r->physical ? "f_mesh_hz,x_n_um,dx_n_m_s,F_N,min_x_n_um,max_x_n_um"
                        : "omega,xn,dxn,force,min_xn,max_xn");
    for (int k = 0; k < nstate; k++) {
        const char *name = wg_state_name(model, k);
        if (name)
            fprintf(f, ",%s%s", name, !r->physical ? "" : 2 * k < nstate ? "_um" : "_m_s");
        else
            fprintf(f, ",y%d", k); /* a state this build does not know */
    }
    for (int j = 0; j < WG_NBEARING; j++)
        fprintf(f, ",%s_impacts", wg_contact_name(WG_C_X1 + j));
    for (int j = 0; j < WG_NBEARING; j++)
        fprintf(f, ",%s_vmax%s", wg_contact_name(WG_C_X1 + j), r->physical ? "_m_s" : "");
    fputc('\n', f);
}

static int rows_poincare(log_run *r, chan *c, const lcm_eventlog_event_t *ev)
{
    DECODE_OR_FAIL(wormgear_poincare_t, BUS_POINCARE, m, ev);
    FILE *f = c->csv;
    fx k = factors(r);
    if (f && first_good(c)) {
        c->ncols = m.nstate;
        poincare_head(r, f, m.nstate);
    }
    for (int i = 0; f && i < m.n; i++) {
        lead(f, ev->timestamp, m.utime, m.seq);
        ci(f, i), ci(f, m.period[i]);
        cd(f, m.tau[i]), cd(f, m.t_s[i]), cd(f, m.omega[i] * k.w), cd(f, m.xn[i] * k.x);
        cd(f, m.dxn[i] * k.v), cd(f, m.force[i] * k.f), cd(f, m.min_xn[i] * k.x);
        cd(f, m.max_xn[i] * k.x);
        csc(f, wg_motion_name(m.motion[i])), ci(f, m.impacts[i]);
        for (int j = 0; j < c->ncols; j++)
            j < m.nstate ? cd(f, m.y[i][j] * (2 * j < m.nstate ? k.x : k.v)) : (void)fputc(',', f);
        for (int j = 0; j < WG_NBEARING; j++) /* empty: a sender without them */
            j < m.nbearing ? ci(f, m.bearing_impacts[i][j]) : (void)fputc(',', f);
        for (int j = 0; j < WG_NBEARING; j++)
            j < m.nbearing ? cd(f, m.bearing_vmax[i][j] * k.v) : (void)fputc(',', f);
        fputc('\n', f);
    }
    int n = m.n;
    wormgear_poincare_t_decode_cleanup(&m);
    return n;
}

static int rows_contact(log_run *r, chan *c, const lcm_eventlog_event_t *ev)
{
    DECODE_OR_FAIL(wormgear_contact_t, BUS_CONTACT, m, ev);
    FILE *f = c->csv;
    fx k = factors(r);
    if (f && first_good(c))
        head(f, r->physical ? "i,tau,t_s,velocity_m_s,period,contact,kind,contact_name,kind_name,"
                              "bearing_every"
                            : "i,tau,t_s,velocity,period,contact,kind,contact_name,kind_name,"
                              "bearing_every");
    for (int i = 0; f && i < m.n; i++) {
        lead(f, ev->timestamp, m.utime, m.seq);
        ci(f, i), cd(f, m.tau[i]), cd(f, m.t_s[i]), cd(f, m.velocity[i] * k.v);
        ci(f, m.period[i]), ci(f, m.contact[i]), ci(f, m.kind[i]);
        csc(f, wg_contact_name(m.contact[i]));
        csc(f, wg_event_name(m.kind[i]));
        ci(f, m.bearing_every); /* 1 all, N 1 in N of a bearing's, 0 mesh only */
        fputc('\n', f);
    }
    int n = m.n;
    wormgear_contact_t_decode_cleanup(&m);
    return n;
}

static int rows_status(log_run *r, chan *c, const lcm_eventlog_event_t *ev)
{
    (void)r;
    DECODE_OR_FAIL(wormgear_status_t, BUS_STATUS, m, ev);
    FILE *f = c->csv;
    if (f && first_good(c))
        head(f, "scene,mode,rate,run,health,fault,tau,t_s,omega,steps,period,steps_per_period,"
                "rtf,lag_s,overruns,loop_mean_us,loop_max_us,steps_per_s,cpu_share,"
                "msgs_dropped,cmds_accepted,cmds_refused,cmds_dropped,rx_dropped,"
                "ticks_refused,tick_refusal,ticks_lost,motion,impacts_per_period,regime,ramp_active,"
                "uptime_s");
    if (f) {
        lead(f, ev->timestamp, m.utime, m.seq);
        csc(f, m.scene), csc(f, m.mode), cd(f, m.rate), csc(f, m.run), csc(f, m.health);
        csc(f, m.fault), cd(f, m.tau), cd(f, m.t_s), cd(f, m.omega), ci(f, m.steps);
        ci(f, m.period), ci(f, m.steps_per_period), cd(f, m.rtf), cd(f, m.lag_s);
        ci(f, m.overruns), cd(f, m.loop_mean_us), cd(f, m.loop_max_us), cd(f, m.steps_per_s);
        cd(f, m.cpu_share), ci(f, m.msgs_dropped), ci(f, m.cmds_accepted);
        ci(f, m.cmds_refused), ci(f, m.cmds_dropped), ci(f, m.rx_dropped);
        ci(f, m.ticks_refused), csc(f, m.tick_refusal), ci(f, m.ticks_lost), csc(f, m.motion);
        cd(f, m.impacts_per_period);
        csc(f, m.regime), ci(f, m.ramp_active), cd(f, m.uptime_s);
        fputc('\n', f);
    }
    wormgear_status_t_decode_cleanup(&m);
    return 1;
}

/* PARAMS: the scalars, then one column per parameter (named by the first
 * message; later messages are matched by name). */
static int rows_params(log_run *r, chan *c, const lcm_eventlog_event_t *ev)
{
    DECODE_OR_FAIL(wormgear_params_t, BUS_PARAMS, m, ev);
    FILE *f = c->csv;
    units_scale sc = {m.omega_n_rad_s, m.length_m, m.mesh_stiffness_N_m};
    if (units_scale_ok(&sc))
        r->scale = sc; /* the samples after it are in its scale */
    if (f && first_good(c)) {
        c->ncols = m.n;
        fprintf(f, "log_utime,utime,seq,reason,cmd_client,cmd_seq,cmd_utime,scene,model,stepper,"
                   "steps_per_period,omega_n_rad_s,length_m,mesh_stiffness_N_m,tau,ramp_active,"
                   "ramp_param,ramp_from,ramp_to,ramp_tau0,ramp_duration_tau");
        for (int i = 0; i < m.n; i++)
            csc(f, m.name[i]); /* from the bus: quoted when it holds , " or a line break */
        fputc('\n', f);
    }
    if (f) {
        lead(f, ev->timestamp, m.utime, m.seq);
        csc(f, m.reason), csc(f, m.cmd_client), ci(f, m.cmd_seq), ci(f, m.cmd_utime);
        csc(f, m.scene);
        csc(f, m.model), csc(f, m.stepper), ci(f, m.steps_per_period), cd(f, m.omega_n_rad_s);
        cd(f, m.length_m), cd(f, m.mesh_stiffness_N_m), cd(f, m.tau), ci(f, m.ramp_active);
        csc(f, m.ramp_param), cd(f, m.ramp_from), cd(f, m.ramp_to), cd(f, m.ramp_tau0);
        cd(f, m.ramp_duration_tau);
        for (int i = 0; i < c->ncols; i++)
            i < m.n ? cd(f, m.value[i]) : (void)fputc(',', f);
        fputc('\n', f);
    }
    wormgear_params_t_decode_cleanup(&m);
    return 1;
}

static int rows_cmd(log_run *r, chan *c, const lcm_eventlog_event_t *ev)
{
    (void)r;
    DECODE_OR_FAIL(wormgear_cmd_t, BUS_CMD, m, ev);
    FILE *f = c->csv;
    if (f && first_good(c))
        head(f, "client,op,params,has_from,from,duration,unit,nsteps,name,rate");
    if (f) {
        char buf[2048] = "";
        size_t len = 0;
        for (int i = 0; i < m.nparams && len < sizeof buf - 64; i++) {
            char num[40];
            len += (size_t)snprintf(buf + len, sizeof buf - len, "%s%s=%s", i ? ";" : "",
                                    m.names[i], wg_num_format(m.values[i], num, sizeof num));
        }
        lead(f, ev->timestamp, m.utime, m.seq);
        csc(f, m.client), csc(f, m.op), csc(f, buf), ci(f, m.has_from), cd(f, m.from);
        cd(f, m.duration), csc(f, m.unit), ci(f, m.nsteps), csc(f, m.name), cd(f, m.rate);
        fputc('\n', f);
    }
    wormgear_cmd_t_decode_cleanup(&m);
    return 1;
}

static int rows_ack(log_run *r, chan *c, const lcm_eventlog_event_t *ev)
{
    (void)r;
    DECODE_OR_FAIL(wormgear_ack_t, BUS_ACK, m, ev);
    FILE *f = c->csv;
    if (f && first_good(c))
        head(f, "client,cmd_seq,cmd_utime,op,accepted,status,code,message,tau,t_s,steps");
    if (f) {
        lead(f, ev->timestamp, m.utime, m.seq);
        csc(f, m.client), ci(f, m.cmd_seq), ci(f, m.cmd_utime), csc(f, m.op);
        ci(f, m.accepted), ci(f, m.status);
        csc(f, m.code), csc(f, m.message), cd(f, m.tau), cd(f, m.t_s), ci(f, m.steps);
        fputc('\n', f);
    }
    wormgear_ack_t_decode_cleanup(&m);
    return 1;
}

static int rows_tick(log_run *r, chan *c, const lcm_eventlog_event_t *ev)
{
    (void)r;
    DECODE_OR_FAIL(wormgear_tick_t, BUS_TICK, m, ev);
    if (c->csv && first_good(c))
        head(c->csv, "nsteps");
    if (c->csv) {
        lead(c->csv, ev->timestamp, m.utime, m.seq);
        ci(c->csv, m.nsteps);
        fputc('\n', c->csv);
    }
    wormgear_tick_t_decode_cleanup(&m);
    return 1;
}

static int rows_scope(log_run *r, chan *c, const lcm_eventlog_event_t *ev)
{
    DECODE_OR_FAIL(wormgear_scope_t, BUS_SCOPE, m, ev);
    FILE *f = c->csv;
    fx k = factors(r);
    if (f && first_good(c))
        head(f, r->physical ? "t_s,tau,f_mesh_hz,x_n_um,dx_n_m_s,F_N"
                            : "t_s,tau,omega,xn,dxn,force");
    if (f) {
        lead(f, ev->timestamp, m.utime, m.seq);
        cd(f, m.t_s), cd(f, m.tau), cd(f, m.omega * k.w), cd(f, m.xn * k.x);
        cd(f, m.dxn * k.v), cd(f, m.force * k.f);
        fputc('\n', f);
    }
    wormgear_scope_t_decode_cleanup(&m);
    return 1;
}

static const struct type {
    const char *name;
    int64_t (*hash)(void);
    int (*rows)(log_run *r, chan *c, const lcm_eventlog_event_t *ev);
} types[] = {
    {"state_t", __wormgear_state_t_get_hash, rows_state},
    {"poincare_t", __wormgear_poincare_t_get_hash, rows_poincare},
    {"contact_t", __wormgear_contact_t_get_hash, rows_contact},
    {"status_t", __wormgear_status_t_get_hash, rows_status},
    {"params_t", __wormgear_params_t_get_hash, rows_params},
    {"cmd_t", __wormgear_cmd_t_get_hash, rows_cmd},
    {"ack_t", __wormgear_ack_t_get_hash, rows_ack},
    {"tick_t", __wormgear_tick_t_get_hash, rows_tick},
    {"scope_t", __wormgear_scope_t_get_hash, rows_scope},
};
enum { NTYPES = sizeof types / sizeof types[0] };

/* ---- reading ------------------------------------------------------------------- */

/* A big-endian int64 (a fingerprint, utime, seq) at p. */
static int64_t be64(const void *p) { return (int64_t)msg_be(p, 8); }

static int type_of(int64_t hash)
{
    for (int t = 0; t < NTYPES; t++)
        if (types[t].hash() == hash)
            return t;
    return T_UNKNOWN;
}

/* The file name of a channel's CSV: DIR/CHANNEL.csv, odd characters as '_',
 * and DIR/CHANNEL~2.csv ... when another channel's already has that name
 * (A/B and A_B were written into one file, interleaved). */
static FILE *open_csv(const log_run *r, const chan *self, char *path, size_t len)
{
    size_t n = (size_t)snprintf(path, len, "%s/", r->out), n0 = n;
    /* at most 200 bytes of the name: a file name has 255 (a longer channel name
     * stopped the whole export with "File name too long"); those alike in
     * their first 200 bytes go to ~2, ~3 ... */
    for (const char *s = self->name; *s && n + 16 < len && n - n0 < 200; s++)
        path[n++] = (*s == '/' || *s == '\\' || (unsigned char)*s < 0x20) ? '_' : *s;
    for (int k = 1;; k++) {
        snprintf(path + n, len - n, k == 1 ? ".csv" : "~%d.csv", k);
        int taken = 0;
        for (int i = 0; i < r->nch && !taken; i++)
            taken = &r->ch[i] != self && r->ch[i].file && !strcmp(r->ch[i].file, path);
        if (!taken)
            break;
        if (k == 1 && !r->quiet)
            fprintf(stderr, "wglog: %s: another channel's CSV has its file name; written to "
                    "the next free one\n", self->shown);
    }
    return fopen(path, "w");
}

static unsigned name_hash(const char *s)
{
    unsigned h = 2166136261u; /* FNV-1a */
    for (; *s; s++)
        h = (h ^ (unsigned char)*s) * 16777619u;
    return h;
}

/* The slot of name in r->hix: its channel's, or the empty one it would take. */
static int *slot_of(log_run *r, const char *name)
{
    unsigned m = (unsigned)r->hcap - 1, i = name_hash(name) & m;
    while (r->hix[i] && strcmp(r->ch[r->hix[i] - 1].name, name))
        i = (i + 1) & m;
    return &r->hix[i];
}

/* Room in the index for one more channel (at most half full): 0, or -1. */
static int index_room(log_run *r)
{
    if (2 * (r->nch + 1) <= r->hcap)
        return 0;
    int cap = r->hcap ? 2 * r->hcap : 64, *old = r->hix, n = r->hcap;
    if (!(r->hix = calloc((size_t)cap, sizeof *r->hix)))
        return r->hix = old, -1;
    r->hcap = cap;
    for (int i = 0; i < n; i++)
        if (old[i])
            *slot_of(r, r->ch[old[i] - 1].name) = old[i];
    free(old);
    return 0;
}

/* The channel of ev, added on first sight (type from the fingerprint). By
 * name through a hash index: a log of 60,000 channels took minutes when each
 * event compared its name with every channel's. */
static chan *find_chan(log_run *r, const lcm_eventlog_event_t *ev)
{
    if (index_room(r))
        return NULL;
    int *slot = slot_of(r, ev->channel);
    if (*slot)
        return &r->ch[*slot - 1];
    if (r->nch == r->cap) {
        int cap = r->cap ? 2 * r->cap : 16;
        chan *c = realloc(r->ch, sizeof *c * (size_t)cap);
        if (!c)
            return NULL;
        r->ch = c, r->cap = cap;
    }
    chan *c = &r->ch[r->nch++];
    *c = (chan){.name = strdup(ev->channel), .type = T_UNKNOWN};
    if (!c->name)
        return r->nch--, NULL;
    *slot = r->nch;
    cli_text(c->shown, sizeof c->shown, ev->channel); /* any sender named it */
    c->hash = ev->datalen >= 8 ? be64(ev->data) : 0;
    c->type = ev->datalen >= 8 ? type_of(c->hash) : T_UNKNOWN;
    c->t0 = ev->timestamp;
    return c;
}

/* Every wormgear type starts utime, seq: tell the senders apart (the log's
 * timestamp is the receiver's clock), count gaps and restarts inside each,
 * and note every sender after the first. */
static void note_seq(chan *c, const lcm_eventlog_event_t *ev)
{
    if (c->type == T_UNKNOWN || ev->datalen < 24 || !strcmp(types[c->type].name, "cmd_t"))
        return; /* cmd_t seq counts per client, not per channel */
    int64_t utime = be64((const char *)ev->data + 8), seq = be64((const char *)ev->data + 16);
    int line, rc = bus_streams_note(&c->seq, seq, utime, 0, ev->timestamp * 1e-6,
                                    ev->timestamp, &line);
    const bus_stream *l = &c->seq.s[line];
    size_t n = strlen(c->notes);
    if ((rc == BUS_NEW && c->seq.ids > 1) || rc == BUS_RESTART)
        snprintf(c->notes + n, sizeof c->notes - n, "%s%s from seq %lld at %.3f s, its clock "
                 "%+.3f s from the log's%s", n ? "; " : "", rc == BUS_NEW ? "a sender" : "a restart",
                 (long long)seq, ((double)ev->timestamp - (double)c->t0) * 1e-6, l->offset_s,
                 bus_stream_replayed(l) ? " (a replay)" : "");
}

/* A channel --channel left out, kept (the first 64) to name when nothing
 * matched. */
static void note_other(log_run *r, const char *name)
{
    char shown[96];
    cli_text(shown, sizeof shown, name);
    for (int i = 0; i < r->nothers; i++)
        if (!strcmp(r->others[i], shown))
            return;
    if (r->nothers < 64)
        memcpy(r->others[r->nothers++], shown, sizeof shown);
    else
        r->more = 1;
}

static int csv_open_max(void)
{
    struct rlimit rl;
    if (getrlimit(RLIMIT_NOFILE, &rl) != 0 || rl.rlim_cur == RLIM_INFINITY)
        return CSV_OPEN_MAX;
    rlim_t half = rl.rlim_cur / 2;
    return half < 4 ? 4 : half < CSV_OPEN_MAX ? (int)half : CSV_OPEN_MAX;
}

/* Close c's CSV, saying so if a write to it failed: 0, or 1. */
static int close_csv(chan *c)
{
    errno = 0;
    int bad = ferror(c->csv), err = errno;
    if (fclose(c->csv))
        bad = 1, err = errno;
    c->csv = NULL;
    if (bad) /* its name and why: "error writing the CSV of X" said neither */
        fprintf(stderr, "wglog: writing %s (channel %s) failed: %s: the file is incomplete\n",
                c->file ? c->file : "?", c->shown, err ? strerror(err) : "a write error");
    return bad;
}

/* c's CSV open for its next rows: made ("w") at its first message, reopened
 * ("a") after close_open; CSV_OPEN_MAX open at most. 0, or -1 (said). */
static int csv_ready(log_run *r, chan *c)
{
    char path[4096];
    if (c->csv)
        return 0;
    if (!r->open_max)
        r->open_max = csv_open_max();
    if (r->nopen == r->open_max) {
        for (int i = 0; i < r->nopen; i++)
            r->wfail |= close_csv(&r->ch[r->open_ix[i]]);
        r->nopen = 0;
    }
    if (c->file)
        c->csv = fopen(c->file, "a");
    else if ((c->csv = open_csv(r, c, path, sizeof path)) && !(c->file = strdup(path)))
        fclose(c->csv), c->csv = NULL, errno = ENOMEM;
    if (!c->csv) {
        fprintf(stderr, "wglog: cannot write %s: %s\n", c->file ? c->file : path,
                strerror(errno));
        return -1;
    }
    r->open_ix[r->nopen++] = (int)(c - r->ch);
    return 0;
}

static int event(log_run *r, const lcm_eventlog_event_t *ev)
{
    if (r->has_re && regexec(&r->re, ev->channel, 0, NULL, 0) != 0) {
        note_other(r, ev->channel);
        return 0;
    }
    chan *c = find_chan(r, ev);
    if (!c || !c->name)
        return -1;
    if (r->export_ && c->type != T_UNKNOWN && (c->msgs == 0 || c->file) && csv_ready(r, c))
        return -1;
    int n = c->type == T_UNKNOWN ? 0 : types[c->type].rows(r, c, ev);
    if (n < 0) {
        c->bad++; /* its seq is no seq either (it was noted: a false restart) */
    } else {
        c->samples += n;
        note_seq(c, ev);
    }
    c->msgs++;
    c->bytes += ev->datalen;
    c->t1 = ev->timestamp;
    return 0;
}

/* --units physical: the scale of the log's first PARAMS (the samples
 * before it are in that scale too). 0, or 1 with a message. */
static int first_scale(log_run *r)
{
    logrd log;
    if (logrd_open(&log, r->path, 1))
        return 0; /* read_log reports it */
    lcm_eventlog_event_t *ev;
    int64_t h = __wormgear_params_t_get_hash();
    while (!units_scale_ok(&r->scale) && (ev = logrd_next(&log))) {
        wormgear_params_t m;
        if (ev->datalen >= 8 && be64(ev->data) == h && /* any channel: --channel STATE too */
            bus_msg_ok(BUS_PARAMS, ev->data, ev->datalen) &&
            wormgear_params_t_decode(ev->data, 0, ev->datalen, &m) >= 0) {
            r->scale = (units_scale){m.omega_n_rad_s, m.length_m, m.mesh_stiffness_N_m};
            wormgear_params_t_decode_cleanup(&m);
        }
        lcm_eventlog_free_event(ev);
    }
    fclose(log.f);
    if (units_scale_ok(&r->scale))
        return 0;
    fprintf(stderr, "wglog: --units physical: %s has no PARAMS message, so its physical scale "
                    "(omega_n, b_c, K_m) is unknown\n", r->path);
    return 1;
}

static int read_log(log_run *r)
{
    logrd log;
    if (logrd_open(&log, r->path, 0))
        return 1;
    int rc = 0;
    lcm_eventlog_event_t *ev;
    while (!rc && (ev = logrd_next(&log))) {
        if (r->events++ == 0)
            r->t0 = ev->timestamp;
        r->t1 = ev->timestamp;
        rc = event(r, ev) ? 1 : 0;
        lcm_eventlog_free_event(ev);
    }
    if (logrd_close(&log, r->path, r->events) && !rc)
        r->damaged = 1; /* the summary of what was read still comes; exit 1 */
    return rc;
}

/* ---- output ---------------------------------------------------------------------- */

static int by_name(const void *a, const void *b)
{
    return strcmp(((const chan *)a)->name, ((const chan *)b)->name);
}

static void summary(log_run *r, FILE *f)
{
    double span = ((double)r->t1 - (double)r->t0) * 1e-6; /* any int64 stamps: no overflow */
    fprintf(f, "log %s: %ld events, %.3f s, %d channels\n", r->path, r->events, span, r->nch);
    if (r->nch > 1) /* qsort of no array (NULL) is undefined */
        qsort(r->ch, (size_t)r->nch, sizeof *r->ch, by_name);
    fprintf(f, "%-24s %-11s %8s %9s %11s %9s %5s %8s %8s %6s %7s\n", "channel", "type", "msgs",
            "samples", "bytes", "rate_hz", "gaps", "missing", "restarts", "bad", "senders");
    for (int i = 0; i < r->nch; i++) {
        const chan *c = &r->ch[i];
        double s = ((double)c->t1 - (double)c->t0) * 1e-6;
        double rate = c->msgs > 1 && s > 0 ? (c->msgs - 1) / s : 0;
        fprintf(f, "%-24s %-11s %8ld %9ld %11lld %9.2f %5ld %8ld %8ld %6ld %7ld\n", c->shown,
                c->type == T_UNKNOWN ? "unknown" : types[c->type].name, c->msgs, c->samples, c->bytes,
                rate, c->seq.gaps, c->seq.missing, c->seq.restarts, c->bad, c->seq.senders);
    }
    for (int i = 0; i < r->nch; i++)
        if (r->ch[i].notes[0])
            fprintf(f, "note: %s: %s\n", r->ch[i].shown, r->ch[i].notes);
}

static int close_all(log_run *r)
{
    int rc = r->wfail;
    r->nopen = 0;
    for (int i = 0; i < r->nch; i++) {
        chan *c = &r->ch[i];
        if (c->csv && close_csv(c))
            rc = 1;
        if (r->export_ && c->bad && c->type != T_UNKNOWN) { /* they went without a word */
            fprintf(stderr, "wglog: %s: %ld of %ld messages are not whole %s messages (their "
                    "bytes fail the check; `wglog summary` counts them as bad): left out of %s\n",
                    c->shown, c->bad, c->msgs, types[c->type].name, c->file ? c->file : "its CSV");
            rc = 1;
        }
        if (r->export_ && c->type == T_UNKNOWN && !r->quiet)
            fprintf(stderr, "wglog: %s: not a wormgear type (fingerprint %016llx), skipped\n",
                    c->shown, (unsigned long long)c->hash);
    }
    return rc;
}

static void usage(FILE *f)
{
    fprintf(f,
            "usage: wglog summary LOG [options]\n"
            "       wglog export LOG [options]\n"
            "Summarise an LCM log of wormgeard (channels, types, counts, rates, seq gaps), or\n"
            "export each channel to DIR/CHANNEL.csv with the type's fields as columns (one row\n"
            "per sample for STATE, POINCARE, CONTACT). Record logs with\n"
            "  lcm-logger --lcm-url='udpm://239.255.76.67:7667?ttl=0' run.lcmlog\n\n"
            "  -o, --out DIR         export: output directory, created if missing (default .)\n"
            "  -c, --channel REGEX   only channels matching this POSIX extended regex, anchored\n"
            "                        (default: all, i.e. '.*')\n"
            "  -u, --units U         export: dimensionless (default) or physical: the samples\n"
            "                        of STATE, POINCARE, CONTACT in Hz, um, m/s, N (columns\n"
            "                        f_mesh_hz, x_n_um, dx_n_m_s, F_N, x1_um ... ds_m_s,\n"
            "                        velocity_m_s), with the scale of the log's PARAMS\n"
            "  -s, --summary         export: also print the summary\n"
            "  -q, --quiet           no notes about skipped channels\n"
            "  -h, --help            this text\n\n"
            "Exit status: 0 ok, 1 unreadable log, unwritable output or no channel matching\n"
            "--channel, 2 usage error.\n");
}

#define PROG "wglog"

static int opt_one(void *ctx, int c, const char *a)
{
    log_run *r = ctx;
    switch (c) {
    case 'o': r->out = a; return 0;
    case 'c': r->pattern = a; return 0;
    case 's': r->also_summary = 1; return 0;
    case 'u':
        if (strcmp(a, "physical") && strcmp(a, "dimensionless"))
            return cli_usage_error(PROG, "--units '%s': dimensionless or physical", a);
        r->physical = !strcmp(a, "physical");
        return 0;
    case 'q': r->quiet = 1; return 0;
    case 'h': usage(stdout); exit(0);
    default: return -1;
    }
}

static int parse(int argc, char **argv, log_run *r)
{
    static const struct option lo[] = {{"out", 1, 0, 'o'},     {"channel", 1, 0, 'c'},
                                       {"summary", 0, 0, 's'}, {"quiet", 0, 0, 'q'}, {"units", 1, 0, 'u'},
                                       {"help", 0, 0, 'h'},    {0, 0, 0, 0}};
    int rc = cli_getopt(PROG, argc, argv, "o:c:u:sqh", lo, opt_one, r);
    if (rc)
        return rc;
    if (argc - optind != 2)
        return cli_usage_error(PROG, "%d argument%s: expected two, a command (summary or export) "
                               "and a log file", argc - optind, argc - optind == 1 ? "" : "s");
    if (strcmp(argv[optind], "summary") && strcmp(argv[optind], "export"))
        return cli_usage_error(PROG, "command '%s': one of summary, export", argv[optind]);
    r->export_ = !strcmp(argv[optind], "export");
    r->path = argv[optind + 1];
    if (r->pattern) {
        char anchored[1024];
        snprintf(anchored, sizeof anchored, "^(%s)$", r->pattern);
        if (regcomp(&r->re, anchored, REG_EXTENDED | REG_NOSUB))
            return cli_usage_error(PROG, "--channel '%s': a POSIX extended regular expression",
                                   r->pattern);
        r->has_re = 1;
    }
    return 0;
}

/* --channel matched none of the log's channels: say which there are, exit 1. */
static int no_match(const log_run *r)
{
    if (!r->nothers) {
        fprintf(stderr, "wglog: %s has no events, so no channel matches --channel '%s'\n",
                r->path, r->pattern);
        return 1;
    }
    fprintf(stderr, "wglog: no channel of %s matches --channel '%s' (a regex matching the "
            "whole name); its channels include", r->path, r->pattern);
    for (int i = 0; i < r->nothers && i < 8; i++)
        fprintf(stderr, "%s %s", i ? "," : "", r->others[i]);
    if (r->nothers > 8 || r->more)
        fprintf(stderr, " and %s%d more", r->more ? "over " : "", r->nothers - 8);
    fprintf(stderr, "\n");
    return 1;
}

int main(int argc, char **argv)
{
    log_run r = {.out = "."};
    int rc = parse(argc, argv, &r);
    if (!rc && r.export_ && mkdir(r.out, 0777) && errno != EEXIST) {
        fprintf(stderr, "wglog: cannot create --out directory '%s': %s\n", r.out, strerror(errno));
        rc = 1;
    }
    if (!rc && r.physical)
        rc = first_scale(&r);
    if (!rc)
        rc = read_log(&r);
    rc |= close_all(&r);
    if (!rc && r.has_re && r.nch == 0)
        rc = no_match(&r);
    if (!rc && (!r.export_ || r.also_summary))
        summary(&r, stdout); /* of what could be read, a damaged log's too */
    rc |= r.damaged;
    for (int i = 0; i < r.nch; i++)
        free(r.ch[i].name), free(r.ch[i].file);
    free(r.ch);
    free(r.hix);
    if (r.has_re)
        regfree(&r.re);
    return cli_stdout_close(PROG, rc);
}

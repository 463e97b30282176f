/* log_rows.c - wglog's CSV rows, one writer per type (log_rows.h). */
#include "log_rows.h"
#include "bus_msg.h"
#include "lcmtypes/wormgear_ack_t.h"
#include "lcmtypes/wormgear_cmd_t.h"
#include "lcmtypes/wormgear_contact_t.h"
#include "lcmtypes/wormgear_params_t.h"
#include "lcmtypes/wormgear_poincare_t.h"
#include "lcmtypes/wormgear_scope_t.h"
#include "lcmtypes/wormgear_state_t.h"
#include "lcmtypes/wormgear_status_t.h"
#include "lcmtypes/wormgear_tick_t.h"
#include "units.h"
#include "wormgear/wg_model.h"
#include "wormgear/wg_param.h"
#include "wormgear/wg_scene.h"

#include <stdio.h>
#include <string.h>

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

int log_rows_type(int64_t hash)
{
    for (int t = 0; t < NTYPES; t++)
        if (types[t].hash() == hash)
            return t;
    return T_UNKNOWN;
}

const char *log_rows_type_name(int type) { return types[type].name; }

int log_rows(log_run *r, chan *c, const lcm_eventlog_event_t *ev)
{
    return types[c->type].rows(r, c, ev);
}

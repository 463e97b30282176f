/* web_msg.c - JSON encodings and schemas of wgweb's channels. */
#include "web_msg.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "wormgear/wg_param.h"

/* A schema field: "t:name:description" with t = n number, i integer,
 * s string, b boolean. */
static const char *const status_fields[] = {
    "i:utime:daemon send time, microseconds since the epoch", "i:seq:STATUS counter",
    "s:scene:scene name", "s:mode:realtime | fast | lockstep",
    "n:rate:realtime rate factor (1 = physical real time)", "s:run:running | paused | stepping",
    "s:health:ok | lagging | fault", "s:fault:what went wrong", "n:tau:simulation time (dimensionless)",
    "n:t_s:simulated time [s]", "n:omega:meshing frequency / omega_n", "i:steps:RK4 steps",
    "i:period:completed mesh periods", "i:steps_per_period:N",
    "n:rtf:real-time factor (simulated s / wall s)", "n:lag_s:behind the pace target [s]",
    "i:overruns:ticks that hit the catch-up cap", "n:loop_mean_us:loop iteration [us]",
    "n:loop_max_us:longest loop iteration [us]", "n:steps_per_s:steps per wall second",
    "n:cpu_share:daemon CPU time / wall time (1 = one core)", "i:msgs_dropped:messages the daemon failed to publish",
    "i:cmds_accepted:commands accepted", "i:cmds_refused:commands refused",
    "i:cmds_dropped:commands the daemon's inbox had no room for",
    "i:rx_dropped:datagrams the kernel dropped on the daemon's sockets",
    "i:ticks_refused:TICKs not taken (undecodable, out of range, unsigned, stale, replayed)",
    "s:tick_refusal:why the last TICK was not taken",
    "i:ticks_lost:TICKs lost on the way (gaps in their seq)",
    "s:motion:no_impact | single_sided | double_sided", "n:impacts_per_period:mesh impacts per period",
    "s:regime:period-N | aperiodic | ramping | unknown", "b:ramp_active:a ramp is running",
    "n:uptime_s:daemon uptime [s]", NULL};
static const char *const scope_fields[] = {
    "n:t_s:simulated time [s]", "n:tau:simulation time (dimensionless)", "i:step:RK4 step index",
    "i:utime:daemon publish time of the STATE batch [us since the epoch]",
    "n:omega:meshing frequency / omega_n", "n:x_n:relative mesh displacement / b_c",
    "n:dx_n:x_n rate (dimensionless)", "n:F:dynamic mesh force / (K_m b_c)",
    "n:fb_x1:worm bearing force x / (K_m b_c)", "n:fb_y1:worm bearing force y / (K_m b_c)",
    "n:fb_z1:worm bearing force z / (K_m b_c)", "n:fb_x2:wheel bearing force x / (K_m b_c)",
    "n:fb_y2:wheel bearing force y / (K_m b_c)", "n:fb_z2:wheel bearing force z / (K_m b_c)",
    "n:theta1:worm angle [rad], 0 to 2 pi", "n:theta2:wheel angle [rad], 0 to 2 pi", NULL};
static const char *const poincare_fields[] = {
    "i:period:index of the period that just ended", "n:tau:simulation time (dimensionless)",
    "n:t_s:simulated time [s]", "n:omega:meshing frequency / omega_n",
    "n:x_n:x_n at the section (psi = 0) / b_c", "n:dx_n:x_n rate at the section",
    "n:F:mesh force at the section / (K_m b_c)", "n:min_x_n:min x_n over the period",
    "n:max_x_n:max x_n over the period", "s:motion:no_impact | single_sided | double_sided",
    "i:motion_code:0 | 1 | 2", "i:impacts:mesh impacts in the period",
    "i:x1_impacts:worm bearing x impacts in the period (either side)",
    "i:y1_impacts:worm bearing y impacts in the period (either side)",
    "i:z1_impacts:worm bearing z impacts in the period (either side)",
    "i:x2_impacts:wheel bearing x impacts in the period (either side)",
    "i:y2_impacts:wheel bearing y impacts in the period (either side)",
    "i:z2_impacts:wheel bearing z impacts in the period (either side)",
    "n:x1_vmax:largest |impact velocity| of bearing x1 in the period (0: none)",
    "n:y1_vmax:largest |impact velocity| of bearing y1 in the period (0: none)",
    "n:z1_vmax:largest |impact velocity| of bearing z1 in the period (0: none)",
    "n:x2_vmax:largest |impact velocity| of bearing x2 in the period (0: none)",
    "n:y2_vmax:largest |impact velocity| of bearing y2 in the period (0: none)",
    "n:z2_vmax:largest |impact velocity| of bearing z2 in the period (0: none)",
    "s:regime:the daemon's latest regime (STATUS)", NULL};
static const char *const contact_fields[] = {
    "n:t_s:simulated time of the crossing [s]", "n:tau:its dimensionless time",
    "i:period:mesh period it fell in", "s:contact:mesh | x1 | y1 | z1 | x2 | y2 | z2",
    "i:contact_code:0 mesh, 1-6 bearings",
    "s:kind:separation | drive_impact | back_impact | back_release", "i:kind_code:0-3",
    "n:velocity:rate of the contact coordinate at the crossing (dimensionless)", NULL};
static const char *const ack_fields[] = {
    "i:utime:daemon send time [us]", "i:seq:ACK counter", "s:client:client id of the command",
    "i:cmd_seq:the command's seq", "s:op:the command's op", "b:accepted:applied",
    "i:status:0 or a negative wg_status code", "s:code:OK | EINVAL | ERANGE | ...",
    "s:message:the daemon's reason", "n:tau:simulation time it took effect",
    "n:t_s:the same [s]", "i:steps:step counter then",
    "s:request_id:the Foxglove request it answers (\"\" if none)",
    "i:ws_client:the WebSocket client that sent it (0 if none)", NULL};
static const char *const bridge_fields[] = {
    "n:uptime_s:bridge uptime [s]", "s:prefix:LCM channel prefix", "s:url:LCM URL",
    "s:daemon:ok | no heartbeat | waiting", "n:heartbeat_age_s:wall seconds since the last STATUS",
    "i:daemon_restarts:daemon restarts seen (STATUS seq going back)",
    "b:commands_allowed:--allow-commands", "i:origins_refused:WebSockets refused for their web page Origin",
    "i:params_ignored:PARAMS messages no daemon sends (scale, N, model, stepper or a value off), not forwarded",
    "i:unverified:with --key-file: messages (ACK, PARAMS, STATUS, STATE, POINCARE, CONTACT) not signed with its key (a daemon without it, or another sender), not forwarded",
    "i:signed_old:with --key-file: signed messages older than the bridge's start or the newest of their kind (played back), not forwarded",
    "i:clients:connected WebSocket clients",
    "i:lcm_msgs:LCM messages received", "i:lcm_gaps:messages lost in seq gaps",
    "n:scope_hz:target /scope samples per wall second",
    "n:scope_in_hz:STATE samples per wall second in", "i:scope_stride:steps between /scope samples",
    "i:poincare_kept:/poincare sections sent", "i:poincare_thinned:sections not sent (rate cap)",
    "i:contact_kept:/contact events sent", "i:contact_thinned:events not sent (cap or filter)",
    "i:queue_drops:messages dropped from client queues (oldest first)",
    "n:cpu_share:bridge CPU time / wall time over the last second (1 = one core)", NULL};

static const char *const *const fields_of[CHAN_N] = {
    NULL,          status_fields,  NULL, scope_fields, poincare_fields, contact_fields,
    ack_fields,    bridge_fields};
static const char *const topic_of[CHAN_N] = {
    NULL, "/status", "/params", "/scope", "/poincare", "/contact", "/ack", "/bridge"};
static const char *const sname_of[CHAN_N] = {
    NULL, "wormgear.Status", "wormgear.Params", "wormgear.Scope", "wormgear.Poincare",
    "wormgear.Contact", "wormgear.Ack", "wormgear.Bridge"};

const char *msg_topic(int c) { return c > 0 && c < CHAN_N ? topic_of[c] : NULL; }
const char *msg_schema_name(int c) { return c > 0 && c < CHAN_N ? sname_of[c] : NULL; }
const char *msg_schema(const msg_schemas *s, int c)
{
    return c > 0 && c < CHAN_N ? s->text[c] : NULL;
}

static const char *type_name(char t)
{
    return t == 'n' ? "number" : t == 'i' ? "integer" : t == 's' ? "string" : "boolean";
}

/* Append the properties and required list of a field table. */
static void schema_props(jbuf *b, const char *const *f, const char *extra_props)
{
    jb_key(b, "properties");
    jb_raw(b, "{");
    for (int i = 0; f[i]; i++) {
        const char *name = f[i] + 2, *desc = strchr(name, ':');
        char key[64];
        snprintf(key, sizeof key, "%.*s", (int)(desc - name), name);
        jb_key(b, key);
        jb_fmt(b, "{\"type\":\"%s\",\"description\":", type_name(f[i][0]));
        jb_str(b, desc + 1);
        jb_raw(b, "}");
    }
    if (extra_props)
        jb_raw(b, extra_props);
    jb_raw(b, "}");
    jb_key(b, "required");
    jb_raw(b, "[");
    for (int i = 0; f[i]; i++) {
        const char *name = f[i] + 2;
        jb_item(b);
        jb_fmt(b, "\"%.*s\"", (int)(strchr(name, ':') - name), name);
    }
    jb_raw(b, "]");
}

static void schema_of_fields(jbuf *b, int c)
{
    jb_raw(b, "{\"type\":\"object\"");
    jb_key(b, "title");
    jb_str(b, sname_of[c]);
    schema_props(b, fields_of[c], NULL);
    jb_raw(b, "}");
}

/* /params: scalars, `values` with one property per table row, `params`. */
static void schema_params(jbuf *b)
{
    static const char *const f[] = {
        "i:utime:daemon send time [us]", "i:seq:PARAMS counter",
        "s:reason:start periodic set ramp ramp-end reset restore get reload",
        "s:cmd_client:client of the command that caused it", "i:cmd_seq:its seq (-1 none)",
        "s:scene:scene", "s:model:consistent | printed", "s:stepper:rk4 | rk4-event",
        "i:steps_per_period:N", "n:omega_n_rad_s:one physical second is omega_n tau units",
        "n:length_m:b_c, x = 1 is this many metres", "n:mesh_stiffness_N_m:K_m, F = 1 is K_m b_c newtons",
        "n:tau:simulation time of the snapshot", "n:t_s:the same [s]", NULL};
    jbuf p;
    jb_init(&p);
    jb_raw(&p, ",\"values\":{\"type\":\"object\",\"properties\":{");
    for (int id = 0; id < WG_NPARAM; id++) {
        const wg_param_info *in = wg_param_info_get(id);
        jb_key(&p, in->name);
        char range[48];
        jb_fmt(&p, "{\"type\":\"number\",\"description\":\"%s [%s], range %s\"}", in->help,
               in->unit, wg_range_shown(in->min, in->max, range, sizeof range));
    }
    jb_raw(&p, "}},\"params\":{\"type\":\"array\",\"items\":{\"type\":\"object\",\"properties\":{"
               "\"name\":{\"type\":\"string\"},\"unit\":{\"type\":\"string\"},"
               "\"value\":{\"type\":\"number\"},\"min\":{\"type\":\"number\"},"
               "\"max\":{\"type\":\"number\"},\"def\":{\"type\":\"number\"},"
               "\"rampable\":{\"type\":\"boolean\"}},"
               "\"required\":[\"name\",\"unit\",\"value\",\"min\",\"max\",\"def\",\"rampable\"]}},"
               "\"ramp\":{\"type\":\"object\",\"properties\":{\"active\":{\"type\":\"boolean\"},"
               "\"param\":{\"type\":\"string\"},\"from\":{\"type\":\"number\"},"
               "\"to\":{\"type\":\"number\"},\"tau0\":{\"type\":\"number\"},"
               "\"duration_tau\":{\"type\":\"number\"}}}");
    jb_raw(b, "{\"type\":\"object\",\"title\":\"wormgear.Params\"");
    schema_props(b, f, jb_text(&p));
    jb_raw(b, "}");
    jb_free(&p);
}

int msg_schemas_init(msg_schemas *s)
{
    memset(s, 0, sizeof *s);
    for (int c = 1; c < CHAN_N; c++) {
        jbuf b;
        jb_init(&b);
        if (c == CHAN_PARAMS)
            schema_params(&b);
        else
            schema_of_fields(&b, c);
        if (b.oom) {
            jb_free(&b);
            msg_schemas_fini(s);
            return -1;
        }
        s->text[c] = b.s; /* start 0: the text is the allocation */
    }
    return 0;
}

void msg_schemas_fini(msg_schemas *s)
{
    for (int c = 0; c < CHAN_N; c++) {
        free(s->text[c]);
        s->text[c] = NULL;
    }
}

const char *msg_motion_name(int code)
{
    static const char *const n[] = {"no_impact", "single_sided", "double_sided"};
    return code >= 0 && code < 3 ? n[code] : "unknown";
}

const char *msg_contact_name(int code)
{
    static const char *const n[] = {"mesh", "x1", "y1", "z1", "x2", "y2", "z2"};
    return code >= 0 && code < 7 ? n[code] : "unknown";
}

const char *msg_kind_name(int code)
{
    static const char *const n[] = {"separation", "drive_impact", "back_impact", "back_release"};
    return code >= 0 && code < 4 ? n[code] : "unknown";
}

static void kn(jbuf *b, const char *k, double v) { jb_key(b, k); jb_num(b, v); }
static void kf(jbuf *b, const char *k, double v) { jb_key(b, k); jb_numf(b, v); }
static void ki(jbuf *b, const char *k, int64_t v) { jb_key(b, k); jb_int(b, v); }
static void ks(jbuf *b, const char *k, const char *v) { jb_key(b, k); jb_str(b, v); }
static void kb(jbuf *b, const char *k, int v) { jb_key(b, k); jb_bool(b, v); }

void msg_scope(jbuf *b, const wormgear_state_t *m, int i)
{
    jb_raw(b, "{");
    kn(b, "t_s", m->t_s[i]);
    kn(b, "tau", m->tau[i]);
    ki(b, "step", m->step0 + (int64_t)i * m->decimation);
    ki(b, "utime", m->utime);
    kf(b, "omega", m->omega[i]);
    kf(b, "x_n", m->xn[i]);
    kf(b, "dx_n", m->dxn[i]);
    kf(b, "F", m->force[i]);
    kf(b, "fb_x1", m->fb_x1[i]);
    kf(b, "fb_y1", m->fb_y1[i]);
    kf(b, "fb_z1", m->fb_z1[i]);
    kf(b, "fb_x2", m->fb_x2[i]);
    kf(b, "fb_y2", m->fb_y2[i]);
    kf(b, "fb_z2", m->fb_z2[i]);
    kf(b, "theta1", m->theta1[i]);
    kf(b, "theta2", m->theta2[i]);
    jb_raw(b, "}");
}

void msg_poincare(jbuf *b, const wormgear_poincare_t *m, int i, const char *regime)
{
    jb_raw(b, "{");
    ki(b, "period", m->period[i]);
    kn(b, "tau", m->tau[i]);
    kn(b, "t_s", m->t_s[i]);
    kn(b, "omega", m->omega[i]);
    kn(b, "x_n", m->xn[i]);
    kn(b, "dx_n", m->dxn[i]);
    kn(b, "F", m->force[i]);
    kn(b, "min_x_n", m->min_xn[i]);
    kn(b, "max_x_n", m->max_xn[i]);
    ks(b, "motion", msg_motion_name(m->motion[i]));
    ki(b, "motion_code", m->motion[i]);
    ki(b, "impacts", m->impacts[i]);
    for (int j = 0; j < m->nbearing && j < 6; j++) {
        static const char *const bn[6][2] = {{"x1_impacts", "x1_vmax"}, {"y1_impacts", "y1_vmax"},
                                             {"z1_impacts", "z1_vmax"}, {"x2_impacts", "x2_vmax"},
                                             {"y2_impacts", "y2_vmax"}, {"z2_impacts", "z2_vmax"}};
        ki(b, bn[j][0], m->bearing_impacts[i][j]);
        kn(b, bn[j][1], m->bearing_vmax[i][j]);
    }
    ks(b, "regime", regime);
    jb_raw(b, "}");
}

void msg_contact(jbuf *b, const wormgear_contact_t *m, int i)
{
    jb_raw(b, "{");
    kn(b, "t_s", m->t_s[i]);
    kn(b, "tau", m->tau[i]);
    ki(b, "period", m->period[i]);
    ks(b, "contact", msg_contact_name(m->contact[i]));
    ki(b, "contact_code", m->contact[i]);
    ks(b, "kind", msg_kind_name(m->kind[i]));
    ki(b, "kind_code", m->kind[i]);
    kn(b, "velocity", m->velocity[i]);
    jb_raw(b, "}");
}

void msg_status(jbuf *b, const wormgear_status_t *m)
{
    jb_raw(b, "{");
    ki(b, "utime", m->utime), ki(b, "seq", m->seq);
    ks(b, "scene", m->scene), ks(b, "mode", m->mode), kn(b, "rate", m->rate);
    ks(b, "run", m->run), ks(b, "health", m->health), ks(b, "fault", m->fault);
    kn(b, "tau", m->tau), kn(b, "t_s", m->t_s), kn(b, "omega", m->omega);
    ki(b, "steps", m->steps), ki(b, "period", m->period);
    ki(b, "steps_per_period", m->steps_per_period);
    kn(b, "rtf", m->rtf), kn(b, "lag_s", m->lag_s), ki(b, "overruns", m->overruns);
    kn(b, "loop_mean_us", m->loop_mean_us), kn(b, "loop_max_us", m->loop_max_us);
    kn(b, "steps_per_s", m->steps_per_s), kn(b, "cpu_share", m->cpu_share);
    ki(b, "msgs_dropped", m->msgs_dropped);
    ki(b, "cmds_accepted", m->cmds_accepted), ki(b, "cmds_refused", m->cmds_refused);
    ki(b, "cmds_dropped", m->cmds_dropped), ki(b, "rx_dropped", m->rx_dropped);
    ki(b, "ticks_refused", m->ticks_refused), ks(b, "tick_refusal", m->tick_refusal);
    ki(b, "ticks_lost", m->ticks_lost);
    ks(b, "motion", m->motion), kn(b, "impacts_per_period", m->impacts_per_period);
    ks(b, "regime", m->regime), kb(b, "ramp_active", m->ramp_active);
    kn(b, "uptime_s", m->uptime_s);
    jb_raw(b, "}");
}

static void params_table(jbuf *b, const wormgear_params_t *m)
{
    jb_key(b, "values");
    jb_raw(b, "{");
    for (int i = 0; i < m->n; i++)
        kn(b, m->name[i], m->value[i]);
    jb_raw(b, "}");
    jb_key(b, "params");
    jb_raw(b, "[");
    for (int i = 0; i < m->n; i++) {
        jb_item(b);
        jb_raw(b, "{");
        ks(b, "name", m->name[i]), ks(b, "unit", m->unit[i]);
        kn(b, "value", m->value[i]), kn(b, "min", m->min[i]), kn(b, "max", m->max[i]);
        kn(b, "def", m->def[i]), kb(b, "rampable", m->rampable[i]);
        jb_raw(b, "}");
    }
    jb_raw(b, "]");
}

void msg_params(jbuf *b, const wormgear_params_t *m)
{
    jb_raw(b, "{");
    ki(b, "utime", m->utime), ki(b, "seq", m->seq);
    ks(b, "reason", m->reason), ks(b, "cmd_client", m->cmd_client), ki(b, "cmd_seq", m->cmd_seq);
    ks(b, "scene", m->scene), ks(b, "model", m->model), ks(b, "stepper", m->stepper);
    ki(b, "steps_per_period", m->steps_per_period);
    kn(b, "omega_n_rad_s", m->omega_n_rad_s), kn(b, "length_m", m->length_m);
    kn(b, "mesh_stiffness_N_m", m->mesh_stiffness_N_m);
    kn(b, "tau", m->tau);
    kn(b, "t_s", m->omega_n_rad_s > 0 ? m->tau / m->omega_n_rad_s : 0.0);
    params_table(b, m);
    jb_key(b, "ramp");
    jb_raw(b, "{");
    kb(b, "active", m->ramp_active), ks(b, "param", m->ramp_param);
    kn(b, "from", m->ramp_from), kn(b, "to", m->ramp_to);
    kn(b, "tau0", m->ramp_tau0), kn(b, "duration_tau", m->ramp_duration_tau);
    jb_raw(b, "}}");
}

void msg_ack(jbuf *b, const wormgear_ack_t *m, const char *request_id, unsigned ws_client)
{
    jb_raw(b, "{");
    ki(b, "utime", m->utime), ki(b, "seq", m->seq);
    ks(b, "client", m->client), ki(b, "cmd_seq", m->cmd_seq), ks(b, "op", m->op);
    kb(b, "accepted", m->accepted), ki(b, "status", m->status);
    ks(b, "code", m->code), ks(b, "message", m->message);
    kn(b, "tau", m->tau), kn(b, "t_s", m->t_s), ki(b, "steps", m->steps);
    ks(b, "request_id", request_id), ki(b, "ws_client", ws_client);
    jb_raw(b, "}");
}

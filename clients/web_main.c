/* web_main.c - wgweb: the daemon's LCM channels as a Foxglove WebSocket
 * server, and the dashboard, on one port. One thread, one libev loop: the
 * LCM socket (ev_io), libwebsockets (on the same loop), a 0.5 s timer
 * (rates, heartbeat, bridge status, ACK timeouts) and INT/TERM signals.
 * Start-up order: schemas, LCM, protocol, server, watchers; shutdown in
 * reverse. */
#include <errno.h>
#include <ev.h>
#include <limits.h>
#include <signal.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

#include "web_bus.h"
#include "web_fox.h"
#include "web_msg.h"
#include "web_opt.h"
#include "web_srv.h"
#include "web_thin.h"

/* The one program struct. */
typedef struct wgweb {
    web_opt o;
    struct ev_loop *loop;
    msg_schemas schemas;
    web_bus bus;
    fox fox;
    srv srv;
    thin_scope scope;
    thin_rate sections, contacts;
    ev_io lcm_w;
    ev_timer sec_w;
    ev_signal int_w, term_w;
    jbuf enc;             /* one message being encoded */
    char root[PATH_MAX];
    char regime[32];      /* the daemon's latest (STATUS) */
    double start_s, last_status_s, last_sec_s, cpu_last_s, cpu_share;
    double last_t_s;      /* latest simulated time seen */
    int heartbeat_lost, have_status;
    long params_ignored;      /* PARAMS no daemon sends (bus_params_odd) */
    uint64_t restarts_seen;
} wgweb;

static double mono_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_MONOTONIC, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static double cpu_s(void)
{
    struct timespec ts;
    clock_gettime(CLOCK_PROCESS_CPUTIME_ID, &ts);
    return ts.tv_sec + ts.tv_nsec * 1e-9;
}

static uint64_t ns_of(double t_s) { return t_s > 0 ? (uint64_t)(t_s * 1e9 + 0.5) : 0; }

static void publish_enc(wgweb *w, int chan, double t_s)
{
    if (!w->enc.oom)
        fox_publish(&w->fox, chan, jb_text(&w->enc), jb_len(&w->enc), ns_of(t_s));
    jb_reset(&w->enc);
}

/* ---- LCM messages in */

static void on_state(void *ctx, const wormgear_state_t *m)
{
    wgweb *w = ctx;
    int want = fox_wanted(&w->fox, CHAN_SCOPE);
    for (int i = 0; i < m->n; i++) {
        int64_t step = m->step0 + (int64_t)i * m->decimation;
        if (thin_scope_keep(&w->scope, step, m->decimation) && want) {
            msg_scope(&w->enc, m, i);
            publish_enc(w, CHAN_SCOPE, m->t_s[i]);
        }
    }
    if (m->n > 0) {
        w->last_t_s = m->t_s[m->n - 1];
        fox_time(&w->fox, ns_of(w->last_t_s));
    }
}

static void on_poincare(void *ctx, const wormgear_poincare_t *m)
{
    wgweb *w = ctx;
    double now = mono_s();
    int want = fox_wanted(&w->fox, CHAN_POINCARE);
    for (int i = 0; i < m->n; i++)
        if (thin_rate_keep(&w->sections, now) && want) {
            msg_poincare(&w->enc, m, i, w->regime);
            publish_enc(w, CHAN_POINCARE, m->t_s[i]);
        }
}

static void on_contact(void *ctx, const wormgear_contact_t *m)
{
    wgweb *w = ctx;
    double now = mono_s();
    int want = fox_wanted(&w->fox, CHAN_CONTACT);
    for (int i = 0; i < m->n; i++) {
        if (m->contact[i] != 0 && !w->o.contacts_all) {
            w->contacts.thinned++;
            continue;
        }
        if (thin_rate_keep(&w->contacts, now) && want) {
            msg_contact(&w->enc, m, i);
            publish_enc(w, CHAN_CONTACT, m->t_s[i]);
        }
    }
}

static void send_get(wgweb *w)
{
    wormgear_cmd_t c;
    memset(&c, 0, sizeof c);
    c.op = (char *)"get";
    c.name = c.unit = (char *)"";
    web_bus_send(&w->bus, &c);
}

/* A STATUS after silence or a seq going back: the daemon (re)started. */
static void daemon_seen(wgweb *w)
{
    uint64_t r = web_bus_restarts(&w->bus, WEB_BUS_STATUS);
    int restarted = r != w->restarts_seen;
    w->restarts_seen = r;
    if (restarted) {
        fox_readvertise(&w->fox);
        fox_status(&w->fox, -1, 1, "the daemon restarted: channels re-advertised");
    } else if (w->heartbeat_lost) {
        fox_status(&w->fox, -1, 0, "daemon heartbeat back");
    }
    if (restarted || w->heartbeat_lost || !w->have_status)
        send_get(w);
    w->heartbeat_lost = 0;
    w->have_status = 1;
}

static void on_status(void *ctx, const wormgear_status_t *m)
{
    wgweb *w = ctx;
    w->last_status_s = mono_s();
    snprintf(w->regime, sizeof w->regime, "%s", m->regime);
    daemon_seen(w);
    if (fox_wanted(&w->fox, CHAN_STATUS)) {
        msg_status(&w->enc, m);
        publish_enc(w, CHAN_STATUS, m->t_s);
    }
}

static void on_params(void *ctx, const wormgear_params_t *m)
{
    wgweb *w = ctx;
    char say[160];
    if (bus_params_ignore(m, &w->params_ignored, "wgweb", say, sizeof say)) {
        fputs(say, stderr);
        return; /* not forwarded: every client would show it */
    }
    fox_params(&w->fox, m);
    if (fox_wanted(&w->fox, CHAN_PARAMS)) {
        msg_params(&w->enc, m);
        publish_enc(w, CHAN_PARAMS, m->omega_n_rad_s > 0 ? m->tau / m->omega_n_rad_s : 0);
    }
}

static void on_ack(void *ctx, const wormgear_ack_t *m)
{
    wgweb *w = ctx;
    char id[64];
    unsigned owner = fox_ack_owner(&w->fox, m, web_bus_client_id(&w->bus), id, sizeof id);
    if (w->o.verbose)
        fprintf(stderr, "wgweb: ack %s seq %lld %s %s\n", m->op, (long long)m->cmd_seq, m->code,
                m->message);
    if (fox_wanted(&w->fox, CHAN_ACK)) {
        msg_ack(&w->enc, m, id, owner);
        publish_enc(w, CHAN_ACK, m->t_s);
    }
    fox_ack(&w->fox, m, web_bus_client_id(&w->bus));
}

static void on_ack_unverified(void *ctx, const wormgear_ack_t *m)
{
    wgweb *w = ctx;
    fox_ack_unverified(&w->fox, m, web_bus_client_id(&w->bus));
}

/* ---- fox hooks */

static void hook_wake(void *ctx, void *conn) { srv_wake(&((wgweb *)ctx)->srv, conn); }
static void hook_kick(void *ctx, void *conn) { srv_kick(&((wgweb *)ctx)->srv, conn); }

static int64_t hook_command(void *ctx, wormgear_cmd_t *cmd, char *why, size_t whylen)
{
    wgweb *w = ctx;
    if (w->o.verbose)
        fprintf(stderr, "wgweb: command %s (%d params)\n", cmd->op, cmd->nparams);
    int64_t seq = web_bus_send(&w->bus, cmd);
    if (seq < 0) {
        snprintf(why, whylen, "%s", web_bus_send_why(&w->bus));
        fprintf(stderr, "wgweb: %s not sent: %s\n", cmd->op, why);
    }
    return seq;
}

/* ---- watchers */

static void on_lcm(struct ev_loop *loop, ev_io *io, int revents)
{
    (void)loop, (void)revents;
    wgweb *w = io->data;
    web_bus_drain(&w->bus, 256);
}

static void bridge_status(wgweb *w, double now)
{
    jbuf *b = &w->enc;
    double age = w->have_status ? now - w->last_status_s : -1;
    jb_raw(b, "{");
    jb_key(b, "uptime_s"), jb_num(b, now - w->start_s);
    jb_key(b, "prefix"), jb_str(b, web_bus_prefix(&w->bus));
    jb_key(b, "url"), jb_str(b, w->bus.url);
    jb_key(b, "daemon"), jb_str(b, !w->have_status ? "waiting" : w->heartbeat_lost ? "no heartbeat" : "ok");
    jb_key(b, "heartbeat_age_s"), jb_num(b, age);
    jb_key(b, "daemon_restarts"), jb_int(b, (int64_t)web_bus_restarts(&w->bus, WEB_BUS_STATUS));
    jb_key(b, "commands_allowed"), jb_bool(b, w->o.allow_commands);
    jb_key(b, "origins_refused"), jb_int(b, (int64_t)w->srv.bad_origin);
    jb_key(b, "params_ignored"), jb_int(b, (int64_t)w->params_ignored);
    jb_key(b, "unverified"), jb_int(b, (int64_t)w->bus.c.unverified_n);
    jb_key(b, "signed_old"), jb_int(b, (int64_t)w->bus.c.old_n);
    jb_key(b, "clients"), jb_int(b, fox_nclients(&w->fox));
    jb_key(b, "lcm_msgs"), jb_int(b, (int64_t)w->bus.msgs);
    jb_key(b, "lcm_gaps"), jb_int(b, (int64_t)web_bus_gaps(&w->bus));
    jb_key(b, "scope_hz"), jb_num(b, w->scope.target_hz);
    jb_key(b, "scope_in_hz"), jb_num(b, w->scope.in_hz);
    jb_key(b, "scope_stride"), jb_int(b, w->scope.stride_steps);
    jb_key(b, "poincare_kept"), jb_int(b, (int64_t)w->sections.kept);
    jb_key(b, "poincare_thinned"), jb_int(b, (int64_t)w->sections.thinned);
    jb_key(b, "contact_kept"), jb_int(b, (int64_t)w->contacts.kept);
    jb_key(b, "contact_thinned"), jb_int(b, (int64_t)w->contacts.thinned);
    jb_key(b, "queue_drops"), jb_int(b, (int64_t)w->fox.queue_drops);
    jb_key(b, "cpu_share"), jb_num(b, w->cpu_share);
    fox_stats(&w->fox, b);
    jb_raw(b, "}");
    publish_enc(w, CHAN_BRIDGE, w->last_t_s);
}

static void on_sec(struct ev_loop *loop, ev_timer *t, int revents)
{
    (void)loop, (void)revents;
    wgweb *w = t->data;
    double now = mono_s(), dt = now - w->last_sec_s, cpu = cpu_s();
    w->cpu_share = dt > 0 ? (cpu - w->cpu_last_s) / dt : 0;
    w->cpu_last_s = cpu;
    w->last_sec_s = now;
    thin_scope_second(&w->scope, dt);
    thin_rate_second(&w->sections, dt);
    thin_rate_second(&w->contacts, dt);
    if (w->have_status && !w->heartbeat_lost && now - w->last_status_s > w->o.heartbeat_s) {
        w->heartbeat_lost = 1;
        fox_status(&w->fox, -1, 1, "no heartbeat from the daemon (%s) for %.1f s",
                   web_bus_prefix(&w->bus), now - w->last_status_s);
    }
    fox_tick(&w->fox, now);
    bridge_status(w, now);
}

static void on_signal(struct ev_loop *loop, ev_signal *s, int revents)
{
    (void)s, (void)revents;
    ev_break(loop, EVBREAK_ALL);
}

/* ---- start-up and shutdown */

/* The dashboard's directory into w->root: 0 with index.html in it, 1
 * without (the WebSocket only: no file is served at all), -1 when a root
 * given with --web-root or $WGWEB_ROOT is not a directory it can read (the
 * program exits 1, as --help says). */
static int find_root(wgweb *w)
{
    const char *r = w->o.web_root ? w->o.web_root : getenv("WGWEB_ROOT");
    char exe[PATH_MAX], probe[PATH_MAX + 16];
    struct stat st;
    if (r && *r) {
        snprintf(w->root, sizeof w->root, "%s", r);
        int bad = stat(w->root, &st) != 0 ? errno : !S_ISDIR(st.st_mode) ? ENOTDIR
                  : access(w->root, R_OK | X_OK) != 0 ? errno : 0;
        if (bad) {
            fprintf(stderr, "wgweb: web root '%s': %s (--web-root or $WGWEB_ROOT: a readable "
                            "directory, the dashboard's index.html in it)\n", w->root,
                    strerror(bad));
            return -1;
        }
    } else {
        ssize_t n = readlink("/proc/self/exe", exe, sizeof exe - 1);
        exe[n > 0 ? n : 0] = '\0';
        char *slash = strrchr(exe, '/');
        if (slash)
            *slash = '\0';
        snprintf(w->root, sizeof w->root, "%.*s/../share/wormgear/web", PATH_MAX - 32, exe);
    }
    snprintf(probe, sizeof probe, "%s/index.html", w->root);
    if (stat(probe, &st) != 0 || !S_ISREG(st.st_mode)) {
        fprintf(stderr, "wgweb: no dashboard in %s (index.html missing): only the Foxglove "
                        "WebSocket is served, no files (build the tree, or pass --web-root)\n",
                w->root);
        return 1;
    }
    return 0;
}

static int start_fox(wgweb *w)
{
    char name[160];
    snprintf(name, sizeof name, "wgweb %s", web_bus_prefix(&w->bus));
    fox_conf fc = {.name = name, .prefix = web_bus_prefix(&w->bus), .url = w->bus.url,
                   .allow_commands = w->o.allow_commands, .max_clients = w->o.max_clients,
                   .queue_len = (size_t)w->o.queue_len, .queue_bytes = (size_t)w->o.queue_len * 4096,
                   .ack_timeout_s = w->o.ack_timeout_s, .schemas = &w->schemas};
    fox_hooks fh = {.ctx = w, .wake = hook_wake, .kick = hook_kick, .command = hook_command};
    return fox_init(&w->fox, &fc, &fh);
}

static int start(wgweb *w)
{
    char why[256];
    web_bus_hooks bh = {.ctx = w, .state = on_state, .poincare = on_poincare, .contact = on_contact,
                    .status = on_status, .params = on_params, .ack = on_ack,
                          .ack_unverified = on_ack_unverified};
    if (msg_schemas_init(&w->schemas) != 0)
        return fprintf(stderr, "wgweb: out of memory\n"), -1;
    int brc = web_bus_open(&w->bus, w->o.url, w->o.prefix, &bh, why, sizeof why);
    if (brc || (w->o.key_file && bus_set_key(&w->bus.c, w->o.key_file, why, sizeof why)))
        return fprintf(stderr, "wgweb: %s\n", why), brc == BUS_EURL ? BUS_EURL : -1;
    if (start_fox(w) != 0)
        return fprintf(stderr, "wgweb: out of memory\n"), -1;
    int root = find_root(w);
    if (root < 0)
        return -1;
    srv_conf sc = {.iface = w->o.listen, .port = w->o.port, .web_root = root ? NULL : w->root,
                   .origins = w->o.origins, .norigins = w->o.norigins,
                   .max_frame = (size_t)w->o.max_frame};
    if (srv_init(&w->srv, w->loop, &sc, &w->fox, why, sizeof why) != 0)
        return fprintf(stderr, "wgweb: %s\n", why), -1;
    return 0;
}

/* INT and TERM held (1) from main's start until the loop's watchers take
 * them (0): one during the start (the LCM and the listening socket) ended
 * wgweb with 143 instead of its clean stop. */
static void hold_stop_signals(int hold)
{
    sigset_t set;
    sigemptyset(&set);
    sigaddset(&set, SIGINT), sigaddset(&set, SIGTERM);
    sigprocmask(hold ? SIG_BLOCK : SIG_UNBLOCK, &set, NULL);
}

static void watch(wgweb *w)
{
    ev_io_init(&w->lcm_w, on_lcm, web_bus_fileno(&w->bus), EV_READ);
    w->lcm_w.data = w;
    ev_io_start(w->loop, &w->lcm_w);
    ev_timer_init(&w->sec_w, on_sec, 0.5, 0.5);
    w->sec_w.data = w;
    ev_timer_start(w->loop, &w->sec_w);
    ev_signal_init(&w->int_w, on_signal, SIGINT);
    ev_signal_init(&w->term_w, on_signal, SIGTERM);
    ev_signal_start(w->loop, &w->int_w);
    ev_signal_start(w->loop, &w->term_w);
    hold_stop_signals(0); /* the watchers take them now, one that came meanwhile first */
}

static void stop(wgweb *w)
{
    if (w->loop) {
        ev_io_stop(w->loop, &w->lcm_w);
        ev_timer_stop(w->loop, &w->sec_w);
        ev_signal_stop(w->loop, &w->int_w);
        ev_signal_stop(w->loop, &w->term_w);
    }
    srv_fini(&w->srv);
    fox_fini(&w->fox);
    web_bus_close(&w->bus);
    msg_schemas_fini(&w->schemas);
    jb_free(&w->enc);
}

/* Before the socket: an address that cannot be used gets the warning too. */
static void warn_exposed(const web_opt *o)
{
    if (!web_opt_is_loopback(o->listen))
        fprintf(stderr, "wgweb: WARNING: --listen %s is not loopback: every host that reaches it "
                        "sees the daemon's data%s\n", o->listen,
                o->allow_commands ? " and can command it (--allow-commands)" : "");
}

static void announce(const wgweb *w)
{
    const char *l = w->o.listen;
    const char *lb = strchr(l, ':') ? "[" : "", *rb = *lb ? "]" : ""; /* IPv6 in a URL */
    printf("wgweb: %s on %s -> http://%s%s%s:%d/ (Foxglove: ws://%s%s%s:%d), commands %s\n",
           web_bus_prefix(&w->bus), w->bus.url, lb, l, rb, w->srv.port, lb, l, rb, w->srv.port,
           w->o.allow_commands ? "allowed" : "refused");
    fflush(stdout);
}

int main(int argc, char **argv)
{
    static wgweb w; /* the one program struct */
    hold_stop_signals(1);
    int rc = web_opt_parse(&w.o, argc, argv);
    if (rc)
        return rc == 1 ? 0 : 2;
    warn_exposed(&w.o);
    signal(SIGPIPE, SIG_IGN);
    w.loop = ev_default_loop(EVFLAG_AUTO);
    jb_init(&w.enc);
    thin_scope_init(&w.scope, w.o.scope_hz);
    thin_rate_init(&w.sections, w.o.poincare_hz, 0x5eed1ull);
    thin_rate_init(&w.contacts, w.o.contact_hz, 0x5eed2ull);
    w.start_s = w.last_sec_s = mono_s();
    w.cpu_last_s = cpu_s();
    snprintf(w.regime, sizeof w.regime, "unknown");
    int src = start(&w);
    if (src != 0) {
        stop(&w);
        return bus_exit_status(src); /* an LCM URL LCM refuses: a usage error */
    }
    watch(&w);
    announce(&w);
    send_get(&w);
    ev_run(w.loop, 0);
    stop(&w);
    ev_loop_destroy(w.loop);
    return 0;
}

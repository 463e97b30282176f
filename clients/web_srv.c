/* web_srv.c - libwebsockets glue: HTTP mount and the Foxglove subprotocol. */
#include "web_srv.h"

#include <arpa/inet.h>
#include <errno.h>
#include <netinet/in.h>
#include <stdio.h>
#include <string.h>
#include <sys/socket.h>
#include <unistd.h>

#include "web_cmd.h"

/* Per-connection data (zeroed by lws). */
typedef struct srv_conn {
    struct lws *wsi;
    int ci;      /* fox client index when open */
    int open;    /* fox_open succeeded */
    int kicked;  /* close at the next writable callback */
    int rx_over; /* the frame being received is over max_frame */
    int close_len;       /* > 0: close with 1007 and close_why at the next writable */
    char close_why[120];
    jbuf rx;     /* the frame being received */
} srv_conn;

static srv *srv_of(struct lws *wsi) { return lws_context_user(lws_get_context(wsi)); }

static int on_established(srv *s, srv_conn *c, struct lws *wsi)
{
    c->wsi = wsi;
    jb_init(&c->rx);
    c->ci = fox_open(s->fox, c);
    if (c->ci < 0) {
        static const char msg[] = "too many clients";
        lws_close_reason(wsi, LWS_CLOSE_STATUS_POLICY_VIOLATION, (unsigned char *)msg,
                         sizeof msg - 1);
        return -1;
    }
    c->open = 1;
    return 0;
}

/* RFC 6455 5.6, 8.1: a text message that is not UTF-8 fails the
 * connection with 1007 (it was taken, with U+FFFD in our answers). Checked
 * on the whole message, so a character split between fragments is fine.
 * The close frame's reason is the one message the client gets; it is sent
 * from the writable callback (returned -1 from here, lws sometimes closed
 * without a close frame: 1006 at the client, seen under ASan). */
static int text_not_utf8(srv *s, srv_conn *c, const jbuf *rx)
{
    long at = web_utf8_bad_at(jb_text(rx), jb_len(rx));
    if (at < 0)
        return 0;
    s->fox->bad_frames++;
    int n = snprintf(c->close_why, sizeof c->close_why, "invalid UTF-8 at byte %ld: a text "
                     "message must be UTF-8 (RFC 6455)", at);
    c->close_len = n < (int)sizeof c->close_why ? n : (int)sizeof c->close_why - 1;
    lws_callback_on_writable(c->wsi);
    return 1;
}

static int on_receive(srv *s, srv_conn *c, struct lws *wsi, const void *in, size_t len)
{
    if (c->close_len) /* failed: nothing more is read */
        return 0;
    if (lws_is_first_fragment(wsi)) {
        jb_reset(&c->rx);
        c->rx_over = 0;
    }
    if (!c->rx_over && jb_len(&c->rx) + len > s->conf.max_frame) {
        c->rx_over = 1;
        s->oversized++;
        s->fox->bad_frames++;
        fox_status(s->fox, c->ci, 2, "frame over %zu bytes discarded", s->conf.max_frame);
        jb_free(&c->rx);
    }
    if (!c->rx_over)
        jb_mem(&c->rx, in, len);
    if (!lws_is_final_fragment(wsi) || lws_remaining_packet_payload(wsi) > 0)
        return 0;
    int binary = lws_frame_is_binary(wsi);
    if (!c->rx_over && !c->rx.oom && !binary && text_not_utf8(s, c, &c->rx))
        return 0;
    if (!c->rx_over && !c->rx.oom)
        fox_rx(s->fox, c->ci, (const unsigned char *)jb_text(&c->rx), jb_len(&c->rx), binary);
    jb_reset(&c->rx);
    c->rx_over = 0;
    return 0;
}

static int on_writeable(srv *s, srv_conn *c, struct lws *wsi)
{
    int binary;
    if (c->close_len) {
        lws_close_reason(wsi, LWS_CLOSE_STATUS_INVALID_PAYLOAD, (unsigned char *)c->close_why,
                         (size_t)c->close_len);
        return -1;
    }
    if (c->kicked)
        return -1;
    for (int n = 0; n < 64 && !lws_send_pipe_choked(wsi); n++) {
        if (!fox_frame(s->fox, c->ci, &s->out, &binary))
            return 0;
        size_t len = jb_len(&s->out);
        unsigned char *p = (unsigned char *)s->out.s + LWS_PRE;
        if (lws_write(wsi, p, len, binary ? LWS_WRITE_BINARY : LWS_WRITE_TEXT) < (int)len)
            return -1;
    }
    if (fox_has_frames(s->fox, c->ci))
        lws_callback_on_writable(wsi);
    return 0;
}

/* A browser sends the page's Origin with a WebSocket: only this bridge's
 * own pages (http://ITS-ADDRESS:PORT, localhost, 127.0.0.1, [::1]) and
 * --allow-origin ones may connect, or any web page the user happens to
 * open could read the daemon's data and, with --allow-commands, drive it.
 * Non-browser clients (Foxglove desktop, node) send no Origin. */
static int origin_ok(const srv *s, const char *o)
{
    const char *own[] = {"localhost", "127.0.0.1", "[::1]", s->conf.iface};
    char want[300];
    for (unsigned i = 0; i < sizeof own / sizeof own[0]; i++) {
        snprintf(want, sizeof want, "http://%s:%d", own[i], s->port);
        if (!strcmp(o, want))
            return 1;
    }
    for (int i = 0; i < s->conf.norigins; i++)
        if (!strcmp(o, s->conf.origins[i]))
            return 1;
    return 0;
}

static int filter(srv *s, struct lws *wsi)
{
    char o[300], v[16];
    /* RFC 6455 knows version 13 only; libwebsockets upgraded any */
    if (lws_hdr_copy(wsi, v, sizeof v, WSI_TOKEN_VERSION) <= 0 || strcmp(v, "13") != 0) {
        lws_return_http_status(wsi, 426, "WebSocket version 13 (RFC 6455) only");
        return -1;
    }
    int olen = lws_hdr_total_length(wsi, WSI_TOKEN_ORIGIN);
    if (olen <= 0) /* no Origin: not a browser */
        return 0;
    if (lws_hdr_copy(wsi, o, sizeof o, WSI_TOKEN_ORIGIN) > 0 && origin_ok(s, o))
        return 0; /* one too long to copy is refused (it was taken as none) */
    if (olen >= (int)sizeof o)
        snprintf(o, sizeof o, "(%d characters)", olen);
    if (s->bad_origin++ < 5)
        fprintf(stderr, "wgweb: refused a WebSocket from the web page origin '%.100s' (not this "
                        "bridge's own; --allow-origin to allow it)\n", o);
    return -1;
}

static int cb_fox(struct lws *wsi, enum lws_callback_reasons reason, void *user, void *in,
                  size_t len)
{
    srv *s = srv_of(wsi);
    srv_conn *c = user;
    switch (reason) {
    case LWS_CALLBACK_FILTER_PROTOCOL_CONNECTION:
        return filter(s, wsi);
    case LWS_CALLBACK_ESTABLISHED:
        return on_established(s, c, wsi);
    case LWS_CALLBACK_RECEIVE:
        return c->open ? on_receive(s, c, wsi, in, len) : 0;
    case LWS_CALLBACK_SERVER_WRITEABLE:
        return c->open ? on_writeable(s, c, wsi) : -1;
    case LWS_CALLBACK_CLOSED:
        if (c->open)
            fox_close(s->fox, c->ci);
        c->open = 0;
        jb_free(&c->rx);
        return 0;
    default:
        return 0;
    }
}

/* protocols[0]: HTTP (static files); a WebSocket that asked for no
 * subprotocol lands here and is refused. */
static int cb_http(struct lws *wsi, enum lws_callback_reasons reason, void *user, void *in,
                   size_t len)
{
    if (reason == LWS_CALLBACK_ESTABLISHED)
        return -1;
    return lws_callback_http_dummy(wsi, reason, user, in, len);
}

static void lws_log(int level, const char *line)
{
    fprintf(stderr, "wgweb: lws%s: %s", level == LLL_ERR ? " error" : "", line);
}

static void fill_info(srv *s, struct lws_context_creation_info *info, struct ev_loop *loop)
{
    s->protos[0] = (struct lws_protocols){"http", cb_http, 0, 0, 0, NULL, 0};
    s->protos[1] = (struct lws_protocols){"foxglove.websocket.v1", cb_fox, sizeof(srv_conn),
                                          4096, 0, NULL, 0};
    memset(&s->mount, 0, sizeof s->mount);
    s->mount.mountpoint = "/";
    s->mount.mountpoint_len = 1;
    s->mount.origin = s->root;
    s->mount.def = "index.html";
    s->mount.origin_protocol = LWSMPRO_FILE;
    s->loops[0] = loop;
    memset(info, 0, sizeof *info);
    info->port = s->conf.port;
    info->iface = s->conf.iface;
    info->protocols = s->protos;
    info->mounts = s->conf.web_root ? &s->mount : NULL; /* none: no file served */
    info->options = LWS_SERVER_OPTION_LIBEV |
                    LWS_SERVER_OPTION_HTTP_HEADERS_SECURITY_BEST_PRACTICES_ENFORCE;
    if (!strchr(s->conf.iface, ':'))
        info->options |= LWS_SERVER_OPTION_DISABLE_IPV6;
    info->foreign_loops = s->loops;
    info->user = s;
    info->vhost_name = "wgweb";
}

/* 0 if iface (an IP address, web_opt) is one of this host's: a socket binds
 * to it (port 0, closed at once). lws keeps a vhost whose address is not
 * here, waiting for it to appear, and listens nowhere. */
static int addr_here(const char *iface, char *why, size_t whylen)
{
    struct sockaddr_in a4 = {.sin_family = AF_INET};
    struct sockaddr_in6 a6 = {.sin6_family = AF_INET6};
    int v4 = inet_pton(AF_INET, iface, &a4.sin_addr) == 1;
    if (!v4 && inet_pton(AF_INET6, iface, &a6.sin6_addr) != 1) {
        snprintf(why, whylen, "cannot listen on '%s': not an IP address", iface);
        return -1;
    }
    int fd = socket(v4 ? AF_INET : AF_INET6, SOCK_STREAM | SOCK_CLOEXEC, 0), err = 0;
    if (fd < 0 || (v4 ? bind(fd, (struct sockaddr *)&a4, sizeof a4)
                      : bind(fd, (struct sockaddr *)&a6, sizeof a6)) != 0)
        err = errno;
    if (fd >= 0)
        close(fd);
    if (err)
        snprintf(why, whylen, "cannot listen on %s: %s (--listen takes an address of this host)",
                 iface, strerror(err));
    return err ? -1 : 0;
}

int srv_init(srv *s, struct ev_loop *loop, const srv_conf *conf, fox *f, char *why,
             size_t whylen)
{
    struct lws_context_creation_info info;
    memset(s, 0, sizeof *s);
    if (addr_here(conf->iface, why, whylen) != 0)
        return -1;
    s->conf = *conf;
    s->fox = f;
    snprintf(s->root, sizeof s->root, "%s", conf->web_root ? conf->web_root : "");
    jb_init_pre(&s->out, LWS_PRE);
    lws_set_log_level(LLL_ERR | LLL_WARN, lws_log);
    fill_info(s, &info, loop);
    s->ctx = lws_create_context(&info);
    if (!s->ctx) {
        snprintf(why, whylen, "cannot listen on %s port %d (in use, or not an address here)",
                 conf->iface, conf->port);
        jb_free(&s->out);
        return -1;
    }
    struct lws_vhost *vh = lws_get_vhost_by_name(s->ctx, "wgweb");
    s->port = vh ? lws_get_vhost_listen_port(vh) : 0;
    if (s->port <= 0) { /* not expected after addr_here: lws listens nowhere */
        snprintf(why, whylen, "cannot listen on %s port %d", conf->iface, conf->port);
        srv_fini(s);
        return -1;
    }
    return 0;
}

void srv_fini(srv *s)
{
    if (s->ctx)
        lws_context_destroy(s->ctx);
    s->ctx = NULL;
    jb_free(&s->out);
}

void srv_wake(srv *s, void *conn)
{
    (void)s;
    srv_conn *c = conn;
    if (c && c->wsi)
        lws_callback_on_writable(c->wsi);
}

void srv_kick(srv *s, void *conn)
{
    srv_conn *c = conn;
    (void)s;
    if (c && c->wsi) {
        c->kicked = 1;
        lws_callback_on_writable(c->wsi);
    }
}

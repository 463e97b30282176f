/* conf.c - the configuration key table, INI reader and option parser. */
#include "conf.h"

#include "wormgear/wg_file.h"
#include "wormgear/wg_param.h"
#include "wormgear/wg_sim.h"
#include "wormgear/wg_status.h"

#include <ctype.h>
#include <getopt.h>
#include <ini.h>
#include <math.h>
#include <stdlib.h>
#include <string.h>

enum { K_STR, K_INT, K_DBL, K_BOOL, K_ENUM, K_STEPPER };

static const char *const mode_names[] = {"realtime", "fast", "lockstep", NULL};
static const char *const policy_names[] = {"continue", "freeze", "stop", NULL};
static const char *const contacts_names[] = {"all", "mesh", "none", NULL};

typedef struct key {
    const char *name;
    unsigned flags;           /* CONF_RESTART: a reload keeps the running value */
    int apply;                /* CONF_APPLY_*: the hook a reload calls on a change */
    int type;
    size_t off, size;
    double min, max;
    const char *const *names; /* K_ENUM values, index = stored int */
    const char *def;
    const char *help;
} key;

/* How each key takes a new value: at once, at the next restart, or at once
 * through an apply hook. */
#define LIVE 0, CONF_APPLY_NONE
#define RESTART CONF_RESTART, CONF_APPLY_NONE
#define APPLY(slot) 0, slot
#define S(f) offsetof(conf, f), sizeof(((conf *)0)->f)
static const key keys[] = {
    {"scene", RESTART, K_STR, S(scene), 0, 0, NULL, "table3", "scene name or INI file"},
    {"url", RESTART, K_STR, S(url), 0, 0, NULL, "udpm://239.255.76.67:7667?ttl=0",
     "LCM URL ($WORMGEAR_URL; ttl=0: this host only, ttl=1: the LAN)"},
    {"prefix", RESTART, K_STR, S(prefix), 0, 0, NULL, "WORMGEAR_",
     "channel prefix ($WORMGEAR_PREFIX), [A-Za-z0-9_.-]{0,40}, one per rig"},
    {"mode", APPLY(CONF_APPLY_MODE), K_ENUM, S(mode), 0, 0, mode_names, "realtime",
     "pacing: realtime, fast, lockstep"},
    {"rate", LIVE, K_DBL, S(rate), WG_RATE_MIN, WG_RATE_MAX, NULL, "1",
     "realtime rate factor, 1 = physical real time (omega_n of the scene)"},
    {"steps_per_period", RESTART, K_INT, S(steps_per_period), WG_STEPS_MIN, WG_STEPS_MAX, NULL,
     "128", "RK4 steps per mesh period N"},
    {"stepper", RESTART, K_STEPPER, S(stepper), 0, 0, NULL, "default",
     "rk4, or rk4-event (split at dead-zone crossings); the model's own: rk4-event, the "
     "printed model rk4"},
    {"scope_hz", LIVE, K_DBL, S(scope_hz), 0, 100, NULL, "50",
     "SCOPE samples (scalars, for lcm-spy) per wall second, 0 = none"},
    {"contacts", APPLY(CONF_APPLY_CONTACTS), K_ENUM, S(contacts), 0, 0, contacts_names, "all",
     "CONTACT events published: all (bearings thinned by bearing_every), mesh (the mesh's "
     "only), none"},
    {"bearing_every", APPLY(CONF_APPLY_CONTACTS), K_INT, S(bearing_every), 1, 1000000000, NULL,
     "1", "contacts = all: publish every Nth event of each bearing (1: every one)"},
    {"state_rate_hz", LIVE, K_DBL, S(state_rate_hz), 0, 100000, NULL, "2000",
     "STATE samples per wall second, 0 = no STATE"},
    {"state_decimation", LIVE, K_INT, S(state_decimation), 0, 1000000000, NULL, "0",
     "fixed steps per STATE sample; 0 = derive from state_rate_hz"},
    {"tick_us", APPLY(CONF_APPLY_TICK), K_INT, S(tick_us), 100, 100000, NULL, "1000",
     "pacing tick, microseconds"},
    {"catchup_ticks", LIVE, K_DBL, S(catchup_ticks), 1, 1000, NULL, "10",
     "catch-up cap: at most this many ticks' worth of steps per tick"},
    {"overrun_policy", LIVE, K_ENUM, S(overrun_policy), 0, 0, policy_names, "continue",
     "on overrun: continue (catch up), freeze (drop the backlog), stop (pause after N)"},
    {"overrun_stop_after", LIVE, K_INT, S(overrun_stop_after), 1, 1000000000, NULL, "1000",
     "consecutive overruns before policy stop pauses the run"},
    {"startup_grace_s", LIVE, K_DBL, S(startup_grace_s), 0, 3600, NULL, "2",
     "overruns ignored by the policy this long after start/resume, seconds"},
    {"lag_warn_ms", LIVE, K_DBL, S(lag_warn_ms), 0.1, 1e6, NULL, "50",
     "health = lagging when behind the pace target by more, milliseconds"},
    {"status_hz", LIVE, K_DBL, S(status_hz), 1, 10, NULL, "2", "STATUS heartbeat rate, Hz"},
    {"state_dir", LIVE, K_STR, S(state_dir), 0, 0, NULL, NULL,
     "directory of save/restore files ($STATE_DIRECTORY, else /var/lib/wormgeard)"},
    {"command_key_file", APPLY(CONF_APPLY_KEY), K_STR, S(command_key_file), 0, 0, NULL, NULL,
     "signed commands only, with this key (64 hex digits; `wgctl keygen FILE`; a relative "
     "name is in $CREDENTIALS_DIRECTORY); empty: unsigned commands accepted"},
    {"accept_commands", LIVE, K_BOOL, S(accept_commands), 0, 1, NULL, "yes",
     "no: refuse every command but get (monitor-only rig)"},
    {"start_paused", LIVE, K_BOOL, S(start_paused), 0, 1, NULL, "no", "start paused"},
    {"mlock", RESTART, K_BOOL, S(mlock), 0, 1, NULL, "no",
     "mlockall(MCL_CURRENT|MCL_FUTURE) at start"},
    {"rt_priority", RESTART, K_INT, S(rt_priority), 0, 99, NULL, "0",
     "SCHED_FIFO priority of every daemon thread, for a rig whose host is busy (needs "
     "CAP_SYS_NICE or an RLIMIT_RTPRIO; a refusal is a warning); 0 = the normal scheduler"},
    {"foreground", LIVE, K_BOOL, S(foreground), 0, 1, NULL, "no",
     "print a one-line status on stdout each second (-F)"},
    {"verbose", APPLY(CONF_APPLY_VERBOSE), K_BOOL, S(verbose), 0, 1, NULL, "no",
     "debug logging (-v)"},
    {"log_prefix", APPLY(CONF_APPLY_VERBOSE), K_BOOL, S(log_prefix), 0, 1, NULL, "no",
     "start each log line with its syslog priority, <3> ... <7> (always under journald, "
     "where $JOURNAL_STREAM is set)"},
};
#undef S
#undef LIVE
#undef RESTART
#undef APPLY
enum { NKEYS = sizeof keys / sizeof keys[0] };

const char *conf_mode_name(int m) { return m >= 0 && m < 3 ? mode_names[m] : "?"; }
const char *conf_policy_name(int p) { return p >= 0 && p < 3 ? policy_names[p] : "?"; }

static int enum_lookup(const char *const *names, const char *v)
{
    for (int i = 0; names[i]; i++)
        if (strcmp(names[i], v) == 0)
            return i;
    return -1;
}

int conf_mode_lookup(const char *name) { return enum_lookup(mode_names, name); }
int conf_contacts_lookup(const char *name) { return enum_lookup(contacts_names, name); }
const char *conf_contacts_name(int c) { return c >= 0 && c < 3 ? contacts_names[c] : "?"; }

static const key *key_find(const char *name)
{
    for (int i = 0; i < NKEYS; i++)
        if (strcmp(keys[i].name, name) == 0)
            return &keys[i];
    return NULL;
}

static void enum_list(const char *const *names, char *buf, size_t len)
{
    buf[0] = 0;
    for (int i = 0; names[i]; i++)
        snprintf(buf + strlen(buf), len - strlen(buf), "%s%s", i ? ", " : "", names[i]);
}

/* The library's stepper names, for messages and --help. */
static void stepper_list(char *buf, size_t len)
{
    buf[0] = 0;
    for (int i = WG_STEPPER_DEFAULT; i <= WG_STEPPER_RK4_EVENT; i++)
        snprintf(buf + strlen(buf), len - strlen(buf), "%s%s", i > WG_STEPPER_DEFAULT ? ", " : "",
                 wg_stepper_name(i));
}

static int parse_bool(const char *v)
{
    static const char *const t[] = {"yes", "true", "on", "1"}, *const f[] = {"no", "false",
                                                                         "off", "0"};
    for (int i = 0; i < 4; i++) {
        if (strcasecmp(v, t[i]) == 0)
            return 1;
        if (strcasecmp(v, f[i]) == 0)
            return 0;
    }
    return -1;
}

static int valid_prefix(const char *v)
{
    if (strlen(v) > 40)
        return 0;
    for (const char *p = v; *p; p++)
        if (!isalnum((unsigned char)*p) && !strchr("_.-", *p))
            return 0;
    return 1;
}

/* x against k's range (and integer for K_INT); text is x as the user
 * wrote it, for the message. 0, or 2 with why. */
static int check_number(const key *k, double x, const char *text, char *why, size_t len)
{
    int isint = k->type == K_INT;
    if (!isfinite(x) || x < k->min || x > k->max || (isint && x != floor(x))) {
        snprintf(why, len, "%s: '%s' must be %s in [%g, %g]", k->name, text,
                 isint ? "an integer" : "a number", k->min, k->max);
        return 2;
    }
    return 0;
}

static int set_number(const key *k, void *dst, const char *v, char *why, size_t len)
{
    char *end;
    double x = strtod(v, &end);
    if (check_number(k, end == v || *end ? NAN : x, v, why, len)) /* not all a number */
        return 2;
    if (k->type == K_INT)
        *(int *)dst = (int)x;
    else
        *(double *)dst = x;
    return 0;
}

static int set_string(const key *k, char *dst, const char *v, char *why, size_t len)
{
    if (!*v && strcmp(k->name, "prefix") != 0 && strcmp(k->name, "command_key_file") != 0) {
        snprintf(why, len, "%s: must not be empty", k->name);
        return 2;
    }
    if (strlen(v) >= k->size) {
        snprintf(why, len, "%s: longer than %zu characters", k->name, k->size - 1);
        return 2;
    }
    if (strcmp(k->name, "prefix") == 0 && !valid_prefix(v)) {
        snprintf(why, len, "prefix: '%s' must match [A-Za-z0-9_.-]{0,40}", v);
        return 2;
    }
    snprintf(dst, k->size, "%s", v);
    return 0;
}

static int set_key(conf *c, const key *k, const char *v, char *why, size_t len)
{
    void *dst = (char *)c + k->off;
    char list[128];
    int i;
    switch (k->type) {
    case K_STR: return set_string(k, dst, v, why, len);
    case K_INT:
    case K_DBL: return set_number(k, dst, v, why, len);
    case K_BOOL:
        if ((i = parse_bool(v)) < 0) {
            snprintf(why, len, "%s: '%s' must be yes or no", k->name, v);
            return 2;
        }
        *(int *)dst = i;
        return 0;
    case K_STEPPER:
        if ((i = wg_stepper_lookup(v)) < WG_STEPPER_DEFAULT) {
            stepper_list(list, sizeof list);
            snprintf(why, len, "%s: '%s' is not one of %s", k->name, v, list);
            return 2;
        }
        *(int *)dst = i;
        return 0;
    default:
        if ((i = enum_lookup(k->names, v)) < 0) {
            enum_list(k->names, list, sizeof list);
            snprintf(why, len, "%s: '%s' is not one of %s", k->name, v, list);
            return 2;
        }
        *(int *)dst = i;
        return 0;
    }
}

int conf_set(conf *c, const char *name, const char *value, char *why, size_t whylen)
{
    const key *k = key_find(name);
    if (!k) {
        snprintf(why, whylen, "unknown key '%s' (see wormgeard --help)", name);
        return 2;
    }
    return set_key(c, k, value, why, whylen);
}

int conf_check_number(const char *name, double x, char *why, size_t whylen)
{
    char text[40];
    const key *k = key_find(name);
    if (!k || (k->type != K_INT && k->type != K_DBL)) {
        snprintf(why, whylen, "unknown numeric key '%s' (see wormgeard --help)", name);
        return 2;
    }
    wg_num_format(x, text, sizeof text); /* for the message only */
    return check_number(k, x, text, why, whylen);
}

void conf_defaults(conf *c)
{
    char why[256];
    memset(c, 0, sizeof *c);
    for (int i = 0; i < NKEYS; i++)
        if (keys[i].def)
            set_key(c, &keys[i], keys[i].def, why, sizeof why);
    const char *sd = getenv("STATE_DIRECTORY"); /* systemd StateDirectory= */
    snprintf(c->state_dir, sizeof c->state_dir, "%s", sd && *sd ? sd : "/var/lib/wormgeard");
    char *colon = strchr(c->state_dir, ':'); /* several directories: the first */
    if (colon)
        *colon = 0;
}

/* A scene parameter override ("name=value"), checked against the table. */
static int add_set(conf *c, const char *name, const char *value, char *why, size_t len)
{
    int id = wg_param_lookup(name);
    double v;
    if (id < 0) {
        snprintf(why, len, "unknown parameter '%s' (wormgeard --help lists them)", name);
        return 2;
    }
    if (wg_param_parse(id, value, &v, why, len))
        return 2;
    /* one entry a parameter: a --set replaces the file's [params] value (the two
     * shared a cap of 32 entries, so a file setting every parameter was refused) */
    size_t nl = strlen(name);
    int at = 0;
    while (at < c->nsets && !(strncmp(c->sets[at], name, nl) == 0 && c->sets[at][nl] == '='))
        at++;
    if (at == CONF_MAX_SETS) {
        snprintf(why, len, "more than %d parameter overrides", CONF_MAX_SETS);
        return 2;
    }
    char num[32]; /* the value as read, in its shortest exact text: a long spelling of it
                   * (160 digits of 0.1) was cut at 127 characters to another value */
    snprintf(c->sets[at], sizeof c->sets[0], "%s=%s", name, wg_num_format(v, num, sizeof num));
    c->nsets += at == c->nsets;
    return 0;
}

/* ---- INI file ------------------------------------------------------------ */

typedef struct reader_ctx {
    const char *p, *end;      /* the text not yet handed to the parser */
    conf *c;
    int line, err;
    int indented, has_key;    /* this line continues the previous value (inih multi-line) */
    int key_line[NKEYS];      /* where each [wormgeard] key was set (0: not yet) */
    int param_line[WG_NPARAM]; /* the same for [params] */
    char msg[400];
} reader_ctx;

/* Note an error at the current line (the first one only). */
static void reader_error(reader_ctx *r, const char *why)
{
    if (!r->err) {
        r->err = r->line;
        snprintf(r->msg, sizeof r->msg, "%s", why);
    }
}

/* Is this line one that inih would take as the continuation of the value
 * above it: indented, not blank or a comment, after a key = value line of
 * the same section (its rule, repeated here from the text). */
static void classify(reader_ctx *r, const char *s, size_t n)
{
    size_t i = 0;
    while (i < n && isspace((unsigned char)s[i]))
        i++;
    int blank = i == n || s[i] == ';' || s[i] == '#';
    r->indented = !blank && i > 0 && r->has_key;
    if (!blank && s[i] == '[' && !r->indented)
        r->has_key = 0;
    else if (!blank)
        r->has_key = 1;
}

/* inih's reader: one line of the text per call, so its line numbers are
 * the file's. A line that does not fit inih's buffer (num bytes with the
 * newline and NUL) ends the parse with an error at its own line. */
static char *read_line(char *str, int num, void *stream)
{
    reader_ctx *r = stream;
    if (r->err || r->p >= r->end)
        return NULL;
    const char *nl = memchr(r->p, '\n', (size_t)(r->end - r->p));
    size_t n = nl ? (size_t)(nl - r->p) + 1 : (size_t)(r->end - r->p);
    size_t chars = n - (nl != NULL);
    r->line++;
    if (num < 2 || chars > (size_t)num - 2) { /* one limit, with or without a newline */
        char why[160];
        snprintf(why, sizeof why, "line too long: %zu characters, the limit is %d", chars,
                 num - 2);
        reader_error(r, why);
        return NULL;
    }
    memcpy(str, r->p, n);
    str[n] = 0;
    classify(r, r->p, n);
    r->p += n;
    return str;
}

/* The line a key was first set at, in *first; 0 when this is the first. */
static int seen_before(reader_ctx *r, const char *section, const char *name, int *first)
{
    int *slot = NULL;
    if (strcmp(section, "params") == 0) {
        int id = wg_param_lookup(name);
        slot = id >= 0 ? &r->param_line[id] : NULL;
    } else {
        const key *k = key_find(name);
        slot = k ? &r->key_line[k - keys] : NULL;
    }
    if (!slot)
        return 0; /* unknown: refused by the setter, with its own message */
    *first = *slot;
    if (!*slot)
        *slot = r->line;
    return *first != 0;
}

/* A key set twice, or a value continued on an indented line: which value
 * was meant is not clear, so neither is taken. 0, or 2 with why. */
static int once(reader_ctx *r, const char *section, const char *name, char *why, size_t len)
{
    int first = 0;
    if (r->indented) {
        snprintf(why, len, "an indented line continues the value of %s (multi-line values "
                 "are not allowed): remove the indentation", name);
        return 2;
    }
    if (!seen_before(r, section, name, &first))
        return 0;
    snprintf(why, len, "%s: set again (first set at line %d); each key may be set once per "
             "file", name, first);
    return 2;
}

static int on_ini(void *user, const char *section, const char *name, const char *value)
{
    reader_ctx *r = user;
    char why[400];
    int rc;
    if (r->err)
        return 1;
    if (strcmp(section, "params") && *section && strcmp(section, "wormgeard")) {
        snprintf(why, sizeof why, "unknown section [%s] (allowed: [wormgeard], [params])",
                 section);
        rc = 2;
    } else if (strstr(value, " #") || strstr(value, "\t#")) {
        /* inih ends a value at " ;" only: the rest was the value ("state_dir =
         * /x # saves" made the directory "/x # saves") */
        snprintf(why, sizeof why, "%s: '%s': " WG_INI_HASH_HINT " (a value in a file may not "
                 "hold ' #')", name, value);
        rc = 2;
    } else if (!(rc = once(r, section, name, why, sizeof why))) {
        rc = strcmp(section, "params") == 0 ? add_set(r->c, name, value, why, sizeof why)
                                            : conf_set(r->c, name, value, why, sizeof why);
    }
    if (rc)
        reader_error(r, why);
    return 1;
}

/* A NUL byte in the text: inih would end the line there and drop the rest
 * silently. Its line (1-based) and column, or 0. */
static int nul_at(const char *text, size_t n, int *col)
{
    const char *z = memchr(text, 0, n);
    if (!z)
        return 0;
    int line = 1;
    const char *bol = text;
    for (const char *q = text; q < z; q++)
        if (*q == '\n')
            line++, bol = q + 1;
    *col = (int)(z - bol) + 1;
    return line;
}

static int parse_text(conf *c, const char *path, const char *text, size_t n, char *why,
                      size_t whylen)
{
    int col = 0, nul = nul_at(text, n, &col);
    if (nul) {
        snprintf(why, whylen, "%s:%d: a NUL byte (column %d): a config file is text", path,
                 nul, col);
        return 2;
    }
    reader_ctx r = {.p = text, .end = text + n, .c = c};
    int line = ini_parse_stream(read_line, &r, on_ini, &r);
    if (r.err) {
        snprintf(why, whylen, "%s:%d: %s", path, r.err, r.msg);
        return 2;
    }
    if (line) {
        snprintf(why, whylen, "%s:%d: syntax error (expected [section] or key = value)", path,
                 line);
        return 2;
    }
    return 0;
}

int conf_read_file(conf *c, const char *path, char *why, size_t whylen)
{
    char *text = malloc(CONF_FILE_MAX + 1);
    if (!text) {
        snprintf(why, whylen, "%s: out of memory to read it", path);
        return 2;
    }
    /* a regular file within the limit; a link is followed (config files
     * often are links), a FIFO or device never opened */
    long n = wg_file_read(path, "config file", 0, text, CONF_FILE_MAX, why, whylen);
    int rc = n < 0 ? 2 : parse_text(c, path, text, (size_t)n, why, whylen);
    free(text);
    if (rc) /* it quotes the file's text: no control byte reaches a terminal or the log */
        wg_text_clean(why);
    if (!rc)
        snprintf(c->path, sizeof c->path, "%s", path);
    return rc;
}

/* ---- command line -------------------------------------------------------- */

enum { OPT_CONFIG = 'c', OPT_HELP = 'h', OPT_FG = 'F', OPT_VERBOSE = 'v', OPT_SET = 1000,
       OPT_CHECK, OPT_KEY0 = 2000 };

typedef struct optset {
    struct option o[NKEYS + 8];
    char names[NKEYS][40];
} optset;

/* Key k's command-line name: its name with '-' for '_' ("steps-per-period"). */
static const char *opt_name(const key *k, char *buf, size_t len)
{
    snprintf(buf, len, "%s", k->name);
    for (char *p = buf; *p; p++)
        *p = *p == '_' ? '-' : *p;
    return buf;
}

static void build_options(optset *s)
{
    int n = 0;
    for (int i = 0; i < NKEYS; i++) {
        opt_name(&keys[i], s->names[i], sizeof s->names[i]);
        s->o[n++] = (struct option){s->names[i],
                                    keys[i].type == K_BOOL ? optional_argument : required_argument,
                                    0, OPT_KEY0 + i};
    }
    s->o[n++] = (struct option){"config", required_argument, 0, OPT_CONFIG};
    s->o[n++] = (struct option){"set", required_argument, 0, OPT_SET};
    s->o[n++] = (struct option){"check-config", no_argument, 0, OPT_CHECK};
    s->o[n++] = (struct option){"help", no_argument, 0, OPT_HELP};
    s->o[n] = (struct option){0, 0, 0, 0};
}

static int apply_set_option(conf *c, const char *arg, char *why, size_t len)
{
    char name[64];
    const char *eq = strchr(arg, '=');
    if (!eq || eq == arg || (size_t)(eq - arg) >= sizeof name) {
        snprintf(why, len, "--set '%s': expected name=value", arg);
        return 2;
    }
    snprintf(name, sizeof name, "%.*s", (int)(eq - arg), arg);
    return add_set(c, name, eq + 1, why, len);
}

/* One option of the second pass. */
static int apply_option(conf *c, int opt, const char *arg, char *why, size_t len)
{
    switch (opt) {
    case OPT_FG: c->foreground = 1; return 0;
    case OPT_VERBOSE: c->verbose = 1; return 0;
    case OPT_CHECK: c->check_only = 1; return 0;
    case OPT_SET: return apply_set_option(c, arg, why, len);
    case OPT_CONFIG:
    case OPT_HELP: return 0;
    default:
        if (opt >= OPT_KEY0 && opt < OPT_KEY0 + NKEYS)
            return set_key(c, &keys[opt - OPT_KEY0], arg ? arg : "yes", why, len);
        return 2;
    }
}

/* An option's key, or --set's parameter, given once on the command line
 * (it overrides the file's): the second of "--rate 1 --rate 3" or "--set
 * omega=1.2 --set omega=1.3" was taken silently. 0, or 2 with why. */
static int given_once(int opt, const char *arg, char *seen, char sets[][64], int *nsets, char *why,
                size_t len)
{
    if (opt >= OPT_KEY0 && opt < OPT_KEY0 + NKEYS) {
        if (seen[opt - OPT_KEY0]++) {
            char o[40];
            snprintf(why, len, "--%s given twice (each option once)",
                     opt_name(&keys[opt - OPT_KEY0], o, sizeof o));
            return 2;
        }
        return 0;
    }
    if (opt != OPT_SET || !arg || !strchr(arg, '='))
        return 0; /* a --set without '=' is refused by its own check */
    int n = (int)(strchr(arg, '=') - arg);
    for (int i = 0; i < *nsets; i++)
        if ((int)strlen(sets[i]) == n && !strncmp(sets[i], arg, (size_t)n)) {
            snprintf(why, len, "--set %.*s given twice (each parameter once)", n, arg);
            return 2;
        }
    if (*nsets < CONF_MAX_SETS && n < 64)
        snprintf(sets[(*nsets)++], 64, "%.*s", n, arg);
    return 0;
}

/* Walk the options; pass 0 only finds --config and --help. */
static int walk(conf *c, int argc, char **argv, int pass, const char **cfg, char *why,
                size_t len)
{
    optset s;
    build_options(&s);
    int opt, help = 0, nsets = 0, configs = 0;
    char seen[NKEYS] = {0}, sets[CONF_MAX_SETS][64]; /* given once each, as in a file */
    optind = 0; /* GNU: full re-initialisation (conf_load may run again) */
    opterr = 0;
    while ((opt = getopt_long(argc, argv, ":c:hFv", s.o, NULL)) != -1) {
        if (opt == '?' || opt == ':') {
            const char *bad = argv[optind - 1];
            snprintf(why, len, opt == ':' ? "option '%s' needs a value"
                                          : "unknown option '%s'",
                     bad);
            return 2;
        }
        /* a boolean takes its value as "--key=no" or as the next word,
         * "--key no"; bare "--key" means yes. The next word is its value
         * whenever it is not an option (wormgeard takes no other words):
         * "--accept-commands maybe" is refused as the value it is, not as
         * "unexpected argument 'maybe'" */
        if (opt >= OPT_KEY0 && opt < OPT_KEY0 + NKEYS && keys[opt - OPT_KEY0].type == K_BOOL &&
            !optarg && optind < argc && argv[optind][0] != '-')
            optarg = argv[optind++];
        if (pass == 0) {
            help |= opt == OPT_HELP;
            if (opt == OPT_CONFIG && configs++) {
                snprintf(why, len, "-c/--config given twice (one config file)");
                return 2;
            }
            if (opt == OPT_CONFIG)
                *cfg = optarg;
            continue;
        }
        if (given_once(opt, optarg, seen, sets, &nsets, why, len) ||
            apply_option(c, opt, optarg, why, len))
            return 2;
    }
    if (optind < argc) {
        snprintf(why, len, "unexpected argument '%s'", argv[optind]);
        return 2;
    }
    return help;
}

/* $WORMGEAR_URL and $WORMGEAR_PREFIX, as the clients take them (above the
 * defaults, below the file and the options); one the key would refuse is
 * refused, never dropped for the default: 2 with why naming the variable. */
static int conf_env(conf *c, char *why, size_t whylen)
{
    static const char *const var[][2] = {{"WORMGEAR_URL", "url"}, {"WORMGEAR_PREFIX", "prefix"}};
    for (int i = 0; i < 2; i++) {
        const char *v = getenv(var[i][0]);
        char kwhy[256];
        if (!v || (!*v && i == 0)) /* an empty URL: unset, as the clients read it */
            continue;
        if (set_key(c, key_find(var[i][1]), v, kwhy, sizeof kwhy)) {
            snprintf(why, whylen, "environment: $%s: %s (fix or unset it)", var[i][0], kwhy);
            return 2;
        }
    }
    return 0;
}

int conf_load(conf *c, int argc, char **argv, char *why, size_t whylen)
{
    const char *cfg = NULL;
    conf_defaults(c);
    int rc = conf_env(c, why, whylen);
    if (rc)
        return rc;
    rc = walk(c, argc, argv, 0, &cfg, why, whylen);
    if (rc == 1) {
        conf_usage(stdout);
        return 1;
    }
    if (rc)
        return rc;
    if (cfg && (rc = conf_read_file(c, cfg, why, whylen)))
        return rc;
    return walk(c, argc, argv, 1, &cfg, why, whylen);
}

/* ---- reload --------------------------------------------------------------- */

static int key_differs(const key *k, const conf *a, const conf *b)
{
    const char *x = (const char *)a + k->off, *y = (const char *)b + k->off;
    return k->type == K_STR ? strcmp(x, y) != 0 : memcmp(x, y, k->size) != 0;
}

static int sets_differ(const conf *a, const conf *b)
{
    int differ = a->nsets != b->nsets;
    for (int i = 0; i < a->nsets && !differ; i++)
        differ = strcmp(a->sets[i], b->sets[i]) != 0;
    return differ;
}

/* "a", "a and b", "a, b and c". */
static void join(const char *const *names, int n, char *buf, size_t len)
{
    buf[0] = 0;
    for (int i = 0; i < n; i++)
        snprintf(buf + strlen(buf), len - strlen(buf), "%s%s",
                 i == 0 ? "" : i == n - 1 ? " and " : ", ", names[i]);
}

void conf_reload(conf *run, conf *loaded, const conf *next, const conf_apply_fn *hooks,
                 void *ctx, char *kept, size_t keptlen, char *held, size_t heldlen)
{
    const char *names[NKEYS + 1], *mine[NKEYS];
    int n = 0, m = 0;
    conf was = *run;
    for (int i = 0; i < NKEYS; i++) {
        const key *k = &keys[i];
        if (!key_differs(k, loaded, next)) {
            if (key_differs(k, &was, loaded)) /* a command's value: the file did not move */
                mine[m++] = k->name;
            continue;
        }
        if (k->flags & CONF_RESTART) {
            names[n++] = k->name;
            continue;
        }
        memcpy((char *)run + k->off, (const char *)next + k->off, k->size);
        if (k->apply != CONF_APPLY_NONE && hooks[k->apply])
            hooks[k->apply](ctx, &was);
    }
    if (sets_differ(loaded, next))
        names[n++] = "[params]";
    snprintf(run->path, sizeof run->path, "%s", next->path);
    join(names, n, kept, keptlen);
    join(mine, m, held, heldlen);
    *loaded = *next;
}

static void key_range(const key *k, char *buf, size_t len)
{
    switch (k->type) {
    case K_INT:
    case K_DBL: snprintf(buf, len, "[%g, %g]", k->min, k->max); break;
    case K_BOOL: snprintf(buf, len, "yes|no"); break;
    case K_ENUM: enum_list(k->names, buf, len); break;
    case K_STEPPER: stepper_list(buf, len); break;
    default: buf[0] = 0;
    }
}

/* A key's default as the help shows it: the stepper's "default" would read
 * "default default", so it says what that value means. */
static const char *key_default(const key *k)
{
    if (!k->def)
        return "(see text)";
    return k->type == K_STEPPER && !strcmp(k->def, "default") ? "\"default\" (the model's own)"
                                                              : k->def;
}

void conf_usage(FILE *f)
{
    fprintf(f, "usage: wormgeard [options]\n"
               "Real-time simulation daemon of the worm gear drive, controlled over LCM.\n\n"
               "  -c, --config FILE     INI config file ([wormgeard] keys below, [params] overrides)\n"
               "      --set name=value  override a scene parameter (repeatable; list below)\n"
               "  -F                    same as --foreground\n"
               "  -v                    same as --verbose\n"
               "      --check-config    load and validate the configuration and the scene, exit;\n"
               "                        nothing is sent or written (a udpm URL is opened, not\n"
               "                        subscribed; file:// and tcpq:// ones are not opened)\n"
               "  -h, --help            this text\n\n"
               "Config keys (file: key = value; command line: --key value):\n");
    for (int i = 0; i < NKEYS; i++) {
        char range[96], opt[40];
        opt_name(&keys[i], opt, sizeof opt);
        key_range(&keys[i], range, sizeof range);
        fprintf(f, "  --%-20s %s\n  %-22s   default %s%s%s\n", opt, keys[i].help, "",
                key_default(&keys[i]), *range ? "; " : "", range);
    }
    fprintf(f, "\nScene parameters for --set and [params] (name unit [min, max] default):\n");
    for (int i = 0; i < WG_NPARAM; i++) {
        const wg_param_info *r = wg_param_info_get(i);
        char shown[48];
        fprintf(f, "  %-5s %-3s %s %g%s: %s\n", r->name, wg_unit_shown(r->unit),
                wg_range_shown(r->min, r->max, shown, sizeof shown), r->def,
                r->flags & WG_PF_RAMP ? " (rampable)" : "", r->help);
    }
    fprintf(f, "\nExit status: 0 clean stop (SIGTERM/SIGINT), 1 runtime failure, 2 usage or "
               "config error.\nProtocol: lcmtypes/PROTOCOL.md; control with wgctl.\n");
}

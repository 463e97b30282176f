/* cli.c - usage errors, numbers from text and clocks for the clients (see
 * cli.h). */
#include "cli.h"

#include "wormgear/wg_param.h"

#include <ctype.h>
#include <errno.h>
#include <math.h>
#include <signal.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

int cli_usage_error(const char *prog, const char *fmt, ...)
{
    va_list ap;
    fprintf(stderr, "%s: ", prog);
    va_start(ap, fmt);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fprintf(stderr, "\n(try %s --help)\n", prog);
    return CLI_EUSAGE;
}

int cli_getopt(const char *prog, int argc, char **argv, const char *shortopts,
               const struct option *longopts, int (*one)(void *ctx, int c, const char *arg),
               void *ctx)
{
    int c, rc;
    opterr = 0;
    while ((c = getopt_long(argc, argv, shortopts, longopts, NULL)) != -1)
        if ((rc = c == '?' ? -1 : one(ctx, c, optarg)))
            return rc > 0 ? rc : cli_getopt_error(prog, argv, shortopts, longopts);
    return 0;
}

/* The row of longopts that the word w ("--name" or "--name=value") names:
 * its exact name, or the one name it begins; NULL with *n the names it
 * begins (0: none, 2 or more: ambiguous). */
static const struct option *long_row(const char *w, const struct option *longopts, int *n)
{
    size_t len = strcspn(w + 2, "=");
    const struct option *hit = NULL;
    *n = 0;
    for (const struct option *o = longopts; o->name; o++) {
        if (strncmp(o->name, w + 2, len) != 0)
            continue;
        if (strlen(o->name) == len) {
            *n = 1;
            return o;
        }
        hit = o, (*n)++;
    }
    return *n == 1 ? hit : NULL;
}

/* "option '--s' is ambiguous: --scene, --set, ..." (what w begins). */
static int long_ambiguous(const char *prog, const char *w, size_t len,
                          const struct option *longopts)
{
    char names[512] = "";
    size_t k = 0;
    for (const struct option *o = longopts; o->name && k < sizeof names; o++)
        if (strncmp(o->name, w + 2, len - 2) == 0)
            k += (size_t)snprintf(names + k, sizeof names - k, "%s--%s", k ? ", " : "", o->name);
    return cli_usage_error(prog, "option '%.*s' is ambiguous: %s (give more of the name)",
                           (int)len, w, names);
}

/* The usage error of the long option word w, or -1 when w itself is
 * well formed (a short option after it was refused). */
static int long_error(const char *prog, const char *w, const struct option *longopts)
{
    int n;
    size_t len = strcspn(w, "=");
    const struct option *o = long_row(w, longopts, &n);
    if (!o && n > 1)
        return long_ambiguous(prog, w, len, longopts);
    if (!o)
        return cli_usage_error(prog, "unknown option '%.*s'", (int)len, w);
    if (o->has_arg == no_argument && w[len])
        return cli_usage_error(prog, "option --%s takes no value, got '%s'", o->name, w);
    if (o->has_arg == required_argument && !w[len])
        return cli_usage_error(prog, "option --%s needs a value", o->name);
    return -1;
}

int cli_getopt_error(const char *prog, char **argv, const char *shortopts,
                     const struct option *longopts)
{
    const char *w = optind > 0 ? argv[optind - 1] : "", *s;
    int rc;
    if (strncmp(w, "--", 2) == 0 && w[2] && (rc = long_error(prog, w, longopts)) >= 0)
        return rc;
    if (!optopt) /* not a short option: getopt_long refused w */
        return cli_usage_error(prog, "unknown option '%s'", w);
    if ((s = strchr(shortopts, optopt)) && s[1] == ':')
        return cli_usage_error(prog, "option -%c needs a value", optopt);
    return cli_usage_error(prog, "unknown option '-%c'", optopt);
}

int cli_opt_outdir(const char *prog, const char *opt, const char *prefix)
{
    char dir[4096];
    const char *slash = strrchr(prefix, '/'), *base = slash ? slash + 1 : prefix;
    size_t n = slash ? (size_t)(slash - prefix) : 0;
    /* PREFIX names files: "runs/" or "" gave runs/.csv, hidden; "-" gave
     * "--poincare.csv"; a name past NAME_MAX less the suffixes failed
     * only when the run was done */
    if (!*base || !strcmp(base, "-") || !strcmp(base, ".") || !strcmp(base, ".."))
        return cli_usage_error(prog, "%s '%s': need a file name prefix (e.g. runs/a: "
                               "runs/a.csv, ...), not a directory or '-'", opt, prefix);
    if (strlen(base) > CLI_PREFIX_NAME_MAX)
        return cli_usage_error(prog, "%s: a file name prefix of at most %d characters (the "
                               "outputs add suffixes such as -bifurcations.csv), got %zu", opt,
                               CLI_PREFIX_NAME_MAX, strlen(base));
    if (!slash)
        snprintf(dir, sizeof dir, ".");
    else if (n == 0)
        snprintf(dir, sizeof dir, "/");
    else if (n < sizeof dir)
        snprintf(dir, sizeof dir, "%.*s", (int)n, prefix);
    else
        return cli_usage_error(prog, "%s: a path of at most %zu characters, got %zu", opt,
                               sizeof dir - 1, strlen(prefix));
    struct stat st;
    const char *why = NULL;
    if (stat(dir, &st) != 0)
        why = strerror(errno);
    else if (!S_ISDIR(st.st_mode))
        why = "not a directory";
    else if (access(dir, W_OK | X_OK) != 0)
        why = strerror(errno);
    if (!why)
        return 0;
    return cli_usage_error(prog, "%s '%s': cannot write in %s: %s (the directory must exist "
                           "and be writable)", opt, prefix, dir, why);
}

int cli_double(const char *s, double *v)
{
    char *end;
    *v = strtod(s, &end);
    return end == s || *end ? -1 : 0;
}

int cli_num(const char *s, double lo, double hi, double *v)
{
    return cli_double(s, v) || !isfinite(*v) || *v < lo || *v > hi ? -1 : 0;
}

int cli_int64(const char *s, int64_t lo, int64_t hi, int64_t *v)
{
    double d;
    if (cli_num(s, (double)lo, (double)hi, &d) || d != floor(d) || fabs(d) >= 0x1p63)
        return -1;
    *v = (int64_t)d;
    return 0;
}

int cli_int(const char *s, int lo, int hi, int *v)
{
    int64_t x;
    if (cli_int64(s, lo, hi, &x))
        return -1;
    *v = (int)x;
    return 0;
}

int cli_csv_num(const char *s, double *v)
{
    const char *p = s + (*s == '-');
    int word = !strcmp(p, "nan") || !strcmp(p, "inf");
    if (!word && (!(isdigit((unsigned char)*p) || *p == '.') || strpbrk(p, "xX")))
        return -1; /* strtod takes " 1", "+1", "0x1p0", "infinity": printf writes none */
    return cli_double(s, v);
}

int cli_csv_int(const char *s, int lo, int hi, int *v)
{
    const char *p = s + (*s == '-');
    size_t n = strlen(p);
    if (n == 0 || n > 10 || strspn(p, "0123456789") != n)
        return -1;
    long long x = strtoll(s, NULL, 10);
    if (x < lo || x > hi)
        return -1;
    *v = (int)x;
    return 0;
}

int cli_opt_num(const char *prog, const char *opt, const char *s, double lo, double hi,
                const char *allowed, double *v)
{
    if (cli_num(s, lo, hi, v))
        return cli_usage_error(prog, "%s '%s': %s", opt, s, allowed);
    return 0;
}

int cli_opt_int(const char *prog, const char *opt, const char *s, int lo, int hi,
                const char *allowed, int *v)
{
    if (cli_int(s, lo, hi, v))
        return cli_usage_error(prog, "%s '%s': %s", opt, s, allowed);
    return 0;
}

char *cli_join_args(int argc, char **argv)
{
    size_t len = 1;
    for (int i = 0; i < argc; i++)
        len += strlen(argv[i]) + 1;
    char *s = malloc(len);
    if (!s)
        return NULL;
    s[0] = 0;
    for (int i = 0; i < argc; i++) {
        strcat(s, argv[i]);
        if (i + 1 < argc)
            strcat(s, " ");
    }
    return s;
}

int cli_duration(const char *s, double *v, const char **unit)
{
    static const struct {
        const char *suffix;
        double factor;
        const char *unit;
    } u[] = {{"", 1, "s"},     {"s", 1, "s"},    {"ms", 1e-3, "s"}, {"us", 1e-6, "s"},
             {"min", 60, "s"}, {"h", 3600, "s"}, {"tau", 1, "tau"}};
    char *end;
    *v = strtod(s, &end);
    if (end == s || !isfinite(*v)) /* "infs" was a duration */
        return -1;
    for (unsigned i = 0; i < sizeof u / sizeof u[0]; i++)
        if (strcmp(end, u[i].suffix) == 0) {
            *v *= u[i].factor;
            *unit = u[i].unit;
            return 0;
        }
    return -1;
}

static struct timespec clock_now(clockid_t id)
{
    struct timespec ts;
    clock_gettime(id, &ts);
    return ts;
}

double cli_mono_s(void)
{
    struct timespec ts = clock_now(CLOCK_MONOTONIC);
    return (double)ts.tv_sec + 1e-9 * (double)ts.tv_nsec;
}

int64_t cli_mono_ns(void)
{
    struct timespec ts = clock_now(CLOCK_MONOTONIC);
    return (int64_t)ts.tv_sec * 1000000000 + ts.tv_nsec;
}

int64_t cli_wall_us(void)
{
    struct timespec ts = clock_now(CLOCK_REALTIME);
    return (int64_t)ts.tv_sec * 1000000 + ts.tv_nsec / 1000;
}

static void on_stop_signals(void (*fn)(int), int flags)
{
    struct sigaction sa;
    memset(&sa, 0, sizeof sa);
    sa.sa_handler = fn;
    sa.sa_flags = flags;
    sigemptyset(&sa.sa_mask);
    sigaction(SIGINT, &sa, NULL);
    sigaction(SIGTERM, &sa, NULL);
}

void cli_on_stop_signals(void (*fn)(int)) { on_stop_signals(fn, 0); }

void cli_on_stop_signals_restart(void (*fn)(int)) { on_stop_signals(fn, SA_RESTART); }

int cli_vary_param(const char *name)
{
    int id = wg_param_lookup(name);
    unsigned fl = id < 0 ? 0 : wg_param_info_get(id)->flags;
    return id < 0 ? -1 : (fl & WG_PF_BODY) ? -2 : (fl & WG_PF_TIED) ? -3 : id;
}

int cli_vary_param_error(const char *prog, const char *opt, const char *name, int code)
{
    if (code == -2)
        return cli_usage_error(prog, "%s '%s': body data, used only for the theta1, theta2 "
                               "outputs; it does not change the motion, so there is nothing "
                               "to vary (vary a parameter of the equations)", opt, name);
    if (code == -3)
        return cli_usage_error(prog, "%s '%s': a direction cosine of the line of action, tied "
                               "to the other two by a1^2 + a2^2 + a3^2 = 1, which varying it "
                               "alone breaks at every point; set a1, a2 and a3 together (--set "
                               "or the scene) and vary another parameter of the equations",
                               opt, name);
    return cli_usage_error(prog, "%s '%s': not a parameter (wgsim --help lists them)", opt, name);
}

int cli_utf8_len(const char *s)
{
    const unsigned char *p = (const unsigned char *)s;
    unsigned c = p[0];
    int n = c >= 0xC2 && c <= 0xDF ? 2 : c >= 0xE0 && c <= 0xEF ? 3 : c >= 0xF0 && c <= 0xF4 ? 4 : 0;
    unsigned lo = c == 0xE0 ? 0xA0 : c == 0xF0 ? 0x90 : 0x80;
    unsigned hi = c == 0xED ? 0x9F : c == 0xF4 ? 0x8F : 0xBF;
    for (int i = 1; i < n; i++, lo = 0x80, hi = 0xBF)
        if (p[i] < lo || p[i] > hi)
            return 0;
    return n;
}

char *cli_text(char *dst, size_t n, const char *s)
{
    size_t o = 0;
    if (n == 0)
        return dst;
    for (const char *p = s ? s : ""; *p;) {
        unsigned char c = (unsigned char)*p;
        int len = c < 0x80 ? 1 : cli_utf8_len(p);
        int ok = c < 0x80 ? c >= 0x20 && c != 0x7F
                          : len > 0 && !(c == 0xC2 && (unsigned char)p[1] < 0xA0);
        size_t w = ok ? (size_t)len : 1;
        if (o + w >= n)
            break;
        if (ok)
            memmove(dst + o, p, w); /* dst may be s: cleaned in place */
        else
            dst[o] = '?';
        o += w;
        p += len > 0 ? len : 1; /* a C1 control: one '?' for its two bytes */
    }
    dst[o] = 0;
    return dst;
}

void cli_json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (; s && *s; s++) {
        unsigned char ch = (unsigned char)*s;
        if (ch == '"' || ch == '\\')
            fprintf(f, "\\%c", ch);
        else if (ch < 0x20)
            fprintf(f, "\\u%04x", ch);
        else
            fputc(ch, f);
    }
    fputc('"', f);
}

int cli_read_line(FILE *fp, char *line, size_t len, const char *path, int lineno, char *why,
                  size_t whylen)
{
    size_t n = 0;
    int c = EOF, nul = 0;
    while (n + 1 < len && (c = getc(fp)) != EOF) {
        nul |= c == 0;
        line[n++] = (char)c;
        if (c == '\n')
            break;
    }
    line[n] = 0;
    if (n == 0 && c == EOF)
        return 0;
    if (nul)
        snprintf(why, whylen, "%s:%d: a NUL byte: not a text file", path, lineno);
    else if (c != '\n' && n + 1 == len)
        snprintf(why, whylen, "%s:%d: longer than %zu characters", path, lineno, len - 2);
    else if (c != '\n')
        snprintf(why, whylen, "%s:%d: the line is cut short (no end of line): a file still "
                 "being written, or truncated", path, lineno);
    else
        return 1;
    return -1;
}

int cli_stdout_close(const char *prog, int rc)
{
    errno = 0;
    int bad = fflush(stdout) != 0;
    int err = errno;
    bad |= ferror(stdout) != 0;
    if (!bad || rc) /* a failure already said (wgsim --poincare - said its own) */
        return rc;
    fprintf(stderr, "%s: writing the standard output failed: %s: it is incomplete\n", prog,
            err ? strerror(err) : "a write error");
    return 1;
}

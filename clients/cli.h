/* cli.h - what every client program needs and would otherwise write again:
 * the usage-error report, numbers from the command line, and the clocks.
 * No LCM and no cairo: wgsim and wglog link it as well as the LCM clients,
 * and tests and benchmarks take their clock from here.
 *
 * Numbers follow one rule: strtod, nothing may follow the number, and
 * (except cli_double) finite and inside [lo, hi]. Parsers return 0, or -1
 * with *v unspecified; the cli_opt_* forms also report the usage error. */
#ifndef WG_CLI_H
#define WG_CLI_H

#include <getopt.h>
#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

/* The exit code of a usage error, in every client. */
enum { CLI_EUSAGE = 2 };

/* Print "prog: <message>" and "(try prog --help)" on stderr. Returns
 * CLI_EUSAGE, so a parser can `return cli_usage_error(...)`. */
int cli_usage_error(const char *prog, const char *fmt, ...)
    __attribute__((format(printf, 2, 3)));

/* getopt_long over argv (its own messages off), one(ctx, c, optarg) for
 * each option; one returns 0, CLI_EUSAGE (reported) or -1 for an option
 * it does not know. Returns 0 with optind at the first operand, one's
 * CLI_EUSAGE, or cli_getopt_error's usage error. */
int cli_getopt(const char *prog, int argc, char **argv, const char *shortopts,
               const struct option *longopts, int (*one)(void *ctx, int c, const char *arg),
               void *ctx);

/* The usage error of the option getopt_long just refused ('?', opterr 0),
 * from argv[optind - 1] and optopt, naming the option as the user typed
 * it: "option --scene needs a value", "unknown option '--bogus'",
 * "option --quiet takes no value, got '--quiet=1'", "option '--s' is
 * ambiguous: --scene, --set", "option -o needs a value", "unknown option
 * '-x'". Returns CLI_EUSAGE. */
int cli_getopt_error(const char *prog, char **argv, const char *shortopts,
                     const struct option *longopts);

/* The whole of s as a number; infinities and NaN pass (for values that
 * the daemon judges and answers, not the client). */
int cli_double(const char *s, double *v);

/* The whole of s as a finite number in [lo, hi]. */
int cli_num(const char *s, double lo, double hi, double *v);

/* The whole of s as a whole number in [lo, hi] ("12", "12.0", "1.2e1"). */
int cli_int(const char *s, int lo, int hi, int *v);
int cli_int64(const char *s, int64_t lo, int64_t hi, int64_t *v);

/* A field of a CSV one of our tools wrote, as printf writes a number (%d,
 * %g, %e): an optional '-', then a digit or '.', or nan or inf; the whole
 * field, no hex, no space or '+' before it. *v may be NaN or infinite (the
 * caller says what its column holds). 0, or -1. */
int cli_csv_num(const char *s, double *v);

/* The same for %d: an optional '-' and digits only, in [lo, hi]. */
int cli_csv_int(const char *s, int lo, int hi, int *v);

/* Option opt's value s by cli_num / cli_int: 0, or CLI_EUSAGE after
 * reporting "prog: opt 's': allowed" (allowed names the range in words). */
int cli_opt_num(const char *prog, const char *opt, const char *s, double lo, double hi,
                const char *allowed, double *v);
int cli_opt_int(const char *prog, const char *opt, const char *s, int lo, int hi,
                const char *allowed, int *v);

/* The directory an output PREFIX writes into ("runs/a": "runs"; "a": the
 * current one): 0 if it is a directory this process may write in, else
 * CLI_EUSAGE after "prog: opt 'PREFIX': cannot write in DIR: reason (the
 * directory must exist and be writable)". PREFIX's last part must be a
 * file name prefix (not empty, '-', '.' or '..') of at most
 * CLI_PREFIX_NAME_MAX characters, leaving the suffixes room in NAME_MAX
 * (255). A sweep checks it before it runs, not after (a map takes a
 * minute). */
enum { CLI_PREFIX_NAME_MAX = 180 };
int cli_opt_outdir(const char *prog, const char *opt, const char *prefix);

/* argv[0] .. argv[argc - 1] joined by single spaces, the command line as
 * a run records it (malloc'ed: free it), or NULL when out of memory. */
char *cli_join_args(int argc, char **argv);

/* A duration of simulated time: a number and a unit, "60s", "250ms",
 * "5us", "2min", "1h", "5000tau", or a bare number of seconds. *v in
 * seconds or tau, *unit "s" or "tau" (the unit of a ramp command). The
 * number is not range-checked: the caller says what is allowed. */
int cli_duration(const char *s, double *v, const char **unit);

/* Line lineno of a text file the user names (path), whole, into line:
 * 1, 0 at the end of the file, or -1 with why set to "path:lineno: " and
 * what is wrong: a NUL byte (not a text file), longer than len - 2
 * characters, or cut short (no end of line: a file still being written,
 * or truncated). Reads at most len - 1 bytes of a line. */
int cli_read_line(FILE *fp, char *line, size_t len, const char *path, int lineno, char *why,
                  size_t whylen);

/* At the end of a program: standard output flushed and checked. rc, or 1
 * after "prog: writing the standard output failed: reason" when rc was 0
 * and a write or the flush failed (a full disk, /dev/full: the output is
 * incomplete; a failing rc was reported already). */
int cli_stdout_close(const char *prog, int rc);

/* The monotonic clock: seconds, and nanoseconds. */
double cli_mono_s(void);
int64_t cli_mono_ns(void);

/* The wall clock in microseconds since the epoch (LCM's utime). */
int64_t cli_wall_us(void);

/* The id of the parameter NAME as something a sweep, map, continuation or
 * rig varies: a row of the table that changes the motion and may change
 * alone. -1 for a name the table lacks, -2 for body data (z1 ... j2: the
 * theta outputs only, the motion would not change), -3 for a row tied to
 * others (a1, a2, a3: a1^2 + a2^2 + a3^2 = 1 breaks at every point). */
int cli_vary_param(const char *name);

/* cli_usage_error for a bad parameter to vary: "OPT 'NAME': not a
 * parameter ...", "... body data ..." or "... a direction cosine ...". */
int cli_vary_param_error(const char *prog, const char *opt, const char *name, int code);

/* Call fn on SIGINT and SIGTERM (no SA_RESTART: a blocking wait returns
 * EINTR, so the program sees its stop flag at once). */
void cli_on_stop_signals(void (*fn)(int));

/* The same with SA_RESTART, for a program that never waits but writes: a
 * write blocked on a full pipe goes on after fn instead of failing with
 * EINTR (stdio would drop the buffer it held: rows lost mid-file). */
void cli_on_stop_signals_restart(void (*fn)(int));

/* Bytes of the well-formed UTF-8 sequence of 2 to 4 bytes at p (RFC 3629:
 * no overlong form, no surrogate, nothing past U+10FFFF), 0 if none. */
int cli_utf8_len(const char *p);

/* A copy of s (NULL: "") that is safe to show on a terminal: a control
 * character (C0, DEL, C1 U+0080..U+009F: escapes a terminal would obey)
 * and each byte that is not part of well-formed UTF-8 become '?'; cut at a
 * character to fit n bytes. Strings off the bus are whatever a sender put
 * there. dst may be s (never longer than s). Returns dst. */
char *cli_text(char *dst, size_t n, const char *s);

/* s (NULL: "") as a JSON string literal on f: quotes, backslashes and
 * control characters escaped. */
void cli_json_str(FILE *f, const char *s);

#endif

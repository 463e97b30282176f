/* bench_args.h - a benchmark's command line, one rule for every benchmark:
 * operands only, in order, each one optional once one before it is left
 * out (a required one first). "--help" or "-h" prints the usage on
 * standard output and exits 0. A value that is not allowed, a missing
 * required operand, an option the benchmark does not have or an operand
 * too many gets one refusal on standard error (cli_usage_error: what was
 * typed, what is allowed) and exit 2, and nothing runs: a benchmark left
 * to atoi ran a "--help" as zero steps (bench_step divided by it), and
 * bench_step with 33 repetitions sorted 33 timings in an array of 32.
 * Static functions only; no global state. */
#ifndef WG_BENCH_ARGS_H
#define WG_BENCH_ARGS_H

#include "cli.h"

#include <stdio.h>
#include <string.h>

/* One operand: a whole number in [lo, hi] into *num, or (num NULL) a word
 * into *word. help says what it is, what is allowed and its default, in
 * words: the usage shows it, and a refusal of the operand repeats it. */
typedef struct bench_arg {
    const char *name, *help;
    double lo, hi;
    double *num;
    const char **word;
    int required;
} bench_arg;

static inline int bench_is_help(const char *s)
{
    return strcmp(s, "--help") == 0 || strcmp(s, "-h") == 0;
}

/* Text s from column `at`, broken at spaces before column 80, each further
 * line indented to `at`. */
static inline void bench_wrap(const char *s, int at)
{
    int col = at;
    while (*s) {
        int w = (int)strcspn(s, " ");
        if (col > at && col + 1 + w > 80) {
            printf("\n%*s", at, "");
            col = at;
        } else if (col > at) {
            putchar(' ');
            col++;
        }
        printf("%.*s", w, s);
        col += w;
        s += w;
        s += strspn(s, " ");
    }
    putchar('\n');
}

static inline void bench_usage(const char *prog, const char *about, const char *tail,
                               const bench_arg *a, int na)
{
    printf("usage: %s", prog);
    for (int k = 0; k < na; k++)
        printf(a[k].required ? " %s" : " [%s]", a[k].name);
    printf("%s\n", tail);
    bench_wrap(about, 0);
    for (int k = 0; k < na; k++) {
        printf("  %-10s ", a[k].name);
        bench_wrap(a[k].help, 13);
    }
}

/* An option, not a number: "-" and then neither a digit nor a point. */
static inline int bench_is_opt(const char *s)
{
    return s[0] == '-' && s[1] != '\0' && !(s[1] >= '0' && s[1] <= '9') && s[1] != '.';
}

/* Parse argv's operands into a[0..na). rest NULL: nothing may follow them;
 * else *rest is the index of the first argument after them (an option
 * starting with "--" ends the operands early), which the benchmark passes
 * on (tail names them in the usage). Returns -1 when the benchmark is to
 * run, else the exit status (0 after --help, CLI_EUSAGE after a refusal). */
static inline int bench_args(const char *prog, const char *about, const char *tail, int argc,
                             char **argv, bench_arg *a, int na, int *rest)
{
    int i = 1, k = 0;
    for (int j = 1; j < argc && !(rest && j > na); j++)
        if (bench_is_help(argv[j])) {
            bench_usage(prog, about, tail, a, na);
            return 0;
        }
    for (; k < na && i < argc; k++, i++) {
        const char *s = argv[i];
        if (rest && strncmp(s, "--", 2) == 0)
            break;
        if (bench_is_opt(s))
            return cli_usage_error(prog, "unknown option '%s' (operands only)", s);
        if (a[k].num) {
            int64_t v;
            if (cli_int64(s, (int64_t)a[k].lo, (int64_t)a[k].hi, &v))
                return cli_usage_error(prog, "%s '%s': %s", a[k].name, s, a[k].help);
            *a[k].num = (double)v;
        } else if (s[0] == '\0' || s[0] == '-') {
            return cli_usage_error(prog, "%s '%s': %s", a[k].name, s, a[k].help);
        } else {
            *a[k].word = s;
        }
    }
    if (k < na && a[k].required)
        return cli_usage_error(prog, "%s missing: %s", a[k].name, a[k].help);
    if (rest) {
        *rest = i;
        return -1;
    }
    if (i < argc && bench_is_opt(argv[i]))
        return cli_usage_error(prog, "unknown option '%s' (operands only)", argv[i]);
    if (i < argc)
        return cli_usage_error(prog, "'%s': an operand too many (at most %d)", argv[i], na);
    return -1;
}

#endif

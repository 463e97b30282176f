/* conf.h - wormgeard configuration: one key table for the INI file, the
 * command line, --help, the mode command's checks and SIGHUP reload.
 *
 * Precedence: built-in defaults < config file (-c FILE, INI, keys in a
 * [wormgeard] section or at top level) < command-line options. Every key is
 * also a long option (`steps_per_period` -> `--steps-per-period`). Errors
 * name the file, line, key and the allowed values or range. Each key is
 * live or restart-only (scene, url, prefix, steps_per_period, stepper,
 * mlock, rt_priority; the [params] overrides too); a live key may name an apply hook
 * that a reload calls when its value changes. */
#ifndef WGD_CONF_H
#define WGD_CONF_H

#include <stddef.h>
#include <stdio.h>

#include "wormgear/wg_param.h"

enum { MODE_REALTIME, MODE_FAST, MODE_LOCKSTEP };
enum { POLICY_CONTINUE, POLICY_FREEZE, POLICY_STOP };
enum { CONTACTS_ALL, CONTACTS_MESH, CONTACTS_NONE };
enum { CONF_MAX_SETS = WG_NPARAM }; /* one override a parameter: a file's every one fits */
enum { CONF_RESTART = 1 }; /* key flag: takes effect at the next restart only */
enum { CONF_FILE_MAX = 1 << 20 }; /* a config file larger than this is refused */

/* The apply hooks of live keys, by slot; the caller of conf_reload supplies
 * them (conf.c calls nothing above it). */
enum { CONF_APPLY_NONE, CONF_APPLY_MODE, CONF_APPLY_TICK, CONF_APPLY_VERBOSE, CONF_APPLY_KEY,
       CONF_APPLY_CONTACTS, CONF_NAPPLY };

typedef struct conf {
    char path[512];           /* config file read ("" = none) */
    char scene[256];          /* scene name or INI file */
    char url[256];            /* LCM URL */
    char prefix[64];          /* channel prefix */
    int mode;                 /* MODE_* */
    double rate;              /* realtime rate factor */
    int steps_per_period;     /* N */
    int stepper;              /* enum wg_stepper_kind */
    double state_rate_hz;     /* STATE samples per wall second (0: off) */
    double scope_hz;          /* SCOPE samples per wall second (0: off) */
    int contacts;             /* CONTACTS_*: which CONTACT events are published */
    int bearing_every;        /* contacts = all: every Nth event of each bearing */
    int state_decimation;     /* fixed steps per STATE sample (0: from state_rate_hz) */
    int tick_us;              /* pacing tick */
    double catchup_ticks;     /* catch-up cap, in ticks' worth of steps */
    int overrun_policy;       /* POLICY_* */
    int overrun_stop_after;   /* consecutive overruns that stop the run */
    double startup_grace_s;   /* overruns ignored this long after (re)start */
    double lag_warn_ms;       /* health = lagging above this lag */
    double status_hz;         /* STATUS rate, 1..10 */
    char state_dir[512];      /* save/restore directory */
    char command_key_file[512]; /* signed commands: the key ("" = off) */
    int accept_commands;      /* 0: refuse every command except get */
    int start_paused;
    int mlock;                /* mlockall at start */
    int rt_priority;          /* SCHED_FIFO priority of every thread, 0: off */
    int foreground;           /* one-line status on stdout each second */
    int verbose;
    int log_prefix;           /* "<N>" priority prefixes on log lines */
    int check_only;           /* --check-config: load, validate, exit */
    int nsets;
    char sets[CONF_MAX_SETS][128]; /* --set name=value (validated by the param table) */
} conf;

/* Fill c with the built-in defaults ($STATE_DIRECTORY honoured). */
void conf_defaults(conf *c);

/* Defaults, $WORMGEAR_URL and $WORMGEAR_PREFIX (one the key would refuse:
 * 2), then the config file named by -c/--config, then the options.
 * Returns 0 to run, 1 when --help was printed (exit 0), 2 on a usage or
 * config error with the message in why ("file:line: key: ..."). Does not
 * keep argv; may be called again (SIGHUP reload). */
int conf_load(conf *c, int argc, char **argv, char *why, size_t whylen);

/* Read one INI file into c (keys as in the table). Only a regular file of
 * at most CONF_FILE_MAX bytes is read, never opened when it is not one (a
 * FIFO would block the daemon, a device never end); a NUL byte, a key set
 * twice in a file, an indented continuation line and a line longer than
 * the parser's buffer are refused. 0, or 2 with why ("file:line: ..."); on
 * a refusal c may hold some of the file's values (the caller drops it). */
int conf_read_file(conf *c, const char *path, char *why, size_t whylen);

/* Set one key from text, as the file and the options do. 0, or 2 with why
 * naming the key and its allowed values. */
int conf_set(conf *c, const char *key, const char *value, char *why, size_t whylen);

/* A live key changed on reload: ctx as given to conf_reload, was the
 * running configuration before the reload (the new values are in place). */
typedef void (*conf_apply_fn)(void *ctx, const conf *was);

/* Reload: one loop over the key table, comparing next with loaded (what
 * the last load said: file and options). Each live key whose value there
 * changed is copied into run, then its hook (hooks[slot], may be NULL) is
 * called; restart-only keys and the [params] overrides keep their running
 * values, and the names of those that changed go to kept ("scene, url and
 * [params]"; "" if none). A live key the load left alone keeps its running
 * value, a command's (mode, rate, contacts) included: those differing from
 * the load are named in held ("mode and rate"; ""). loaded becomes next; the
 * config file path follows next. */
void conf_reload(conf *run, conf *loaded, const conf *next, const conf_apply_fn *hooks,
                 void *ctx, char *kept, size_t keptlen, char *held, size_t heldlen);

/* Check number x for key name against the table (its range; an integer for
 * integer keys), as conf_set checks text: 0, or 2 with why naming the key,
 * the value (%.17g) and the range. */
int conf_check_number(const char *name, double x, char *why, size_t whylen);

/* Names of enum values, for logs and STATUS. */
const char *conf_mode_name(int mode);
const char *conf_policy_name(int policy);
int conf_mode_lookup(const char *name);

/* "all" "mesh" "none"; the CONTACTS_* of a name, or -1. */
const char *conf_contacts_name(int contacts);
int conf_contacts_lookup(const char *name);

/* Print the --help text (every key with its default and range). */
void conf_usage(FILE *f);

#endif

/* wgd.h - the one daemon struct of wormgeard.
 *
 * Everything mutable lives here: configuration, logging, the simulation,
 * the LCM side, the output batches, pacing, statistics, the systemd
 * notifier and the libev watchers. main.c initialises the modules in the
 * order below and finalises them in reverse. Only one thread touches it
 * (the libev loop); signal handling is libev's ev_signal, whose callbacks
 * only set flags. */
#ifndef WGD_H
#define WGD_H

#include <ev.h>
#include <stdint.h>

#include "auth.h"
#include "conf.h"
#include "inbox.h"
#include "lcmio.h"
#include "log.h"
#include "pace.h"
#include "stream.h"
#include "wire.h"
#include "wormgear/wg_scene.h"
#include "wormgear/wg_sim.h"

enum { RUN_RUNNING, RUN_PAUSED };
enum { HEALTH_OK, HEALTH_LAGGING, HEALTH_FAULT };
enum { WGD_TICK_WHY = 512 }; /* room for why a TICK was not taken (STATUS tick_refusal) */

/* A `step` command in progress (its ACK is sent when it completes). */
typedef struct stepjob {
    int active;
    uint64_t left, total;
    char client[WIRE_MAX_CLIENT + 1]; /* echoed byte for byte in its ACK */
    char op[16];
    int64_t seq, utime;
} stepjob;

/* A `set` waiting for the next Poincare section (at_section = 1): the
 * parameters validated on arrival, applied and ACKed at psi = 0. */
typedef struct syncjob {
    int active;
    int n, ids[WG_NPARAM];
    double values[WG_NPARAM];
    char client[WIRE_MAX_CLIENT + 1]; /* echoed byte for byte in its ACK */
    int64_t seq, utime;
} syncjob;

/* What the command being handled changed (cmd.c): reported once its ACK
 * is out, so the ACK leaves first and PARAMS right behind it. */
typedef struct change {
    int due;
    int what;                  /* REPORT_ORBIT | REPORT_RATE */
    const char *reason;        /* "set", "ramp", "reset", "restore" */
} change;

/* Accumulators and derived figures for STATUS (report.c). */
typedef struct stats {
    int64_t t_ns;              /* start of the current STATUS interval */
    double tau;                /* simulated time run since then (engine_run: a reset or a
                                  restore jumps the state, not this) */
    uint64_t steps;            /* sim steps run since then */
    double cpu_s;              /* process CPU time then */
    double loop_sum_ns, loop_max_ns;
    uint64_t loops;
    double ns_per_step;        /* smoothed cost of one step */
    /* last computed figures */
    double rtf, steps_per_s, cpu_share, loop_mean_us, loop_max_us, impacts_per_period;
    double bearing_ipp[WG_NBEARING], bearing_vmax[WG_NBEARING]; /* per bearing, x1 ... z2 */
    int health;
    int64_t next_status_ns, next_params_ns, next_fg_ns, next_flush_ns, next_scope_ns;
    uint64_t cmds_accepted, cmds_refused;
    uint64_t tick_gaps;        /* TICKs lost: the gaps in their seq */
    uint64_t status_foreign;   /* STATUS messages on our channel not ours (report.c) */
    uint64_t ticks_refused;    /* TICKs not taken (lockstep.c) */
    char tick_why[WGD_TICK_WHY]; /* why the last was not taken, escaped ("" none yet) */
    uint64_t tick_seq_next;    /* expected TICK seq (wraps; valid once tick_seen) */
    int tick_seen;
    uint64_t tick_senders;     /* TICK seq discontinuities: a new or restarted sender */
    int64_t tick_ns, tick_cpu_ns; /* the last timer tick: wall and main-thread CPU time */
    int64_t busiest_ns;        /* the longest handler since then (wall) */
    uint64_t tick_steps;       /* sim steps then */
    int fg_failed;             /* stdout failed: the foreground line is no longer printed */
    uint64_t pub_dropped;      /* io.dropped at the last second's look (report.c) */
    int pub_failing;           /* publishing failed in the last second's look */
    uint64_t pub_failed_from;  /* io.dropped when it started failing */
} stats;

/* Steps owed and not yet run: the loop runs them in bounded chunks between
 * I/O, so a command is answered while they run (loop.c). */
typedef struct backlog {
    uint64_t ticks;            /* from TICK messages (lockstep) */
    uint64_t realtime;         /* due by the pace at the last tick */
} backlog;

/* systemd notification state (sdn.c). */
typedef struct sdn {
    int ready;                 /* READY=1 sent */
    uint64_t wd_usec;          /* WatchdogSec (0: off) */
    int64_t next_wd_ns;
} sdn;

typedef struct wgd {
    int argc;
    char **argv;
    conf conf;
    conf conf_loaded;            /* as the last load said (file, options): a reload applies
                                    what changed since, a command's mode or rate stays */
    log_ctx log;
    /* simulation (engine.c) */
    wg_scene scene;
    wg_params scene_params;    /* the scene's parameters with the --set overrides */
    wg_sim sim;
    int sim_ok;
    int run;                   /* RUN_RUNNING / RUN_PAUSED */
    int fault;                 /* a blow-up or a policy stop happened */
    char fault_msg[320];
    stepjob step;
    syncjob sync;
    change changed;
    backlog owed;
    /* transport and outputs */
    inbox in;                  /* CMD messages received, not yet handled (cmd.c) */
    auth auth;                 /* signed commands: the key and per-client counters */
    unsigned char cmdbuf[INBOX_MSG_MAX]; /* the one being handled */
    lcmio io;
    stream st;
    pace pace;
    stats stat;
    sdn sd;
    /* loop (loop.c) */
    struct ev_loop *loop;
    ev_io lcm_w, tick_w;
    ev_idle work_w;            /* runs owed steps, fast mode, a step job: chunk by chunk */
    ev_signal sig_int, sig_term, sig_hup;
    int tfd;
    int stop, reload;          /* set by the signal callbacks */
    int64_t start_ns;
    char init_why[640];        /* why a module's init failed (main logs it) */
} wgd;

#endif

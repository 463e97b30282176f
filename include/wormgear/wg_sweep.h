/* wg_sweep.h - parameter sweeps with continuation, per-point regime
 * analysis, chains on threads, and the transitions table (MODEL.md s5-s6).
 *
 * A *chain* is a sequence of parameter values run in order, each point
 * seeded with the previous point's final state (so jumps show as up/down
 * hysteresis). Chains are independent: a 1-D study is two chains (up and
 * down) per damping value, a 2-D map one chain per row. A chain's result
 * depends only on its inputs, never on the thread or process that ran it. */
#ifndef WG_SWEEP_H
#define WG_SWEEP_H

#include <signal.h>
#include "wg_regime.h"

enum { WG_POINT_NSEC = 128 };

/* Analysis settings of every point of a sweep. */
/* Early stop's window (wg_sweep_opts.settle): 24 sections (periods up to
 * 12 stop early) keep every robust point's classification on the Table-3
 * study and on the lowfreq, realistic and torsional scenes
 * (lib.test_settle); on the study so do 20, 32 and 64, 16 does not. Off
 * by default: a chain continued from an early-stopped point starts a hair
 * off the attractor and, where attractors coexist, may follow another one
 * than the full transient's chain does (1,377 of 1,430 robust points of
 * the study agree chain for chain). */
enum { WG_SETTLE_WINDOW = 24 };

/* Ranges of the tolerances (wg_sweep_opts_check). The period tolerance
 * compares Poincare states, O(1) in b_c: its floor at most the loose
 * tolerance a point takes once its LLE says it converges (1e-4: a
 * period-2 orbit whose two sections are further apart than that is told
 * from period 1; a floor of 1e300 made every point period 1), at least
 * WG_TOL_MIN. The factor on the one-period error at least 1 (points
 * closer than the integration resolves are the same point) and at most
 * 1000. The LLE threshold in [1e-4, 0.1] per mesh period: chaos at
 * 0.1 per period doubles a separation in 7 periods; the estimate over
 * the default 300 periods is good to about 1e-3. */
#define WG_TOL_FLOOR_MAX 1e-4
#define WG_TOL_FACTOR_MIN 1.0
#define WG_TOL_FACTOR_MAX 1e3
#define WG_LLE_TOL_MIN 1e-4
#define WG_LLE_TOL_MAX 0.1

typedef struct wg_sweep_opts {
    int model, stepper;  /* enum wg_model_kind, wg_stepper_kind */
    int steps;           /* N per mesh period; raised to 1.25x the RK4 limit */
    int transient;       /* periods run before recording (each point) */
    int settle;          /* early stop: the transient ends once the last `settle`
                            sections repeat with a period n <= WG_PERIOD_MAX within
                            the period tolerance, n at most half of them and 8
                            pairs left (0: always the full transient) */
    int record;          /* periods recorded for period detection, >= 64 */
    int extend;          /* extra transient blocks while no period is found */
    int lle_periods;     /* twin-trajectory periods for aperiodic points */
    double lle_d0;       /* twin separation */
    double lle_tol;      /* |LLE| per period below this: quasi-periodic,
                            WG_LLE_TOL_MIN..WG_LLE_TOL_MAX */
    double tol_factor;   /* period tolerance = max(tol_floor, factor * err),
                            WG_TOL_FACTOR_MIN..WG_TOL_FACTOR_MAX */
    double tol_floor;    /* WG_TOL_MIN..WG_TOL_FLOOR_MAX */
    int floquet;         /* Floquet multipliers of periodic points (wg_shoot.h:
                            variational monodromy, rk4-event stepper only) */
    int verify;          /* re-analyse each point's attractor with 2N steps */
    int pair;            /* chains each thread advances at once (the same
                            results): 2 to 8 (8, the default), their runs paired
                            (wg_sim_run_pair) or, three or more where the CPU
                            has AVX2 or AVX-512, batched (wg_sim_run_batch),
                            a Lyapunov exponent's twin run beside its base; 1:
                            one chain at a time (the twin still paired with its
                            base). A thread takes at most its share of the
                            chains, and two at once when that is under three */
} wg_sweep_opts;

/* Result of one point. */
typedef struct wg_point {
    double value, value2; /* swept parameter value (and the row's, 2-D) */
    int regime, period;   /* enum wg_regime_kind; n for periodic */
    int converged;        /* period met tol (else inferred from LLE < 0) */
    int motion;           /* worst motion class over the recorded periods */
    int steps;            /* N used */
    int transient;        /* periods of transient before the first record (fewer
                             than the option's when it settled early) */
    int nsec;             /* Poincare samples stored (<= WG_POINT_NSEC) */
    double impacts;       /* mesh impacts per period */
    double bimpacts[WG_NBEARING]; /* each bearing's impacts per period, x1 y1 z1 x2 y2 z2
                                     (crossing +b_j upward or -b_j downward) */
    double bvmax[WG_NBEARING];    /* their largest |velocity| over the recorded periods */
    double min_xn, max_xn;
    double lle;           /* largest exponent per mesh period, NAN if not run */
    double err;           /* one-period integration error estimate (max norm) */
    double tol;           /* period tolerance used */
    double resid;         /* period residual (max norm) */
    double xn[WG_POINT_NSEC], dxn[WG_POINT_NSEC]; /* Poincare x_n, x_n' */
    int nfloq;            /* multipliers stored (0 if not computed) */
    double floq_re[WG_NSTATE_MAX], floq_im[WG_NSTATE_MAX];
    double y_end[WG_NSTATE_MAX]; /* final state at psi = 0 */
    int checked;          /* verify: the 2N re-analysis ran */
    int check_regime, check_period, check_motion; /* its classification */
} wg_point;

/* One chain: parameter `param` over npts values from v0 to v1 (inclusive,
 * evenly spaced; dir = -1 runs them from v1 down to v0). */
typedef struct wg_chain {
    wg_params base;       /* every other parameter */
    int param;            /* wg_param_id swept */
    double v0, v1;
    int npts, dir;
    int param2;           /* row parameter of a 2-D map (-1: none); its value is in base */
    int has_y0;           /* start from y0, else the static equilibrium */
    double y0[WG_NSTATE_MAX];
    wg_point *pts;        /* npts results, in run order; caller-owned */
    int ndone;            /* points completed */
    int rc;               /* WG_OK or the error that stopped the chain */
    char why[160];
} wg_chain;

/* Progress callback: one more point of chain `chain` is done. */
typedef void (*wg_progress_fn)(void *ctx, int chain, int ndone);

/* Defaults: rk4-event, N = 256, transient 300 (the whole of it: settle 0;
 * WG_SETTLE_WINDOW is the early-stop window worth asking for), record 128, extend 3, LLE 300 periods d0 1e-7 tol 0.01,
 * tol = max(1e-9, 10 err), no Floquet, pair 8. */
void wg_sweep_opts_default(wg_sweep_opts *o);

/* WG_OK if the chains and points take o's tolerances (tol_floor,
 * tol_factor, lle_tol) in the ranges above; else WG_ERANGE with why ("need
 * 1e-13 to 0.0001 ..., got 1e+300") and *field (if not NULL) the member at
 * fault, so a program can say it in the words of its own options.
 * wg_chain_run, wg_chains_run and wg_point_run refuse such o the same way
 * (the chain's rc and why). */
int wg_sweep_opts_check(const wg_sweep_opts *o, const char **field, char *why, size_t whylen);

/* Value of point i (in run order) of a chain. */
double wg_chain_value(const wg_chain *c, int i);

/* Run chain c point by point (with o->verify, each point's final state is
 * analysed again with twice the steps per period, not continued; the
 * chain follows the N solution); stops early (status WG_OK, ndone < npts) when
 * *stop becomes non-zero (stop may be NULL). Allocates two or three sims for
 * the duration of the call. WG_OK or the status that ended the chain (also
 * in c->status, with c->why). */
int wg_chain_run(wg_chain *c, const wg_sweep_opts *o, volatile sig_atomic_t *stop,
                 wg_progress_fn progress, void *ctx);

/* Run n chains on `threads` POSIX threads (1: in the caller); a chain may
 * move to a thread running fewer between two of its points (the same
 * results); progress is called under a lock. Returns WG_OK or the first
 * failing chain's status; each chain keeps its own status. n = 0: nothing
 * runs, WG_OK; n < 0: WG_EINVAL. */
int wg_chains_run(wg_chain *cs, int n, const wg_sweep_opts *o, int threads,
                  volatile sig_atomic_t *stop, wg_progress_fn progress, void *ctx);

/* Analyse one point at parameters p starting from y (psi = 0): the same
 * code as a chain's point. *pt gets the result (value and value2 are left
 * 0 for the caller), y the final state. */
int wg_point_run(const wg_params *p, const wg_sweep_opts *o, double *y, wg_point *pt,
                 char *why, size_t whylen);

/* 1 if pt holds a measurement; 0 for a point with no section recorded and
 * no regime (a rig's point the daemon refused) or a diverged one (its
 * integration blew up before any record: its motion, impacts and x_n
 * extremes read "no impact, 0"), whose other fields are not values: writers
 * leave them empty, figures draw nothing for them. */
int wg_point_measured(const wg_point *pt);

/* ---- the analysis of recorded sections ----------------------------------
 * The steps of a point's analysis that only need the recorded Poincare
 * sections, whoever integrated them: the offline sweep (wg_point_run) and
 * the live rig (wgrig, sections from the daemon) share these. */

/* n recorded sections: n x nstate states and the period that ended at each. */
typedef struct wg_record {
    int nstate, n;
    const double *y;
    const wg_period *stats;
} wg_record;

/* One-period integration error |P_2N(y[n-2]) - y[n-1]| (max norm), P_2N
 * taken with `fine`, a sim at twice the record's steps per period. The 2N
 * error being 16x smaller, this estimates the record's own. WG_EINVAL if
 * fewer than 2 sections, else the status of the step. */
int wg_record_period_error(wg_sim *fine, const wg_record *r, double *err);

/* Classify a point with no strict period from a record taken after its LLE
 * (pt->tol and pt->lle set): period with the strict tolerance, or with a
 * loose one when the LLE says the orbit converges; then the regime. */
void wg_record_classify(const wg_sweep_opts *o, const wg_record *r, wg_point *pt);

/* min/max x_n, worst motion class, mean mesh impacts per period, and each
 * bearing's mean impacts per period and largest impact speed over r. */
void wg_record_stats(const wg_record *r, wg_point *pt);

/* ---- transitions (the paper's Table 3) ---------------------------------- */

enum wg_trans_kind {
    WG_TR_GRAZING,      /* min x_n reaches b: impacts begin (or end) */
    WG_TR_BACKSIDE,     /* first back-side impact: double-sided motion */
    WG_TR_JUMP,         /* up/down attractors differ: envelopes (min, max x_n) apart by
                           > 0.02 b (0.1 b if both aperiodic); the hysteresis interval */
    WG_TR_DOUBLING,     /* period n -> 2n */
    WG_TR_HALVING,      /* period 2n -> n (increasing parameter) */
    WG_TR_PERIOD,       /* any other change of period */
    WG_TR_CHAOS,        /* a chaotic interval [lo, hi] */
    WG_TR_QUASI,        /* a quasi-periodic interval [lo, hi] */
    WG_TR_RETURN_P1,    /* back to period-1 from a higher period or chaos */
    WG_NTRANS
};

/* One transition, located between grid values (lo, hi) of a sweep. Values
 * are in increasing-parameter terms for both directions: a down-sweep
 * event from period 2 at high omega to period 1 below is a doubling. */
typedef struct wg_transition {
    int kind;           /* enum wg_trans_kind */
    int dir;            /* +1 up sweep, -1 down sweep, 0 both / interval */
    double lo, hi;      /* bracket (interval kinds: its first and last point) */
    double at;          /* best estimate (interpolated for grazing) */
    int from, to;       /* periods (0 = aperiodic) or motion classes */
    double lo2, hi2;    /* JUMP: the other sweep's bracket; hysteresis is [lo2, hi] */
} wg_transition;

/* Name of a transition kind: "grazing", "jump", "period doubling", ... */
const char *wg_trans_name(int kind);

/* Transitions of an up sweep and a down sweep over the same grid (either
 * may be NULL/0 points; points in run order). b is the backlash, NAN where
 * the sweep varies b itself (each point's value is its b: grazing is where
 * min x_n crosses it). Writes at most max entries to out, sorted by
 * parameter value; returns the count. */
int wg_transitions(const wg_point *up, int nup, const wg_point *down, int ndown, double b,
                   wg_transition *out, int max);

#endif

/* wg_regime.h - regime of an orbit: period from Poincare points, largest
 * Lyapunov exponent, eigenvalues for Floquet multipliers (MODEL.md s5).
 *
 * Everything here works on a *map*: a function that advances a state by one
 * mesh period (the Poincare map psi = 0 -> psi = 2 pi). wg_simmap adapts a
 * wg_sim to that interface, so the daemon's STATUS, wgsweep and wgrig share
 * one implementation; tests plug in textbook maps (logistic, Henon, linear).
 * Periodic orbits of the model and their Floquet multipliers (from the
 * variational equations) are in wg_shoot.h.
 * Nothing allocates: callers own every buffer. */
#ifndef WG_REGIME_H
#define WG_REGIME_H

#include <stddef.h>
#include "wg_sim.h"

enum { WG_PERIOD_MAX = 32, WG_TRACK_LEN = 96 };

/* Regime of an attractor. */
enum wg_regime_kind {
    WG_REGIME_NONE = 0,     /* not computed (interrupted, or too few points) */
    WG_REGIME_PERIODIC,     /* period-n, n = 1..32 */
    WG_REGIME_QUASIPERIODIC,/* no period <= 32, largest exponent ~ 0 */
    WG_REGIME_CHAOTIC,      /* largest exponent > 0 */
    WG_REGIME_DIVERGED      /* the integration blew up */
};

/* A map x -> P(x) on dim doubles, in place; returns WG_OK or a status. */
typedef struct wg_map {
    int (*fn)(void *ctx, double *x);
    void *ctx;
    int dim;
} wg_map;

/* Poincare map of a wg_sim: `periods` mesh periods of the sim's N steps from
 * psi = 0. The sim's parameters must stay constant while it is used. `run`
 * (may be NULL: wg_sim_run) takes the steps instead, with run_ctx: it must
 * give wg_sim_run's result (the sweeps pair the runs of several chains). */
typedef struct wg_simmap {
    wg_sim *sim;
    int periods;
    int (*run)(void *run_ctx, wg_sim *sim, uint64_t n);
    void *run_ctx;
} wg_simmap;

/* "none", "periodic", "quasiperiodic", "chaotic", "diverged". */
const char *wg_regime_name(int kind);

/* Smallest n in 1..nmax such that every pair of the npts points (each dim
 * doubles, row-major) that are n apart lies within tol (max norm); 0 if no
 * such n with at least max(n, 8) pairs. *resid (may be NULL) receives the
 * largest pair distance for the n returned, or the smallest such distance
 * over all n when 0 is returned. */
int wg_period_detect(const double *pts, int npts, int dim, int nmax, double tol,
                     double *resid);

/* Streaming period detection for a live run (daemon STATUS): the last
 * WG_TRACK_LEN Poincare states and period statistics, no allocation. */
typedef struct wg_tracker {
    double pts[WG_TRACK_LEN][WG_NSTATE_MAX]; /* a ring: the oldest at head */
    int dim, n, head;
    double tol;
    int motion;      /* worst motion class over the stored periods */
    long impacts;    /* mesh impacts over the stored periods */
    int imp[WG_TRACK_LEN], mot[WG_TRACK_LEN];
} wg_tracker;

/* Empty tracker for states of `dim` values, period tolerance tol (> 0). */
void wg_tracker_init(wg_tracker *t, int dim, double tol);

/* Add one Poincare section (the oldest drops out when full). */
void wg_tracker_push(wg_tracker *t, const wg_section *sec);

/* Period of the stored sections, oldest first, by wg_period_detect (0: none
 * found, or fewer than 16 stored; then *resid is INFINITY). */
int wg_tracker_period(const wg_tracker *t, double *resid);

/* Adapter: wg_map over sm (fn = wg_simmap_step, dim = sim's nstate). */
wg_map wg_simmap_map(wg_simmap *sm);

/* Map function of wg_simmap: set the state x at psi = 0, run, copy back.
 * WG_OK or WG_ENONFINITE. */
int wg_simmap_step(void *ctx, double *x);

/* Largest Lyapunov exponent by a twin trajectory (Benettin): `base` and
 * `twin` are two maps of the same system (they may share nothing), x the
 * start (advanced in place along the orbit), d0 the initial separation
 * (Euclidean). The twin is pulled back to distance d0 whenever the
 * separation leaves [d0/1e3, d0*1e3] (checked every map step), so it stays
 * in the linear regime while a wg_simmap twin is rarely reset. *lle gets the
 * exponent per map step (per mesh period for a 1-period wg_simmap). WG_OK,
 * WG_EINVAL (dim > 64, steps < 1, d0 <= 0) or a map error. */
int wg_lle_twin(const wg_map *base, const wg_map *twin, double *x, int steps, double d0,
                double *lle);

/* Runs sims a and b (distinct) n steps each, as wg_sim_run(a, n, NULL,
 * NULL) and wg_sim_run(b, n, NULL, NULL) would, with run_ctx; returns a's
 * status, or b's if a's is WG_OK. */
typedef int (*wg_run2_fn)(void *run_ctx, wg_sim *a, wg_sim *b, uint64_t n);

/* wg_lle_twin of two wg_simmaps of one period, with its exponent to the
 * bit: sim from x (advanced in place along the orbit) and twin, a second
 * sim of the same system and N (its state is overwritten). The two advance
 * together, as wg_sim_run_pair does (one fills the machine while the other
 * waits), or by run2(run_ctx, sim, twin, N) where run2 is not NULL (the
 * sweeps batch them with other chains' runs). WG_EINVAL if sim is twin or
 * their sizes or N differ; else as wg_lle_twin. */
int wg_lle_sims(wg_sim *sim, wg_sim *twin, double *x, int periods, double d0, wg_run2_fn run2,
                void *run_ctx, double *lle);

/* Eigenvalues of a real n x n matrix A (row-major, destroyed), n <= 16:
 * balancing, Hessenberg reduction and Francis double-shift QR. wr, wi get
 * the real and imaginary parts, sorted by decreasing modulus. WG_OK, or
 * WG_ENONFINITE if QR did not converge. */
int wg_eig(int n, double *A, double *wr, double *wi);

#endif

/* wg_sim.h - fixed-step RK4 integration of the model, with the excitation
 * phase, Poincare sections, contact events and per-period motion class.
 *
 * Steps are h = 2 pi / (omega N): the phase psi advances by exactly 2 pi / N
 * per step (also during an omega ramp, where h is solved per step), so psi is
 * an integer index k and the Poincare section psi = 0 falls on a step
 * boundary. With constant parameters the excitation comes from a table built
 * once (no libm in the hot loop). The kernel is chosen once per parameter
 * change, specialised on what the scene needs (bearings or torsional only,
 * dead zones, k_a, e_m). A wg_sim owns all its memory: nothing is allocated
 * per step. */
#ifndef WG_SIM_H
#define WG_SIM_H

#include <stdint.h>
#include "wg_model.h"

enum wg_stepper_kind {
    WG_STEPPER_DEFAULT = -1, /* the model's own: rk4-event, or rk4 for the printed form */
    WG_STEPPER_RK4 = 0,      /* classical RK4 on the true (kinked) RHS */
    WG_STEPPER_RK4_EVENT = 1 /* RK4 split at located dead-zone crossings */
};

enum { WG_STEPS_MIN = 8, WG_STEPS_MAX = 65536, WG_STEPS_DEFAULT = 128 };

/* The smallest tolerance on a difference of states that a run may ask
 * for: states are O(1) (lengths in b_c), double precision resolves about
 * 2e-16 of them and a mesh period's RK4 steps round to about 1e-15 (a
 * converged period-1 orbit's residual is 3e-15), so a tolerance under
 * 1e-13 is never met, or met by chance. wg_cont_check and
 * wg_sweep_opts_check refuse one. */
#define WG_TOL_MIN 1e-13

/* Allowed ramp durations, in tau (a millionth of a unit of time up to
 * 1e15; a shorter ramp is a set, a longer one never ends). */
#define WG_RAMP_TAU_MIN 1e-6
#define WG_RAMP_TAU_MAX 1e15

/* The realtime rate factor's range (simulated over physical real time; 1
 * is physical): wormgeard's `rate` and the mode command's, for the daemon
 * and every client that sends one. */
#define WG_RATE_MIN 1e-6
#define WG_RATE_MAX 1000.0

typedef struct wg_sim_config {
    int model;            /* enum wg_model_kind */
    int stepper;          /* enum wg_stepper_kind (WG_STEPPER_DEFAULT: the model's) */
    int steps_per_period; /* N, WG_STEPS_MIN..WG_STEPS_MAX */
} wg_sim_config;

/* A located or interpolated crossing of a dead-zone boundary. */
typedef struct wg_event {
    double tau;      /* time of the crossing */
    double velocity; /* rate of the contact coordinate at the crossing */
    uint64_t period; /* mesh period it fell in */
    int contact;     /* enum wg_contact */
    int kind;        /* enum wg_event_kind */
} wg_event;

/* Statistics of one completed mesh period. */
typedef struct wg_period {
    uint64_t period;     /* index of the completed period, from 0 */
    double min_xn;       /* minimum of x_n over the period (Hermite-refined) */
    double max_xn;
    int motion;          /* enum wg_motion */
    int impacts;         /* mesh drive + back impacts in the period */
    int bimpacts[WG_NBEARING]; /* each bearing's impacts (either side), x1 ... z2 */
    double bvmax[WG_NBEARING]; /* ... and its largest |impact velocity| (0: none) */
} wg_period;

/* Poincare sample: the state at psi = 0 (mod 2 pi), once per period. */
typedef struct wg_section {
    double tau, omega;
    double y[WG_NSTATE_MAX];
    wg_outputs out;
    wg_period stats; /* the period that just ended */
} wg_section;

struct wg_sim;

/* Output callbacks; any may be NULL (that work is then skipped). */
typedef struct wg_sink {
    void *ctx;
    void (*on_step)(void *ctx, const struct wg_sim *sim);
    void (*on_section)(void *ctx, const wg_section *sec);
    void (*on_event)(void *ctx, const wg_event *ev);
} wg_sink;

typedef struct wg_ramp {
    int active;
    int id;           /* parameter ramped */
    double v0, v1;    /* start and target value */
    double tau0, dur; /* start time and duration (tau units, > 0) */
} wg_ramp;

/* The library's private part of a run: kernel, coefficients, excitation
 * table, stability cache, contact zones, period statistics (lib/internal.h). */
struct wg_sim_core;

/* One run. Callers read these fields and never write them: every change
 * goes through the functions below, which keep them consistent. */
typedef struct wg_sim {
    wg_params p;          /* current parameters (ramped value included) */
    wg_sim_config cfg;    /* the stepper here is the one chosen (never DEFAULT) */
    int nstate;
    double y[WG_NSTATE_MAX];
    uint32_t k;           /* phase index: psi = 2 pi k / N */
    uint64_t period;      /* completed mesh periods */
    uint64_t steps;       /* accepted steps */
    double tau, tau_c;    /* time and its compensation term (Kahan) */
    double h;             /* step for constant omega */
    double hmax;          /* RK4 stability limit for the current parameters */
    wg_ramp ramp;         /* the ramp in progress, if active */
    uint64_t nevents[WG_NCONTACT][WG_NEVKIND]; /* contact events so far */
    uint64_t nsplit;      /* rk4-event: extra sub-steps taken */
    struct wg_sim_core *core;
} wg_sim;

/* Everything that defines the future of a run: configuration, parameters
 * (a ramped one at its current value), state, phase, time, counters, the
 * ramp and the period statistics. Plain data; wg_snapshot.h writes it as
 * text and reads it back, and wg_sim_restore decides whether it makes a run. */
typedef struct wg_snapshot {
    int model, stepper, steps_per_period;
    wg_params p;
    double y[WG_NSTATE_MAX];
    uint32_t k;
    double tau, tau_c;
    uint64_t period, steps;
    wg_ramp ramp;
    wg_period cur, last;
} wg_snapshot;

/* Names of the steppers: "default", "rk4", "rk4-event"; lookup returns
 * WG_STEPPER_DEFAULT, WG_STEPPER_RK4 or WG_STEPPER_RK4_EVENT, or -2 if the
 * name is none of them. */
const char *wg_stepper_name(int stepper);
int wg_stepper_lookup(const char *name);

/* The stepper a run of `model` uses when `stepper` is asked for: itself, or
 * for WG_STEPPER_DEFAULT the model's (rk4-event; rk4 for the printed form,
 * which supports nothing else). WG_OK with *chosen, or WG_EUNSUPPORTED with
 * why when the model cannot run the stepper asked for. wg_sim_init decides
 * with this; tools that name the stepper before a run ask it too. */
int wg_stepper_choose(int model, int stepper, int *chosen, char *why, size_t whylen);

/* Set up sim for parameters p and configuration cfg, in the static
 * equilibrium, psi = 0, tau = 0. WG_ERANGE/WG_EUNSUPPORTED/WG_ESTABILITY
 * with why; WG_ENOMEM. On error nothing needs freeing. */
int wg_sim_init(wg_sim *sim, const wg_params *p, const wg_sim_config *cfg,
                char *why, size_t whylen);

/* Release the sim's memory. Safe on a zeroed or failed sim. */
void wg_sim_fini(wg_sim *sim);

/* Replace every parameter at once (atomic: all valid, or nothing changes).
 * psi, tau and the state are continuous; an active ramp is cancelled.
 * WG_ERANGE or WG_ESTABILITY (N too small for the new parameters) with why. */
int wg_sim_set_params(wg_sim *sim, const wg_params *p, char *why, size_t whylen);

/* Would wg_sim_set_params accept p? The same checks (table ranges, the
 * direction cosines, RK4 stability for this N), nothing applied. */
int wg_sim_check_params(wg_sim *sim, const wg_params *p, char *why, size_t whylen);

/* Ramp parameter id linearly to `target` over `dur` tau units (dur > 0),
 * phase-continuously, from *from (the parameter jumps there first) or, with
 * from NULL, from its current value. Only WG_PF_RAMP parameters; dur in
 * [WG_RAMP_TAU_MIN, WG_RAMP_TAU_MAX]. Validated completely before anything
 * changes (the duration, the table's range at both ends: every value along
 * the ramp is then finite and in range; the stability limit over the ramp):
 * on error sim is unchanged and why says which end or bound is wrong. A ramp
 * in progress is replaced. */
int wg_sim_ramp(wg_sim *sim, int id, const double *from, double target, double dur, char *why,
                size_t whylen);

/* Set the state (nstate values) and phase index; resets period statistics
 * and cancels a ramp. Cheap (no table rebuild) when no ramp was active. */
void wg_sim_set_state(wg_sim *sim, const double *y, uint32_t k, double tau);

/* Capture the run into snap. */
void wg_sim_snapshot(const wg_sim *sim, wg_snapshot *snap);

/* Continue bit-exactly from snap, every field checked as the live path
 * would: WG_ESTATE if its model, stepper or N differ from sim's; the codes
 * of wg_sim_set_params for the parameters (ranges, cosines, stability); for
 * an active ramp (active 0 or 1) those of wg_sim_ramp from ramp.v0 (a
 * rampable parameter, duration, both ends in range and stable), with tau0 in
 * [tau - dur, tau] and the ramped value on the ramp line; WG_EINVAL for
 * k >= N, a state not finite or absurd, tau outside [0, 1e15], |tau_c| >
 * 1e-12 (1 + tau), period > steps, cur.period != period, or period
 * statistics that are not sane (motion a class, impacts >= 0, finite
 * min_xn <= max_xn). On error sim is unchanged and why names the field and
 * what is allowed. */
int wg_sim_restore(wg_sim *sim, const wg_snapshot *snap, char *why, size_t whylen);

/* Back to the static equilibrium at psi = 0, tau = 0, counters cleared;
 * kernel, excitation table and step re-derived from the parameters. */
void wg_sim_reset(wg_sim *sim);

/* Advance n steps, reporting to sink (may be NULL). WG_OK, or
 * WG_ENONFINITE with the state of the last good step kept (the failed step
 * is not applied); *done (may be NULL) receives the steps taken. */
int wg_sim_run(wg_sim *sim, uint64_t n, const wg_sink *sink, uint64_t *done);

/* Advance two distinct sims at once: sim[j] as wg_sim_run(sim[j], n[j],
 * sink[j]) would, to the bit, until either has taken its n[j] steps or
 * failed. While both take plain steps of the same specialisation (the
 * same model, stepper and kind of parameters, whatever their values or N)
 * they run in one loop, where one fills the machine while the other waits
 * on its dependency chain; otherwise in turn. done[j] receives the steps
 * sim[j] took, rc[j] its status (as wg_sim_run's); run the other's rest
 * by another call. */
void wg_sim_run_pair(wg_sim *const sim[2], const uint64_t n[2], const wg_sink *const sink[2],
                     uint64_t done[2], int rc[2]);

/* Advance L (1..8) distinct sims at once, sim[j] as wg_sim_run(sim[j],
 * n[j], sink[j]) would, to the bit, until one has taken its n[j] steps or
 * failed: wg_sim_run_pair for more sims. While all take plain steps of the
 * same specialisation they run in one loop, one sim per vector lane, where
 * the CPU has AVX2 or AVX-512 (else, and whenever one cannot, each in
 * turn). More than 8: none runs, each rc[j] is WG_EINVAL; L < 1: nothing. */
void wg_sim_run_batch(int L, wg_sim *const sim[], const uint64_t n[], const wg_sink *const sink[],
                      uint64_t done[], int rc[]);

/* Current excitation phase psi in [0, 2 pi) and meshing frequency. */
double wg_sim_psi(const wg_sim *sim);
double wg_sim_omega(const wg_sim *sim);

/* Length in tau of a step at the current omega, 2 pi / (omega N) (during
 * an omega ramp, of a step at the present value). */
double wg_sim_step_tau(const wg_sim *sim);

/* The mesh displacement x_n at the current state, as the contact logic
 * computed it at the end of the last step (cheap: no excitation call). */
double wg_sim_xn(const wg_sim *sim);

/* Outputs (x_n, x_n', F, bearing forces) at the current state. */
void wg_sim_outputs(const wg_sim *sim, wg_outputs *o);

/* theta1, theta2 (rad, [0, 2 pi)) at the current state and phase: wg_angles
 * with the run's completed periods (the rigid part is 0 at the start of a
 * run). Also right inside on_step on the step that ends a period, where
 * sim->period does not count that period yet. */
void wg_sim_angles(const wg_sim *sim, double th[2]);

/* Kernel specialisation as text, e.g. "full+bj+b+ka+em" or "torsional+b". */
const char *wg_sim_kernel_name(const wg_sim *sim, char *buf, size_t len);

/* The instruction set its own steps run on: "sse2", "avx2", "avx512" or
 * "avx512vl" (AVX2's form with AVX-512VL's registers; chosen at
 * wg_sim_init: $WG_ISA, else the CPU's; the same bits on each), "baseline"
 * for the printed form's unspecialised step. */
const char *wg_sim_isa_name(const wg_sim *sim);

#endif

/* wg_cont.h - pseudo-arclength continuation of periodic orbits with impacts.
 *
 * A period-n orbit is a fixed point of P^n, the rk4-event Poincare map
 * (wg_shoot.h); Newton uses its variational monodromy M, and the derivative
 * in the continued parameter by central differences. The branch is
 * followed in (state, parameter) with an adaptive pseudo-arclength step,
 * so it turns at folds and follows unstable parts. Between two points the
 * test functions are watched and every sign change is located on the
 * branch (secant with bisection safeguard on the arclength):
 *   fold              the tangent's parameter component changes sign
 *                     (a real multiplier through +1);
 *   period doubling   a real multiplier through -1;
 *   torus             a complex pair through the unit circle;
 *   branch point      a real multiplier through +1 without a fold;
 *   grazing           the minimum or maximum of a contact coordinate over
 *                     the orbit (x_n, or a bearing's) reaches +c or -c.
 * At a period doubling the run can switch onto the period-2n branch.
 * The library prints nothing: points, bifurcations and notes (Newton
 * failures, step halvings, why a branch ended) go to callbacks. */
#ifndef WG_CONT_H
#define WG_CONT_H

#include <signal.h>
#include "wg_shoot.h"

enum wg_bif_kind { WG_BIF_FOLD, WG_BIF_PD, WG_BIF_TORUS, WG_BIF_GRAZING, WG_BIF_BP, WG_NBIF };

/* Ranges of the tolerances (wg_cont_check). The residual is a state's, O(1)
 * in b_c: at most 1e-6 (an orbit rougher than that misplaces the tests'
 * zeros: a tolerance of 1e300 took the first guess as the orbit, lost
 * both tori and put the grazing elsewhere); the bracket is in parameter
 * units: at most 1e-5, a hundredth of the first step (a coarser location
 * is no better than a fine sweep's grid). Both at least WG_TOL_MIN. */
#define WG_CONT_TOL_MAX 1e-6
#define WG_CONT_LOC_TOL_MAX 1e-5

/* Settings of a run. Steps are pseudo-arclength in the norm
 * sqrt(dparam^2 + |dstate|^2 / dim): parameter units, the state by its RMS. */
typedef struct wg_cont_opts {
    int model;          /* enum wg_model_kind (consistent only) */
    int param;          /* continued parameter, wg_param_id */
    double from, to;    /* range (either order); a branch ends where it leaves it */
    double start;       /* first point, inside the range */
    int period;         /* n of the first branch, 1..WG_SHOOT_NMAX */
    int steps;          /* N per mesh period, raised to 1.25x the RK4 limit over the range */
    int transient;      /* periods run from y0 at `start` before the first Newton */
    double ds0, ds_min, ds_max; /* first, smallest and largest step */
    double tol;         /* Newton: max-norm residual |P^n(x) - x|,
                           WG_TOL_MIN..WG_CONT_TOL_MAX */
    double loc_tol;     /* location: arclength bracket (bounds the parameter bracket),
                           WG_TOL_MIN..WG_CONT_LOC_TOL_MAX */
    int max_points;     /* per branch */
    int depth;          /* period-doubling branch switches (0: none) */
    int monodromy;      /* enum wg_monodromy used by Newton and for the multipliers */
} wg_cont_opts;

/* One point of a branch. */
typedef struct wg_cont_point {
    int branch, index, period;
    double value;                     /* the continued parameter */
    double y[WG_NSTATE_MAX];          /* Poincare state (psi = 0) */
    double xnsec[WG_SHOOT_NMAX];      /* x_n at the n sections of the orbit */
    double qmin[WG_NCONTACT], qmax[WG_NCONTACT]; /* contact extremes over the orbit */
    int ncross[WG_NCONTACT];          /* dead-zone crossings of each contact over the orbit */
    int stable;                       /* every multiplier inside the unit circle */
    int nmult;
    double mre[WG_NSTATE_MAX], mim[WG_NSTATE_MAX]; /* multipliers, largest |mu| first */
    double dvalue;                    /* tangent's parameter component (unit tangent) */
    double ds;                        /* step that reached this point */
    int newton_its;
    double resid;                     /* |P^n(x) - x|, max norm */
} wg_cont_point;

/* A located bifurcation. */
typedef struct wg_bif {
    int kind;                         /* enum wg_bif_kind */
    int branch, period;
    double value;
    double y[WG_NSTATE_MAX];
    double mu_re, mu_im;              /* the multiplier that crossed (grazing: the largest) */
    double xn, min_xn, max_xn;        /* x_n at the section, its extremes over the orbit */
    int contact;                      /* grazing: enum wg_contact, else -1 */
    int side;                         /* grazing: the threshold +c (+1) or -c (-1) */
    int extreme;                      /* grazing: of the minimum (-1) or maximum (+1) */
    double bracket;                   /* parameter bracket left by the location */
    int evals;                        /* corrector solves the location took */
} wg_bif;

/* Note codes. */
enum wg_cont_note {
    WG_NOTE_NEWTON,     /* Newton failed: the step is halved */
    WG_NOTE_ANGLE,      /* the tangent turned too far: the step is halved */
    WG_NOTE_LOCATE,     /* a location did not converge (the bracket is reported) */
    WG_NOTE_SWITCH,     /* branch switching at a period doubling failed */
    WG_NOTE_END         /* a branch ended (msg says why) */
};

typedef struct wg_cont_sink {
    void *ctx;
    void (*on_point)(void *ctx, const wg_cont_point *pt);
    void (*on_bif)(void *ctx, const wg_bif *b);
    void (*on_note)(void *ctx, int code, int branch, double value, const char *msg);
} wg_cont_sink;

/* Names: "fold", "period_doubling", "torus", "grazing", "branch_point". */
const char *wg_bif_name(int kind);

/* Defaults: omega, period 1, N 256, transient 500, ds 1e-3 (min 1e-7,
 * max 0.01), tol 1e-10, loc_tol 1e-9, 5000 points, depth 1, monodromy of
 * the map. */
void wg_cont_opts_default(wg_cont_opts *o);

/* WG_OK if wg_cont_run takes o; else WG_EUNSUPPORTED, WG_EUNKNOWN, WG_ERANGE
 * or WG_EINVAL with why ("need a range, got omega = 1 twice") and *field
 * (if field is not NULL) naming the member of wg_cont_opts at fault
 * ("from", "to", "start", "ds_max", ...; "range" for from and to
 * together), so a program can say it in the
 * words of its own options. */
int wg_cont_check(const wg_cont_opts *o, const char **field, char *why, size_t whylen);

/* Steps per period a run of o over its range uses for parameters p. */
int wg_cont_steps(const wg_params *p, const wg_cont_opts *o);

/* Continue from the orbit reached from y0 (nstate values at psi = 0) at
 * param = o->start, towards o->to, and (when start lies inside the range)
 * towards o->from as a second branch; then the switched branches. Stops
 * early when *stop becomes non-zero (stop may be NULL): what was reported
 * stands. WG_OK; WG_EINVAL / WG_ERANGE / WG_EUNSUPPORTED (options, model)
 * or the first Newton failing, with why. */
int wg_cont_run(const wg_params *p, const double *y0, const wg_cont_opts *o,
                const wg_cont_sink *sink, volatile sig_atomic_t *stop, char *why,
                size_t whylen);

#endif

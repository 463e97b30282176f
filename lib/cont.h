/* cont.h - shared between wg_cont.c (branches: corrector, tangent, steps,
 * switching) and wg_cont_bif.c (test functions, location) only. */
#ifndef WG_CONT_INTERNAL_H
#define WG_CONT_INTERNAL_H

#include "wormgear/wg_cont.h"

enum { UMAX = WG_NSTATE_MAX + 1, QMAX = 64 };

/* A converged point: unknowns u (active coordinates, then the parameter),
 * its unit tangent, dP/dparam, the map evaluated there, the multipliers. */
typedef struct sol {
    int n;                       /* period */
    double u[UMAX], t[UMAX];
    double pl[WG_NSTATE_MAX];
    wg_orbit orb;
    double wr[WG_NSTATE_MAX], wi[WG_NSTATE_MAX];
    int its;
    double resid;
} sol;

/* A period doubling waiting for its branch switch. */
typedef struct pdq {
    double u[UMAX], v[WG_NSTATE_MAX]; /* the point and the -1 eigenvector */
    double bracket;                   /* its location's parameter bracket */
    int n, depth, done;
} pdq;

/* One run. */
typedef struct cont {
    wg_sim sim;
    wg_params p;
    const wg_cont_opts *o;
    const wg_cont_sink *sink;
    volatile sig_atomic_t *stop;
    double lo, hi;                /* parameter range */
    int d, idx[WG_NSTATE_MAX];    /* active coordinates */
    double base[WG_NSTATE_MAX];   /* full-state template (inactive entries) */
    double th;                    /* weight of the state in the norm: 1/d */
    int nbranch;
    int has_ref;                  /* the branch's period is even: ref is set */
    double ref[WG_NSTATE_MAX];    /* direction of P^(n/2)(x) - x at its first point */
    pdq q[QMAX];
    int nq;
    char *why;
    size_t whylen;
} cont;

/* Weighted dot product of two (state, parameter) vectors. */
double cont_wdot(const cont *c, const double *a, const double *b);

/* Newton from up with the constraint a . (u - up) = 0 (a already weighted);
 * on WG_OK *s holds the point with its map, dP/dparam and residual. */
int cont_correct(cont *c, int n, const double *up, const double *a, sol *s);

/* Unit tangent of s oriented along tprev, and its multipliers. */
int cont_finish(cont *c, sol *s, const double *tprev);

/* P^(n/2)(x) - x over the active coordinates (n even), and its max norm. */
double cont_half_gap(const cont *c, const sol *s, double *gap);

/* Report a note through the sink. */
void cont_note(const cont *c, int code, int branch, double value, const char *fmt, ...)
    __attribute__((format(printf, 5, 6)));

/* Located bifurcations between consecutive points A and B of branch id
 * (B at arclength sb along A's tangent): reported to the sink in arclength
 * order; period doublings queued for switching when depth > 0. Returns 1
 * if a branch point was found (a switched branch then ends there). */
int cont_detect(cont *c, const sol *A, const sol *B, double sb, int id, int depth);

#endif

/* internal.h - shared between the library's own files (and its white-box tests) only. */
#ifndef WG_INTERNAL_H
#define WG_INTERNAL_H

#include "wormgear/wg_sim.h"

#define TWO_PI 6.283185307179586

/* One RK4 step of a specialised kernel: y0 -> y1 over h, with the
 * excitation at the step's start, middle and end (e[0..2]). */
typedef void (*wg_kernel_fn)(const double *restrict y0, double *restrict y1,
                             const void *restrict kc, const wg_exc *restrict e, double h);

/* Coefficients the kernels read (derived from wg_params at each change). */
typedef struct wg_kcoef {
    double c[7];      /* mesh direction: x_n = c . q (+ s) */
    double m[7];      /* mass-ratio weights of F on each DOF */
    double k[6];      /* bearing stiffness */
    double d[7];      /* 2 xi per DOF (s: 2 xi_g) */
    double dp;        /* 2 xi_p */
    double b, bj;     /* dead zones */
    double w[7], zc[7]; /* zone-locked g: g = w x - zc (rk4-event) */
    double rot[3][2];   /* cos, sin of phi1, phi2, phi: excitation by rotation */
    double cd[6], ck[6]; /* c_i d_i, c_i k_i */
    double M;           /* 1 + sum c_i m_i, summed in index order */
} wg_kcoef;

/* ---- a trace of the rk4-event splits (read by wg_shoot.c) ------------------ */

enum { CT_MAX_SPLITS = 8 }; /* located crossings per step (rk4-event) */

/* One located crossing inside a step: the state integrated up to t_state,
 * the contacts that switched there (from zone to zone), the contact rates at
 * that state; the rest of the step starts again at t_next (= t_state unless
 * the crossing's Newton refinement ran out of iterations). */
typedef struct ct_split {
    double t_state, t_next;
    double yc[WG_NSTATE_MAX];
    double vc[WG_NCONTACT];
    int n;
    int contact[WG_NCONTACT], zone_from[WG_NCONTACT], zone_to[WG_NCONTACT];
} ct_split;

/* The splits of one step, in time order. */
typedef struct ct_trace {
    int n;
    ct_split sp[CT_MAX_SPLITS];
} ct_trace;

/* ---- the cubic Hermite of a coordinate over one step (wg_herm.c) ----------- */

/* t in [0, 1] over the step */
typedef struct herm {
    double q0, q1, d0, d1; /* values and h-scaled rates at the ends */
} herm;

/* dH/dt at t (per unit t: divide by the step for a rate) */
double herm_der(const herm *H, double t);

/* The root of H(t) = c in [0, 1], given H(0) - c and H(1) - c of opposite
 * signs (to ~1e-15 in t). */
double herm_root(const herm *H, double c);

/* Extrema of H on [0, 1] (including the ends). */
double herm_min(const herm *H);
double herm_max(const herm *H);

/* A step of length h from (q0, v0) to (q1, v1) whose rate changes sign has
 * an extremum inside: lower *mn to the minimum (v0 < 0) or raise *mx to the
 * maximum. The ends are the caller's. */
void herm_turn(double q0, double q1, double v0, double v1, double h, double *mn, double *mx);

/* A run of plain steps in one kernel call (constant parameters, no ramp,
 * no per-step callback), the state kept in registers between steps. Each
 * step does what wg_sim_run's general step does when no contact changes
 * zone, in the same arithmetic: the kernel, the mesh contact in ct_contacts'
 * order, Kahan time, the period's min/max x_n (with herm_turn where x_n'
 * turns round), k + 1. The run stops after a step that completes a period
 * (k reaches N: the caller counts the period) and before a step that
 * changes a contact's zone (contact j stays when lo[j] <= x <= hi[j]) or
 * that might bring the state near `fin` (every |y_i| must stay below
 * fin / 16, so their sum stays below fin); the caller takes that step, from
 * the state the run computed for it (`trial`). */
typedef struct wg_krun {
    double y[WG_NSTATE_MAX];     /* in/out: state */
    double xn, dxn;              /* in/out: mesh contact of y */
    double tau, tau_c;           /* in/out: Kahan time */
    double min_xn, max_xn;       /* in/out: the period's statistics */
    uint32_t k, N;               /* in/out: phase index (N: a period ended); steps per period */
    double h, fin;               /* step; sum |y| must stay below fin */
    const wg_exc *table;         /* 2N+1 half-step excitation entries */
    double lo[WG_NCONTACT], hi[WG_NCONTACT]; /* zone bounds per contact */
    double *trial;               /* out: the step the run stopped before, as the kernel */
    int has_trial;               /*      writes it into y1 (1: written) */
} wg_krun;

/* At most n plain steps of r (above); returns the number taken. */
typedef uint64_t (*wg_krun_fn)(const void *restrict kc, wg_krun *restrict r, uint64_t n);

/* Two runs (above) of the same specialisation in one loop, each step as
 * the single run takes it, until either would stop: at most na plain steps
 * of ra and nb of rb; m[0], m[1] the numbers taken. */
typedef void (*wg_krun2_fn)(const void *restrict ka, wg_krun *restrict ra, uint64_t na,
                            const void *restrict kb, wg_krun *restrict rb, uint64_t nb,
                            uint64_t m[2]);

/* Up to KB_LANES runs of the same specialisation in one loop, one run per
 * vector lane (AVX2 and AVX-512): every lane does a single run's
 * arithmetic in the same order, so each run's bits are wg_krun's. The lanes sit apart in
 * the batch (one row of KB_LANES per quantity); kb_load and kb_store
 * (wg_sim_run.c) move one run in and out. The loop stops once a lane in
 * `active` stops: it refused a step (its `trial` written, has_trial set),
 * or it took the steps it may (lim_steps: the steps asked for, or to the
 * period's end). The other lanes take the step a lane refused, then stop
 * too; ran[l] is what lane l took (lim_steps and ep move on by it). Lanes
 * outside `active` compute and are ignored; on AVX2 (two 4-wide groups)
 * the upper group is not computed while none of its lanes is active, and
 * its ran[l] is 0. */
enum { KB_LANES = 8 };
typedef struct wg_kbatch {
    /* each lane's run: state, mesh contact, Kahan time, period extrema */
    double q[6][KB_LANES], v[6][KB_LANES], s[KB_LANES], vs[KB_LANES];
    double xn[KB_LANES], dxn[KB_LANES], tau[KB_LANES], tc[KB_LANES];
    double mn[KB_LANES], mx[KB_LANES];
    /* each lane's constants (wg_kcoef) and zone bounds (fbound) */
    double c[6][KB_LANES], m[6][KB_LANES], k[6][KB_LANES], nd[6][KB_LANES]; /* nd: -d */
    double cd[6][KB_LANES], ck[6][KB_LANES], w[6][KB_LANES], zc[6][KB_LANES];
    double bj[KB_LANES], M[KB_LANES], ds[KB_LANES], dp[KB_LANES], b[KB_LANES];
    double w0[KB_LANES], zc0[KB_LANES], h[KB_LANES];
    double lo[6][KB_LANES], hi[6][KB_LANES], lim[KB_LANES], mlo[KB_LANES], mhi[KB_LANES];
    const wg_exc *ep[KB_LANES];   /* in/out: the lane's &table[2k] */
    uint64_t lim_steps[KB_LANES]; /* in/out: steps the lane may still take */
    uint64_t ran[KB_LANES];       /* out: steps each lane took in the last loop */
    double *trial[KB_LANES];      /* where a refused step goes (wg_krun.trial) */
    unsigned active;              /* lanes whose stops count */
    unsigned refused;             /* out: lanes that refused the step after `ran` */
} __attribute__((aligned(64))) wg_kbatch;

/* Run the batch until a lane in `active` stops; returns the stopped lanes
 * (a refused one refused the step after its ran[l]). */
typedef unsigned (*wg_kbatch_fn)(wg_kbatch *restrict B);

/* The private part of a wg_sim (allocated by wg_sim_init with the table). */
typedef struct wg_sim_core {
    wg_kcoef kc;
    wg_kernel_fn kernel;  /* specialised kernel for the current parameters */
    wg_krun_fn krun;      /* its run of plain steps (NULL: printed form) */
    unsigned kflags;      /* which specialisation (for reports) */
    int isa;              /* instruction set of its batched loop's kernels (KISA_*) */
    int isa_one;          /* ... of its own: kernel, krun, a pair's (kernel_isa_one) */
    int wrap_pending;     /* 1 from psi wrapping to 0 until period counts it (on_step) */
    wg_exc *table;        /* 2N+1 excitation entries at half steps */
    double (*trig)[4];    /* 2N+1: model_exc_trig at the table's phases, for */
    double trig_phi[3];   /* ... these phi1, phi2, phi (trig_set: computed) */
    int trig_set;
    uint64_t exc_gen;     /* bumped by every sim_coefficients and sim_build_table */
    struct ct_psi0 *psi0; /* N: cos, sin of 2 pi k / N for ct_split_step, once set */
    wg_params hkey;       /* parameters hkey_hmax was computed for (cache) */
    double hkey_hmax;     /* 0: no cached value */
    /* contact bookkeeping at the end of the last step */
    int zone[WG_NCONTACT];
    double zlo[WG_NCONTACT], zhi[WG_NCONTACT]; /* contact j stays in its zone iff zlo <= x <= zhi */
    double q[WG_NCONTACT], v[WG_NCONTACT];
    wg_period cur;        /* statistics of the period in progress */
    wg_period last;       /* statistics of the last completed period */
    ct_trace *trace;      /* non-NULL: ct_split_step records its splits here */
    uint64_t batched;     /* steps taken in a batched loop (wg_sim_run_batch) */
} wg_sim_core;

/* wg_exc_eval in two parts: the libm part at phase psi, t = cos(psi +
 * phi1), cos(psi + phi2), sin(psi + phi2), cos(psi + phi), which an omega
 * or an amplitude leaves as it is; and the excitation from t, the same bits
 * as wg_exc_eval's. */
void model_exc_trig(const wg_params *p, double psi, double t[4]);
void model_exc_of_trig(const wg_params *p, const double t[4], double omega, wg_exc *e);

/* Mesh direction c (x_n = c . q) and force weights m (mass ratio times c). */
void model_mesh_vectors(int model, const wg_params *p, double c[7], double m[7]);

/* wg_rk4_hmax the slow way (the reference its tests compare with, and the
 * fallback if QR fails): bisection on h of the spectral radius of the RK4
 * step matrix R(hA), from norms of its repeated squares (3-5 ms). */
double model_rk4_hmax_bisect(const wg_params *p);

/* Kernel specialisation bits. */
enum {
    KF_EM = 1u << 0,   /* e_m != 0: transmission error terms */
    KF_KA = 1u << 1,   /* k_a != 0: time-varying stiffness */
    KF_MB = 1u << 2,   /* b != 0: mesh dead zone */
    KF_BJ = 1u << 3,   /* b_j != 0: bearing dead zones */
    KF_LOCK = 1u << 4, /* zone-locked dead zones (rk4-event) */
    KF_BEAR = 1u << 5, /* bearings move (else torsional: s only) */
    KF_NKERNEL = 64
};

/* Instruction sets the kernels are built for; every one gives the same
 * bits (kern_tmpl.h). KISA_AVX512VL is AVX2's 4-wide form compiled with
 * AVX-512VL: 32 vector registers instead of 16, so the steps spill less. */
enum { KISA_SSE2, KISA_AVX2, KISA_AVX512, KISA_AVX512VL, KISA_N };

/* Name ("sse2", "avx2", "avx512", "avx512vl"); whether this CPU runs it;
 * the one a new wg_sim's batched loop uses: $WG_ISA if it names a
 * supported set, else the widest, AVX-512 (its own kernels:
 * kernel_isa_one). */
const char *kernel_isa_name(int isa);
int kernel_isa_supported(int isa);
int kernel_isa_choose(void);

/* The set for one run's own kernels (a step, its run of plain steps, two
 * runs paired) where isa is the one kernel_isa_choose gave: on an Intel
 * CPU, AVX2's 4-wide form in place of AVX-512 (with AVX-512VL's registers
 * where the CPU has them) unless $WG_ISA names avx512, else isa. A run
 * fills six of a 512-bit vector's eight lanes, and Intel's cores run
 * 512-bit operations on two vector ports instead of three: on the Xeon
 * (Emerald Rapids) of the twentieth session the AVX2 run loop took 41-46 ns
 * a step against 48-51 (bench_gsl, table3 no impact), while a batch of
 * eight runs, one a lane, still gained from AVX-512 (the 21-row map
 * 6.0-6.2 s against 8.4-8.8 s with WG_ISA=avx2); on that of the
 * twenty-first, AVX-512VL's registers took the rk4-event step from 42.1-46.0
 * to 38.0-39.2 ns. On the AMD EPYC of the first sessions the AVX-512 run loop was
 * the quicker, 45 against 49 ns (docs/performance.md, "A run's own kernels
 * on AVX2 on an Intel CPU" and "AVX2's form with AVX-512VL's registers"). */
int kernel_isa_one(int isa);

/* The 4-wide set, for a CPU with AVX2 (callers check): AVX2's form with
 * AVX-512VL's registers if the CPU has AVX-512VL, else AVX2's. */
int kernel_isa_4wide(void);

/* The consistent-form kernel for a set of KF_* bits and an instruction set;
 * kc is a wg_kcoef. */
wg_kernel_fn kernel_select(unsigned kflags, int isa);

/* The run function for a set of KF_* bits and an instruction set. */
wg_krun_fn krun_select(unsigned kflags, int isa);

/* The paired run for a set of KF_* bits and an instruction set (NULL: the
 * torsional path, which is not paired). */
wg_krun2_fn krun2_select(unsigned kflags, int isa);

/* The batched run of L lanes for a set of KF_* bits and an instruction
 * set (NULL: the torsional path, or the baseline, which has none). On
 * AVX-512 a batch of four or fewer takes the 4-wide loop (kernel_isa_4wide):
 * one 4-wide vector a quantity costs less than an 8-wide one, with the
 * same bits. */
wg_kbatch_fn kbatch_select(unsigned kflags, int isa, int L);

/* RK4 step of the printed form (unspecialised, for comparison); kc is the
 * wg_params. */
void kernel_printed(const double *restrict y0, double *restrict y1, const void *restrict kc,
                    const wg_exc *restrict e, double h);

/* Solve B z = r in place (B, n x n row-major, destroyed; z returned in r) by
 * LU with partial pivoting (wg_floquet.c). WG_OK, or WG_ERANGE if B is
 * singular to working precision. */
int la_solve(int n, double *a, double *r);

/* min/max without libm's NaN rules (strict C11 keeps fmin/fmax out of line;
 * the values here are finite). */
static inline double dmin(double a, double b) { return a < b ? a : b; }
static inline double dmax(double a, double b) { return a > b ? a : b; }

/* A run's bounds (kern_tmpl.h's fbound, a wg_kbatch lane): lim = fin / 16,
 * which every |y_i| must stay below, and the bearings' zone bounds clipped
 * to it, into lo6 and hi6; returns lim. */
static inline double krun_bounds(const wg_krun *r, double lo6[6], double hi6[6])
{
    const double lim = r->fin / 16;
    for (int j = 0; j < 6; j++) {
        lo6[j] = dmax(r->lo[1 + j], -lim);
        hi6[j] = dmin(r->hi[1 + j], lim);
    }
    return lim;
}

/* ---- the sim's derived state (wg_sim.c), read by the step loop (wg_sim_run.c) */

/* The kernel constants, the contacts' locks and the kernel choice from
 * s->p: after any change of parameters. */
void sim_coefficients(wg_sim *s);

/* The excitation table and h from s->p (omega, the excitation terms). */
void sim_build_table(wg_sim *s);

/* A new period begins at x_n = xn with the mesh in its current zone. */
void sim_period_start(wg_sim *s, double xn);

/* ---- snapshot fields (wg_sim_check.c) -------------------------------------- */

#define ABSURD 1e9 /* |sum of state| beyond this is a blow-up */

/* Finite and not absurd: one sum catches NaN, Inf and runaway values. */
int sim_finite_state(const double *y, int n);

/* vsnprintf into why, then rc. */
int sim_refuse(int rc, char *why, size_t whylen, const char *fmt, ...)
    __attribute__((format(printf, 4, 5)));

/* A snapshot's phase, state, time, counters and period statistics: WG_OK,
 * or WG_EINVAL with why naming the field and what is allowed. */
int sim_snapshot_fields_ok(const wg_snapshot *w, char *why, size_t whylen);

/* An active ramp's start and current value agree with its line: WG_OK or
 * WG_EINVAL with why. */
int sim_ramp_now_ok(const wg_snapshot *w, char *why, size_t whylen);

/* ---- contacts (wg_contact.c) ---------------------------------------------- */

/* Phase within one step: psi(t), omega(t) for 0 <= t <= h, piecewise
 * quadratic while an omega ramp runs and linear after it ends (at t = tr). */
typedef struct phase {
    double psi0, om0, r, tr, om1;
} phase;

/* Excitation at sub-step time t (one sin/cos of psi, phases by rotation). */
void ct_exc_at(const wg_sim *s, const phase *ph, double t, wg_exc *e);

/* The same from c0 = cos psi0 and s0 = sin psi0, psi(t) by rotation
 * (ct_split_step's: no libm call while psi(t) - psi0 <= 1/4). */
wg_exc ct_exc_rot(const wg_sim *s, const phase *ph, double c0, double s0, double t);

/* Zone of x against a dead zone +-c: +1 above, -1 below, 0 inside. */
static inline int ct_zone(double x, double c) { return (x > c) - (x < -c); }

/* Dead-zone half width of a contact: b for the mesh, b_j for a bearing. */
static inline double ct_threshold(const wg_sim *s, int contact)
{
    return contact == WG_C_MESH ? s->p.v[WG_P_B] : s->p.v[WG_P_B_J];
}

/* Contacts that can move: all seven, or the mesh only on the torsional path. */
static inline int ct_ncontacts(const wg_sim *s)
{
    return (s->core->kflags & KF_BEAR) || s->cfg.model == WG_MODEL_PRINTED ? WG_NCONTACT : 1;
}

/* Contact coordinates and rates at state y with excitation e (the mesh
 * only, when the bearings are rigid). */
static inline void ct_contacts(const wg_sim *s, const double *y, const wg_exc *e, double *q, double *v)
{
    int nd = s->nstate / 2;
    const double *c = s->core->kc.c;
    double x = -e->te, dx = e->dte;
    if (!(s->core->kflags & KF_BEAR) && s->cfg.model == WG_MODEL_CONSISTENT) {
        q[0] = x + y[6];
        v[0] = dx + y[13];
        return;
    }
    for (int i = 0; i < 6; i++) {
        x += c[i] * y[i];
        dx += c[i] * y[nd + i];
        q[i + 1] = y[i];
        v[i + 1] = y[nd + i];
    }
    if (s->cfg.model == WG_MODEL_PRINTED) {
        x += y[6] + y[7];
        dx += y[14] + y[15];
    } else {
        x += y[6];
        dx += y[13];
    }
    q[0] = x;
    v[0] = dx;
}

/* The contacts (bit j of the first nc) whose coordinate q[j] lies outside
 * its zone's bounds (zlo, zhi, kept by ct_set_lock): every one whose
 * ct_zone differs from its zone, and a NaN's (lib.test_model). */
static inline unsigned ct_left(const wg_sim *s, const double *q, int nc)
{
    unsigned m = 0;
    for (int j = 0; j < nc; j++)
        m |= (unsigned)!((s->core->zlo[j] <= q[j]) & (q[j] <= s->core->zhi[j])) << j;
    return m;
}

/* Lock contact's dead zone on `zone` (g = w x - zc) for the locked kernels,
 * and set the bounds of that zone (zlo, zhi) for the runs of plain steps.
 * Called whenever a zone or a threshold changes. */
void ct_set_lock(wg_sim *s, int contact, int zone);

/* The contact events of one step, sorted by the caller. */
enum { MAX_STEP_EVENTS = 64 };
typedef struct evbuf {
    int n;
    wg_event ev[MAX_STEP_EVENTS];
} evbuf;

/* Interpolate the crossings of contact j from zone z0 to z1 over a piece
 * [t0, t0 + len] of the step. */
void ct_interpolate(const wg_sim *s, evbuf *b, int j, int z0, int z1, const herm *H, double t0,
                    double len);

/* The cosine and sine of psi0 = 2 pi k / N that ct_split_step rotates
 * from at step k (in an omega ramp too): computed at the first split step at k,
 * kept for the next (a periodic orbit splits at the same k every period).
 * They depend on k and N only, so no change of parameters stales them.
 * Outside a ramp, also the excitation by rotation at the step's start and
 * end (e0, eh), which the parameters do stale: valid while gen is the
 * core's exc_gen. */
typedef struct ct_psi0 {
    double c, s;
    int set;
    uint64_t gen;
    wg_exc e0, eh;
} ct_psi0;

/* rk4-event: integrate [0, h] from y0 into y1 with the kinked contacts'
 * zones locked between located crossings (y1 holds the unsplit step on
 * entry); appends events, leaves s->zone as at the end of the step. */
void ct_split_step(wg_sim *s, const phase *ph, const double *y0, double *y1, double h,
                   evbuf *b);

#endif

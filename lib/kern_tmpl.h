/* kern_tmpl.h - the specialised RK4 steps of the consistent form, as a
 * template instantiated once per instruction set (wg_kernel*.c):
 *   KW     lanes per bearing vector: 2 (SSE2), 4 (AVX2, and AVX2's form
 *          with AVX-512VL's registers) or 8 (AVX-512);
 *   KSUF   suffix of the tables this defines, kern_tab_KSUF and
 *          krun_tab_KSUF (64 entries each, indexed by the KF_* bits), and
 *          krun2_tab_KSUF (the full path's 32, indexed by the other bits).
 *
 * One generic step, always inlined, instantiated for every combination of
 * the KF_* bits; the compiler removes the terms a scene does not need. The
 * excitation comes in as three entries (stage 1, stages 2-3, stage 4), so
 * the kernels call no libm. Dead zones are branch-free (min/max), or in
 * zone-locked form g = w x - zc for the event-splitting stepper.
 *
 * Every width does the same roundings in the same order, so the three
 * instruction sets give the same bits (test_model checks it): the six
 * bearings sit in NB = 6/KW vectors (lanes past the sixth are zero and
 * stay zero), every bearing operation is lane-wise, and the one sum across
 * bearings is always ((x1 + z1) + y2) + ((y1 + x2) + z2) (hsumb). No FMA
 * contraction: the build is ISO C11, where GCC keeps a*b + c two roundings.
 *
 * Full path: the mesh coordinate is carried as scalars through the stages,
 * using linearity: with X = c.q and V = c.v (s included),
 *   X_{j+1} = X_0 + a V_j,   V_{j+1} = V_0 + a (P_j - M F_j),
 * where P_j = sum_i c_i (-d_i v_i - k_i g_i) - d_s v_s + f is the part of
 * c.acc that does not depend on F, and M = c.m + 1. P_j is computed
 * alongside F_j, so the F -> F dependency chain per stage is a handful of
 * operations instead of a 7-term dot product. */
#include "internal.h"

#include <math.h>
#if defined(__SSE2__)
#include <immintrin.h>
#endif

#define INLINE static inline __attribute__((always_inline))
#define NB ((6 + KW - 1) / KW)
#define KCAT2(a, b) a##_##b
#define KCAT(a, b) KCAT2(a, b)

typedef double v2d __attribute__((vector_size(16)));
typedef double vb __attribute__((vector_size(8 * KW)));
typedef long long vbi __attribute__((vector_size(8 * KW)));

INLINE double dz(double x, double c)
{
    double t = x < c ? x : c;
    t = t > -c ? t : -c;
    return x - t;
}

INLINE vb vsplat(double x)
{
#if KW == 4 /* one vbroadcastsd (GCC builds the generic form from two shuffles) */
    return (vb)_mm256_broadcastsd_pd(_mm_set_sd(x));
#else
    vb r;
    for (int l = 0; l < KW; l++)
        r[l] = x;
    return r;
#endif
}

/* Bearing vector b from a[0..5] (lanes past the sixth: zero), and back. */
INLINE vb vload6(const double *restrict a, int b)
{
    vb r;
#if KW == 2
    __builtin_memcpy(&r, &a[2 * b], sizeof r);
#elif KW == 4
    if (b == 0)
        __builtin_memcpy(&r, a, sizeof r);
    else
        r = (vb)_mm256_zextpd128_pd256(_mm_loadu_pd(&a[4]));
#else
    (void)b;
    r = (vb)_mm512_maskz_loadu_pd(0x3f, a);
#endif
    return r;
}

INLINE void vstore6(double *restrict a, int b, vb v)
{
#if KW == 2
    __builtin_memcpy(&a[2 * b], &v, sizeof v);
#elif KW == 4
    if (b == 0)
        __builtin_memcpy(a, &v, sizeof v);
    else
        _mm_storeu_pd(&a[4], _mm256_castpd256_pd128((__m256d)v));
#else
    (void)b;
    _mm512_mask_storeu_pd(a, 0x3f, (__m512d)v);
#endif
}

/* x - clamp(x, -c, c) lane-wise, as dz(): min(x, c), then max(., 0 - c). */
INLINE vb vdz(vb x, vb c)
{
#if KW == 2 && !defined(__SSE2__)
    return (vb){dz(x[0], c[0]), dz(x[1], c[1])};
#elif KW == 2
    __m128d t = _mm_min_pd((__m128d)x, (__m128d)c);
    t = _mm_max_pd(t, _mm_sub_pd(_mm_setzero_pd(), (__m128d)c));
#elif KW == 4
    __m256d t = _mm256_min_pd((__m256d)x, (__m256d)c);
    t = _mm256_max_pd(t, _mm256_sub_pd(_mm256_setzero_pd(), (__m256d)c));
#else
    __m512d t = _mm512_min_pd((__m512d)x, (__m512d)c);
    t = _mm512_max_pd(t, _mm512_sub_pd(_mm512_setzero_pd(), (__m512d)c));
#endif
#if KW != 2 || defined(__SSE2__)
    return x - (vb)t;
#endif
}

/* The sum over the six bearing lanes of p, always as
 * ((x1 + z1) + y2) + ((y1 + x2) + z2). */
INLINE double hsumb(const vb p[NB])
{
#if KW == 2
    v2d t = p[0] + p[1] + p[2];
#elif KW == 4
    v2d t = (v2d)_mm256_castpd256_pd128((__m256d)p[0]) +
            (v2d)_mm256_extractf128_pd((__m256d)p[0], 1) +
            (v2d)_mm256_castpd256_pd128((__m256d)p[1]);
#else
    /* lanes 2-3 from the low 256 bits (vextractf128) and 4-5 from the high
     * ones (vextractf64x4): on Zen 5 both are quicker on the path than a
     * 512-bit lane shuffle (bench_pair's hsumb link) */
    __m256d lo = _mm512_castpd512_pd256((__m512d)p[0]);
    v2d t = (v2d)_mm256_castpd256_pd128(lo) + (v2d)_mm256_extractf128_pd(lo, 1) +
            (v2d)_mm256_castpd256_pd128(_mm512_extractf64x4_pd((__m512d)p[0], 1));
#endif
    return t[0] + t[1];
}

INLINE vb vabs(vb x) { return (vb)((vbi)x & ~(vbi)vsplat(-0.0)); }

/* Every lane of a comparison mask true. */
INLINE int vall(vbi m)
{
    long long all = m[0];
    for (int l = 1; l < KW; l++)
        all &= m[l];
    return all != 0;
}

/* Per-kernel constants, loaded once per step (or per run of steps). */
typedef struct vconst {
    vb c[NB], m[NB], k[NB], d[NB], cd[NB], ck[NB], w[NB], zc[NB], bj;
    double M, ds;
} vconst;

INLINE void vconst_load(vconst *V, const wg_kcoef *restrict K)
{
#pragma GCC unroll 3
    for (int b = 0; b < NB; b++) {
        V->c[b] = vload6(K->c, b);
        V->m[b] = vload6(K->m, b);
        V->k[b] = vload6(K->k, b);
        V->d[b] = vload6(K->d, b);
        V->cd[b] = vload6(K->cd, b);
        V->ck[b] = vload6(K->ck, b);
        V->w[b] = vload6(&K->w[1], b);
        V->zc[b] = vload6(&K->zc[1], b);
    }
    V->bj = vsplat(K->bj);
    V->M = K->M;
    V->ds = K->d[6];
}

/* The dynamic mesh force F = 2 xi_p x_n' + k_p g(x_n; b) from the mesh
 * scalars X, V before the transmission error (MODEL.md s2): the full and the
 * torsional stages share it. */
INLINE double mesh_force(const wg_kcoef *restrict K, const wg_exc *restrict e, double X,
                         double V, const int LOCK, const int MB, const int KA, const int EM)
{
    double xn = X, dxn = V;
    if (EM) {
        xn -= e->te;
        dxn += e->dte;
    }
    double g = !MB ? xn : LOCK ? K->w[0] * xn - K->zc[0] : dz(xn, K->b);
    return K->dp * dxn + (KA ? e->kp * g : g);
}

/* One stage: from bearing positions q, velocities v, s' vs and the mesh
 * scalars X, V, the accelerations acc, s'' as6 and c.acc. */
INLINE void stage_full(const vconst *restrict C, const wg_kcoef *restrict K,
                       const wg_exc *restrict e, const vb q[NB], const vb v[NB], double vs,
                       double X, double V, vb acc[NB], double *as6, double *cacc,
                       const int LOCK, const int BJ, const int MB, const int KA, const int EM)
{
    double F = mesh_force(K, e, X, V, LOCK, MB, KA, EM);
    vb base[NB], pb[NB];
#pragma GCC unroll 3
    for (int b = 0; b < NB; b++) {
        vb gb = !BJ ? q[b] : LOCK ? C->w[b] * q[b] - C->zc[b] : vdz(q[b], C->bj);
        base[b] = -(C->d[b] * v[b]) - C->k[b] * gb;
        pb[b] = C->cd[b] * v[b] + C->ck[b] * gb;
        acc[b] = base[b] - C->m[b] * vsplat(F);
    }
    double P = (e->fx - C->ds * vs) - hsumb(pb);
    *as6 = (e->fx - F) - C->ds * vs;
    *cacc = P - C->M * F;
}

/* The full path's state in registers: bearings and their rates as NB
 * vectors each, s and s'. */
typedef struct kst {
    vb q[NB], v[NB];
    double s, vs;
} kst;

INLINE kst kst_load(const double *restrict y)
{
    kst a;
#pragma GCC unroll 3
    for (int b = 0; b < NB; b++) {
        a.q[b] = vload6(y, b);
        a.v[b] = vload6(&y[7], b);
    }
    a.s = y[6];
    a.vs = y[13];
    return a;
}

INLINE void kst_store(double *restrict y, kst a)
{
#pragma GCC unroll 3
    for (int b = 0; b < NB; b++) {
        vstore6(y, b, a.q[b]);
        vstore6(&y[7], b, a.v[b]);
    }
    y[6] = a.s;
    y[13] = a.vs;
}

/* T RK4 steps of independent trajectories (T = 1, or 2 for the paired
 * run), stage by stage in turn, so that one trajectory's work sits next to
 * the other's while it waits on its chain. Each trajectory's arithmetic is
 * the same whatever T. kern_batch.h does this step, frun_check and
 * kloc_accept again with a run per lane (brk4, run_batch), operation for
 * operation: a change here is a change there (lib.test_pair compares the
 * two bitwise). */
INLINE void rk4_full_t(const int T, const vconst *const C[], const wg_kcoef *const K[],
                       const wg_exc *const e[], const double h[], const kst y0[], kst y1[],
                       const int LOCK, const int BJ, const int MB, const int KA, const int EM)
{
    vb q[2][NB], v[2][NB], acc[2][NB], sq[2][NB], sv[2][NB];
    double s0[2], vs0[2], X0[2], V0[2], X[2], V[2], vs[2], as6[2], cacc[2], ssv[2], sas[2];
    double at[2][4];
    static const double wt[4] = {1.0, 2.0, 2.0, 1.0};
#pragma GCC unroll 2
    for (int t = 0; t < T; t++) {
        vb pq[NB], pv[NB];
#pragma GCC unroll 3
        for (int b = 0; b < NB; b++) {
            q[t][b] = y0[t].q[b];
            v[t][b] = y0[t].v[b];
            pq[b] = C[t]->c[b] * y0[t].q[b];
            pv[b] = C[t]->c[b] * y0[t].v[b];
        }
        s0[t] = y0[t].s, vs0[t] = y0[t].vs;
        X0[t] = hsumb(pq) + s0[t], V0[t] = hsumb(pv) + vs0[t];
        X[t] = X0[t], V[t] = V0[t], vs[t] = vs0[t];
        ssv[t] = 0.0, sas[t] = 0.0;
        at[t][0] = 0.5 * h[t], at[t][1] = 0.5 * h[t], at[t][2] = h[t], at[t][3] = 0.0;
#pragma GCC unroll 3
        for (int b = 0; b < NB; b++)
            sq[t][b] = sv[t][b] = vsplat(0.0);
    }
#pragma GCC unroll 4
    for (int j = 0; j < 4; j++) {
#pragma GCC unroll 2
        for (int t = 0; t < T; t++) {
            stage_full(C[t], K[t], &e[t][(j + 1) / 2], q[t], v[t], vs[t], X[t], V[t], acc[t],
                       &as6[t], &cacc[t], LOCK, BJ, MB, KA, EM);
            vb w = vsplat(wt[j]), a = vsplat(at[t][j]);
#pragma GCC unroll 3
            for (int b = 0; b < NB; b++) {
                sq[t][b] += w * v[t][b];
                sv[t][b] += w * acc[t][b];
            }
            ssv[t] += wt[j] * vs[t];
            sas[t] += wt[j] * as6[t];
            if (j == 3)
                continue;
            double Vn = V0[t] + at[t][j] * cacc[t];
            X[t] = X0[t] + at[t][j] * V[t];
            V[t] = Vn;
#pragma GCC unroll 3
            for (int b = 0; b < NB; b++) {
                vb qn = y0[t].q[b] + a * v[t][b];
                v[t][b] = y0[t].v[b] + a * acc[t][b];
                q[t][b] = qn;
            }
            vs[t] = vs0[t] + at[t][j] * as6[t];
        }
    }
#pragma GCC unroll 2
    for (int t = 0; t < T; t++) {
        vb h6 = vsplat(h[t] / 6.0);
#pragma GCC unroll 3
        for (int b = 0; b < NB; b++) {
            y1[t].q[b] = y0[t].q[b] + h6 * sq[t][b];
            y1[t].v[b] = y0[t].v[b] + h6 * sv[t][b];
        }
        y1[t].s = s0[t] + h[t] / 6.0 * ssv[t];
        y1[t].vs = vs0[t] + h[t] / 6.0 * sas[t];
    }
}

INLINE kst rk4_full_st(const vconst *restrict C, const wg_kcoef *restrict K,
                       const wg_exc *restrict e, double h, kst y0, const int LOCK, const int BJ,
                       const int MB, const int KA, const int EM)
{
    const vconst *Cs[1] = {C};
    const wg_kcoef *Ks[1] = {K};
    const wg_exc *es[1] = {e};
    kst y1;
    rk4_full_t(1, Cs, Ks, es, &h, &y0, &y1, LOCK, BJ, MB, KA, EM);
    return y1;
}

INLINE void rk4_full(const double *restrict y0, double *restrict y1, const wg_kcoef *restrict K,
                     const wg_exc *restrict e, double h, const int LOCK, const int BJ,
                     const int MB, const int KA, const int EM)
{
    vconst C;
    vconst_load(&C, K);
    kst_store(y1, rk4_full_st(&C, K, e, h, kst_load(y0), LOCK, BJ, MB, KA, EM));
}

/* Torsional path: only s and s' (indices 6 and 13) move. */
INLINE void rhs_tors(double s, double v, double *ds, double *dv, const wg_kcoef *restrict K,
                     const wg_exc *restrict e, const int LOCK, const int MB, const int KA,
                     const int EM)
{
    double F = mesh_force(K, e, s, v, LOCK, MB, KA, EM);
    *ds = v;
    *dv = (e->fx - F) - K->d[6] * v;
}

INLINE void rk4_tors_st(double *s1, double *v1, double s, double v, const wg_kcoef *restrict K,
                        const wg_exc *restrict e, double h, const int LOCK, const int MB,
                        const int KA, const int EM)
{
    double a1, b1, a2, b2, a3, b3, a4, b4;
    rhs_tors(s, v, &a1, &b1, K, &e[0], LOCK, MB, KA, EM);
    rhs_tors(s + 0.5 * h * a1, v + 0.5 * h * b1, &a2, &b2, K, &e[1], LOCK, MB, KA, EM);
    rhs_tors(s + 0.5 * h * a2, v + 0.5 * h * b2, &a3, &b3, K, &e[1], LOCK, MB, KA, EM);
    rhs_tors(s + h * a3, v + h * b3, &a4, &b4, K, &e[2], LOCK, MB, KA, EM);
    *s1 = s + h / 6.0 * ((a1 + a4) + 2.0 * (a2 + a3));
    *v1 = v + h / 6.0 * ((b1 + b4) + 2.0 * (b2 + b3));
}

INLINE void rk4_tors(const double *restrict y0, double *restrict y1, const wg_kcoef *restrict K,
                     const wg_exc *restrict e, double h, const int LOCK, const int MB,
                     const int KA, const int EM)
{
    rk4_tors_st(&y1[6], &y1[13], y0[6], y0[13], K, e, h, LOCK, MB, KA, EM);
}

/* ---- runs of plain steps (wg_krun) ------------------------------------------ */

/* The bookkeeping of accepted steps (wg_sim_run's after_step when nothing
 * happens), on local copies. */
typedef struct kloc {
    double xn, dxn, tau, tc, mn, mx;
    uint32_t k;
} kloc;

INLINE kloc kloc_load(const wg_krun *r)
{
    return (kloc){r->xn, r->dxn, r->tau, r->tau_c, r->min_xn, r->max_xn, r->k};
}

INLINE void kloc_store(wg_krun *r, kloc l)
{
    r->xn = l.xn, r->dxn = l.dxn, r->tau = l.tau, r->tau_c = l.tc;
    r->min_xn = l.mn, r->max_xn = l.mx, r->k = l.k;
}

/* Accept a step ending at mesh contact (x, dx): as after_step, an extremum
 * inside the step first (rare: out of line), then the end. */
INLINE void kloc_accept(kloc *l, double h, double x, double dx)
{
    double dt = h - l->tc, t = l->tau + dt;
    l->tc = (t - l->tau) - dt;
    l->tau = t;
    if (__builtin_expect((l->dxn < 0) != (dx < 0), 0))
        herm_turn(l->xn, x, l->dxn, dx, h, &l->mn, &l->mx);
    l->mn = dmin(l->mn, x);
    l->mx = dmax(l->mx, x);
    l->xn = x;
    l->dxn = dx;
    l->k++;
}

/* A run's zone and blow-up bounds. Finite and far from the blow-up bound:
 * every |y_i| < fin / 16, so the sum the general step tests (< fin) holds
 * too; a step the run refuses is taken by the general step with the same
 * bits. The bearing zones' bounds are clipped to it, and all lanes are
 * tested with one mask. */
typedef struct fbound {
    vb lo[NB], hi[NB], vlim;
    double lim, mlo, mhi;
} fbound;

INLINE void fbound_load(fbound *restrict B, const wg_krun *restrict r)
{
    double lo6[6], hi6[6];
    B->lim = krun_bounds(r, lo6, hi6);
    B->vlim = vsplat(B->lim);
    B->mlo = r->lo[0], B->mhi = r->hi[0];
#pragma GCC unroll 3
    for (int b = 0; b < NB; b++) {
        B->lo[b] = vload6(lo6, b);
        B->hi[b] = vload6(hi6, b);
    }
}

/* The step w just computed (with excitation e): the mesh contact summed as
 * ct_contacts sums it (-te, then c_i y_i in index order, then s) into x,
 * dx, then the zone and finiteness tests. 1: a plain step. The products
 * c_i y_i are taken a bearing vector at a time, and x and dx are summed
 * side by side as the two lanes of one pair: each lane does the same
 * roundings in the same order as a scalar sum would. */
INLINE int frun_check(const vconst *restrict C, const fbound *restrict B,
                      const wg_exc *restrict e, const kst *restrict w, double *restrict x,
                      double *restrict dx)
{
    double pq[NB * KW], pv[NB * KW];
#pragma GCC unroll 3
    for (int b = 0; b < NB; b++) {
        vb a = C->c[b] * w->q[b], d = C->c[b] * w->v[b];
        __builtin_memcpy(&pq[b * KW], &a, sizeof a);
        __builtin_memcpy(&pv[b * KW], &d, sizeof d);
    }
    v2d m = {-e[2].te, e[2].dte};
#pragma GCC unroll 6
    for (int j = 0; j < 6; j++)
        m += (v2d){pq[j], pv[j]};
    m += (v2d){w->s, w->vs};
    vbi ok = (w->q[0] >= B->lo[0]) & (w->q[0] <= B->hi[0]) & (vabs(w->v[0]) < B->vlim);
#pragma GCC unroll 3
    for (int b = 1; b < NB; b++)
        ok &= (w->q[b] >= B->lo[b]) & (w->q[b] <= B->hi[b]) & (vabs(w->v[b]) < B->vlim);
    *x = m[0], *dx = m[1];
    return vall(ok) && fabs(w->s) < B->lim && fabs(w->vs) < B->lim && m[0] >= B->mlo &&
           m[0] <= B->mhi;
}

/* The run stops before the step z: leave it for the general step. */
INLINE void frun_refuse(wg_krun *restrict r, kst z)
{
    kst_store(r->trial, z);
    r->has_trial = 1;
}

/* The hot loop of the full path. One function so the state and the kernel
 * constants stay in registers. */
INLINE uint64_t run_full(const wg_kcoef *restrict K, wg_krun *restrict r, uint64_t n,
                         const int LOCK, const int BJ, const int MB, const int KA, const int EM)
{
    vconst C;
    vconst_load(&C, K);
    fbound B;
    fbound_load(&B, r);
    kst y = kst_load(r->y);
    kloc l = kloc_load(r);
    const double h = r->h;
    const uint32_t N = r->N;
    uint64_t i;
    for (i = 0; i < n && l.k < N; i++) {
        const wg_exc *e = &r->table[2 * l.k];
        kst z = rk4_full_st(&C, K, e, h, y, LOCK, BJ, MB, KA, EM);
        double x, dx;
        if (!frun_check(&C, &B, e, &z, &x, &dx)) {
            frun_refuse(r, z);
            break;
        }
        y = z;
        kloc_accept(&l, h, x, dx);
    }
    kst_store(r->y, y);
    kloc_store(r, l);
    return i;
}

/* Two independent runs of the full path (the same specialisation, any
 * parameters) in one loop, so that the second fills the machine while the
 * first waits on its dependency chain: each step exactly as run_full takes
 * it. Stops when either run would stop; m[0], m[1] are the steps each
 * took. */
INLINE void run_full2(const wg_kcoef *restrict Ka, wg_krun *restrict ra, uint64_t na,
                      const wg_kcoef *restrict Kb, wg_krun *restrict rb, uint64_t nb,
                      uint64_t m[2], const int LOCK, const int BJ, const int MB, const int KA,
                      const int EM)
{
    vconst Ca, Cb;
    vconst_load(&Ca, Ka);
    vconst_load(&Cb, Kb);
    const vconst *C[2] = {&Ca, &Cb};
    const wg_kcoef *K[2] = {Ka, Kb};
    fbound Ba, Bb;
    fbound_load(&Ba, ra);
    fbound_load(&Bb, rb);
    kst ya = kst_load(ra->y), yb = kst_load(rb->y);
    kloc la = kloc_load(ra), lb = kloc_load(rb);
    const double ha = ra->h, hb = rb->h, h[2] = {ha, hb};
    const uint32_t Na = ra->N, Nb = rb->N;
    uint64_t i = 0, j = 0;
    while (i < na && la.k < Na && j < nb && lb.k < Nb) {
        const wg_exc *e[2] = {&ra->table[2 * la.k], &rb->table[2 * lb.k]};
        const kst y[2] = {ya, yb};
        kst z[2];
        rk4_full_t(2, C, K, e, h, y, z, LOCK, BJ, MB, KA, EM);
        const kst za = z[0], zb = z[1];
        double xa, dxa, xb, dxb;
        int oka = frun_check(&Ca, &Ba, e[0], &za, &xa, &dxa);
        int okb = frun_check(&Cb, &Bb, e[1], &zb, &xb, &dxb);
        if (__builtin_expect(!(oka && okb), 0)) {
            if (oka)
                ya = za, kloc_accept(&la, ha, xa, dxa), i++;
            else
                frun_refuse(ra, za);
            if (okb)
                yb = zb, kloc_accept(&lb, hb, xb, dxb), j++;
            else
                frun_refuse(rb, zb);
            break;
        }
        ya = za, yb = zb;
        kloc_accept(&la, ha, xa, dxa);
        kloc_accept(&lb, hb, xb, dxb);
        i++, j++;
    }
    kst_store(ra->y, ya);
    kloc_store(ra, la);
    kst_store(rb->y, yb);
    kloc_store(rb, lb);
    m[0] = i, m[1] = j;
}

/* The torsional path's loop: s and s' only (the bearings rest at zero). */
INLINE uint64_t run_tors(const wg_kcoef *restrict K, wg_krun *restrict r, uint64_t n,
                         const int LOCK, const int MB, const int KA, const int EM)
{
    kloc l = kloc_load(r);
    double s = r->y[6], v = r->y[13], h = r->h, fin = r->fin, rest = 0.0;
    const double mlo = r->lo[0], mhi = r->hi[0];
    const uint32_t N = r->N;
    for (int j = 0; j < 14; j++)
        rest += j == 6 || j == 13 ? 0.0 : fabs(r->y[j]);
    uint64_t i;
    for (i = 0; i < n && l.k < N; i++) {
        const wg_exc *e = &r->table[2 * l.k];
        double s1, v1;
        rk4_tors_st(&s1, &v1, s, v, K, e, h, LOCK, MB, KA, EM);
        double x = -e[2].te + s1, dx = e[2].dte + v1;
        if (!(rest + fabs(s1) + fabs(v1) < fin && x >= mlo && x <= mhi)) {
            r->trial[6] = s1, r->trial[13] = v1; /* as rk4_tors */
            r->has_trial = 1;
            break;
        }
        s = s1, v = v1;
        kloc_accept(&l, h, x, dx);
    }
    r->y[6] = s, r->y[13] = v;
    kloc_store(r, l);
    return i;
}

#if KW >= 4
#include "kern_batch.h" /* batches: one run per vector lane */
#endif

/* ---- the 64 instantiations and their tables ------------------------------------ */

#define KNAME(B, L, J, M, A, E) kern_##B##L##J##M##A##E
#define KERNEL(B, L, J, M, A, E)                                                              \
    static void KNAME(B, L, J, M, A, E)(const double *restrict y0, double *restrict y1,        \
                                        const void *restrict kc, const wg_exc *restrict e,     \
                                        double h)                                              \
    {                                                                                          \
        if (B)                                                                                 \
            rk4_full(y0, y1, kc, e, h, L, J, M, A, E);                                         \
        else                                                                                   \
            rk4_tors(y0, y1, kc, e, h, L, M, A, E);                                            \
    }
#define RNAME(B, L, J, M, A, E) krun_##B##L##J##M##A##E
#define KRUN(B, L, J, M, A, E)                                                                \
    static uint64_t RNAME(B, L, J, M, A, E)(const void *restrict kc, wg_krun *restrict r,      \
                                            uint64_t n)                                        \
    {                                                                                          \
        return B ? run_full(kc, r, n, L, J, M, A, E) : run_tors(kc, r, n, L, M, A, E);         \
    }
#define PNAME(L, J, M, A, E) krun2_##L##J##M##A##E
#define KRUN2(L, J, M, A, E)                                                                   \
    static void PNAME(L, J, M, A, E)(const void *restrict ka, wg_krun *restrict ra, uint64_t na,\
                                     const void *restrict kb, wg_krun *restrict rb, uint64_t nb,\
                                     uint64_t m[2])                                            \
    {                                                                                          \
        run_full2(ka, ra, na, kb, rb, nb, m, L, J, M, A, E);                                   \
    }
#if KW >= 4
#define BNAME(L, J, M, A, E) kbatch_##L##J##M##A##E
#define KBATCH(L, J, M, A, E)                                                                  \
    static unsigned BNAME(L, J, M, A, E)(wg_kbatch *restrict B)                               \
    {                                                                                          \
        return run_batch(B, L, J, M, A, E);                                                    \
    }
#else
#define KBATCH(L, J, M, A, E)
#endif
#define K_E(B, L, J, M, A)                                                                    \
    KERNEL(B, L, J, M, A, 0) KERNEL(B, L, J, M, A, 1) KRUN(B, L, J, M, A, 0) KRUN(B, L, J, M, A, 1)
#define K_A(B, L, J, M) K_E(B, L, J, M, 0) K_E(B, L, J, M, 1)
#define K_M(B, L, J) K_A(B, L, J, 0) K_A(B, L, J, 1)
#define K_J(B, L) K_M(B, L, 0) K_M(B, L, 1)
#define K_L(B) K_J(B, 0) K_J(B, 1)
K_L(0)
K_L(1)
#define P_E(L, J, M, A)                                                                        \
    KRUN2(L, J, M, A, 0) KRUN2(L, J, M, A, 1) KBATCH(L, J, M, A, 0) KBATCH(L, J, M, A, 1)
#define P_A(L, J, M) P_E(L, J, M, 0) P_E(L, J, M, 1)
#define P_M(L, J) P_A(L, J, 0) P_A(L, J, 1)
#define P_J(L) P_M(L, 0) P_M(L, 1)
P_J(0)
P_J(1)

#define T_E(N, B, L, J, M, A) N(B, L, J, M, A, 0), N(B, L, J, M, A, 1),
#define T_A(N, B, L, J, M) T_E(N, B, L, J, M, 0) T_E(N, B, L, J, M, 1)
#define T_M(N, B, L, J) T_A(N, B, L, J, 0) T_A(N, B, L, J, 1)
#define T_J(N, B, L) T_M(N, B, L, 0) T_M(N, B, L, 1)
#define T_L(N, B) T_J(N, B, 0) T_J(N, B, 1)
const wg_kernel_fn KCAT(kern_tab, KSUF)[KF_NKERNEL] = {T_L(KNAME, 0) T_L(KNAME, 1)};
const wg_krun_fn KCAT(krun_tab, KSUF)[KF_NKERNEL] = {T_L(RNAME, 0) T_L(RNAME, 1)};
#define PN(B, L, J, M, A, E) PNAME(L, J, M, A, E)
const wg_krun2_fn KCAT(krun2_tab, KSUF)[KF_NKERNEL / 2] = {T_L(PN, 1)};
#if KW >= 4
#define BN(B, L, J, M, A, E) BNAME(L, J, M, A, E)
const wg_kbatch_fn KCAT(kbatch_tab, KSUF)[KF_NKERNEL / 2] = {T_L(BN, 1)};
#endif

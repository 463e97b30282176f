/* wg_kernel.c - specialised RK4 steps of the consistent form.
 *
 * One generic step, always inlined, instantiated for every combination of
 * the KF_* bits; the compiler removes the terms a scene does not need. The
 * excitation comes in as three entries (stage 1, stages 2-3, stage 4), so
 * the kernels call no libm. Dead zones are branch-free (min/max), or in
 * zone-locked form g = w x - zc for the event-splitting stepper. */
#include "internal.h"

#define INLINE static inline __attribute__((always_inline))

INLINE double dz(double x, double c)
{
    double t = x < c ? x : c;
    t = t > -c ? t : -c;
    return x - t;
}

/* Full path. The six bearings are handled as three 2-wide vectors (x1 y1 |
 * z1 x2 | y2 z2). The mesh coordinate is carried as scalars through the
 * stages, using linearity: with X = c.q and V = c.v (s included),
 *   X_{j+1} = X_0 + a V_j,   V_{j+1} = V_0 + a (P_j - M F_j),
 * where P_j = sum_i c_i (-d_i v_i - k_i g_i) - d_s v_s + f is the part of
 * c.acc that does not depend on F, and M = c.m + 1. P_j is computed
 * alongside F_j, so the F -> F dependency chain per stage is a handful of
 * operations instead of a 7-term dot product. */
typedef double v2d __attribute__((vector_size(16)));

INLINE v2d vload(const double *p)
{
    v2d r;
    __builtin_memcpy(&r, p, sizeof r);
    return r;
}

INLINE void vstore(double *p, v2d v) { __builtin_memcpy(p, &v, sizeof v); }

INLINE v2d vsplat(double x) { return (v2d){x, x}; }

#if defined(__SSE2__)
#include <emmintrin.h>
INLINE v2d vdz(v2d x, v2d c)
{
    __m128d t = _mm_min_pd((__m128d)x, (__m128d)c);
    t = _mm_max_pd(t, _mm_sub_pd(_mm_setzero_pd(), (__m128d)c));
    return x - (v2d)t;
}
#else
INLINE v2d vdz(v2d x, v2d c) { return (v2d){dz(x[0], c[0]), dz(x[1], c[1])}; }
#endif

/* Per-kernel constants, loaded once per step. */
typedef struct vconst {
    v2d c[3], m[3], k[3], d[3], cd[3], ck[3], w[3], zc[3], bj;
    double M, ds;
} vconst;

INLINE void vconst_load(vconst *V, const wg_kcoef *restrict K)
{
#pragma GCC unroll 3
    for (int b = 0; b < 3; b++) {
        V->c[b] = vload(&K->c[2 * b]);
        V->m[b] = vload(&K->m[2 * b]);
        V->k[b] = vload(&K->k[2 * b]);
        V->d[b] = vload(&K->d[2 * b]);
        V->cd[b] = V->c[b] * V->d[b];
        V->ck[b] = V->c[b] * V->k[b];
        V->w[b] = vload(&K->w[1 + 2 * b]);
        V->zc[b] = vload(&K->zc[1 + 2 * b]);
    }
    V->bj = vsplat(K->bj);
    double M = 1.0;
    for (int i = 0; i < 6; i++)
        M += K->c[i] * K->m[i];
    V->M = M;
    V->ds = K->d[6];
}

INLINE double hsum3(v2d a, v2d b, v2d c)
{
    v2d t = a + b + c;
    return t[0] + t[1];
}

/* One stage: from bearing positions q, velocities v, s' vs and the mesh
 * scalars X, V, the accelerations acc, s'' as6 and c.acc. */
INLINE void stage_full(const vconst *restrict C, const wg_kcoef *restrict K,
                       const wg_exc *restrict e, const v2d q[3], const v2d v[3], double vs,
                       double X, double V, v2d acc[3], double *as6, double *cacc,
                       const int LOCK, const int BJ, const int MB, const int KA, const int EM)
{
    double xn = X, dxn = V;
    if (EM) {
        xn -= e->te;
        dxn += e->dte;
    }
    double g = !MB ? xn : LOCK ? K->w[0] * xn - K->zc[0] : dz(xn, K->b);
    double F = K->dp * dxn + (KA ? e->kp * g : g);
    v2d base[3], pb[3];
#pragma GCC unroll 3
    for (int b = 0; b < 3; b++) {
        v2d gb = !BJ ? q[b] : LOCK ? C->w[b] * q[b] - C->zc[b] : vdz(q[b], C->bj);
        base[b] = -(C->d[b] * v[b]) - C->k[b] * gb;
        pb[b] = C->cd[b] * v[b] + C->ck[b] * gb;
        acc[b] = base[b] - C->m[b] * vsplat(F);
    }
    double P = (e->fx - C->ds * vs) - hsum3(pb[0], pb[1], pb[2]);
    *as6 = (e->fx - F) - C->ds * vs;
    *cacc = P - C->M * F;
}

INLINE void rk4_full(const double *restrict y0, double *restrict y1, const wg_kcoef *restrict K,
                     const wg_exc *restrict e, double h, const int LOCK, const int BJ,
                     const int MB, const int KA, const int EM)
{
    vconst C;
    vconst_load(&C, K);
    v2d q0[3], v0[3], q[3], v[3], acc[3], sq[3], sv[3];
#pragma GCC unroll 3
    for (int b = 0; b < 3; b++) {
        q0[b] = q[b] = vload(&y0[2 * b]);
        v0[b] = v[b] = vload(&y0[7 + 2 * b]);
    }
    double s0 = y0[6], vs0 = y0[13];
    double X0 = hsum3(C.c[0] * q0[0], C.c[1] * q0[1], C.c[2] * q0[2]) + s0;
    double V0 = hsum3(C.c[0] * v0[0], C.c[1] * v0[1], C.c[2] * v0[2]) + vs0;
    double X = X0, V = V0, vs = vs0, as6, cacc;
    double ssv = 0.0, sas = 0.0;
    static const double wt[4] = {1.0, 2.0, 2.0, 1.0};
    const double at[4] = {0.5 * h, 0.5 * h, h, 0.0};
#pragma GCC unroll 3
    for (int b = 0; b < 3; b++)
        sq[b] = sv[b] = vsplat(0.0);
#pragma GCC unroll 4
    for (int j = 0; j < 4; j++) {
        stage_full(&C, K, &e[(j + 1) / 2], q, v, vs, X, V, acc, &as6, &cacc, LOCK, BJ, MB, KA, EM);
        v2d w = vsplat(wt[j]), a = vsplat(at[j]);
    #pragma GCC unroll 3
    for (int b = 0; b < 3; b++) {
            sq[b] += w * v[b];
            sv[b] += w * acc[b];
        }
        ssv += wt[j] * vs;
        sas += wt[j] * as6;
        if (j == 3)
            break;
        double Vn = V0 + at[j] * cacc;
        X = X0 + at[j] * V;
        V = Vn;
    #pragma GCC unroll 3
    for (int b = 0; b < 3; b++) {
            v2d qn = q0[b] + a * v[b];
            v[b] = v0[b] + a * acc[b];
            q[b] = qn;
        }
        vs = vs0 + at[j] * as6;
    }
    v2d h6 = vsplat(h / 6.0);
#pragma GCC unroll 3
    for (int b = 0; b < 3; b++) {
        vstore(&y1[2 * b], q0[b] + h6 * sq[b]);
        vstore(&y1[7 + 2 * b], v0[b] + h6 * sv[b]);
    }
    y1[6] = s0 + h / 6.0 * ssv;
    y1[13] = vs0 + h / 6.0 * sas;
}

/* Torsional path: only s and s' (indices 6 and 13) move. */
INLINE void rhs_tors(double s, double v, double *ds, double *dv, const wg_kcoef *restrict K,
                     const wg_exc *restrict e, const int LOCK, const int MB, const int KA,
                     const int EM)
{
    double xn = s, dxn = v;
    if (EM) {
        xn -= e->te;
        dxn += e->dte;
    }
    double g = !MB ? xn : LOCK ? K->w[0] * xn - K->zc[0] : dz(xn, K->b);
    double F = K->dp * dxn + (KA ? e->kp * g : g);
    *ds = v;
    *dv = (e->fx - F) - K->d[6] * v;
}

INLINE void rk4_tors(const double *restrict y0, double *restrict y1, const wg_kcoef *restrict K,
                     const wg_exc *restrict e, double h, const int LOCK, const int MB,
                     const int KA, const int EM)
{
    double s = y0[6], v = y0[13], a1, b1, a2, b2, a3, b3, a4, b4;
    rhs_tors(s, v, &a1, &b1, K, &e[0], LOCK, MB, KA, EM);
    rhs_tors(s + 0.5 * h * a1, v + 0.5 * h * b1, &a2, &b2, K, &e[1], LOCK, MB, KA, EM);
    rhs_tors(s + 0.5 * h * a2, v + 0.5 * h * b2, &a3, &b3, K, &e[1], LOCK, MB, KA, EM);
    rhs_tors(s + h * a3, v + h * b3, &a4, &b4, K, &e[2], LOCK, MB, KA, EM);
    y1[6] = s + h / 6.0 * ((a1 + a4) + 2.0 * (a2 + a3));
    y1[13] = v + h / 6.0 * ((b1 + b4) + 2.0 * (b2 + b3));
}

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
#define K_E(B, L, J, M, A) KERNEL(B, L, J, M, A, 0) KERNEL(B, L, J, M, A, 1)
#define K_A(B, L, J, M) K_E(B, L, J, M, 0) K_E(B, L, J, M, 1)
#define K_M(B, L, J) K_A(B, L, J, 0) K_A(B, L, J, 1)
#define K_J(B, L) K_M(B, L, 0) K_M(B, L, 1)
#define K_L(B) K_J(B, 0) K_J(B, 1)
K_L(0)
K_L(1)

#define T_E(B, L, J, M, A) KNAME(B, L, J, M, A, 0), KNAME(B, L, J, M, A, 1),
#define T_A(B, L, J, M) T_E(B, L, J, M, 0) T_E(B, L, J, M, 1)
#define T_M(B, L, J) T_A(B, L, J, 0) T_A(B, L, J, 1)
#define T_J(B, L) T_M(B, L, 0) T_M(B, L, 1)
#define T_L(B) T_J(B, 0) T_J(B, 1)
static const wg_kernel_fn kernels[KF_NKERNEL] = {T_L(0) T_L(1)};

wg_kernel_fn kernel_select(unsigned kflags)
{
    return kernels[kflags & (KF_NKERNEL - 1)];
}

void kernel_printed(const double *restrict y0, double *restrict y1, const void *restrict kc,
                    const wg_exc *restrict e, double h)
{
    const wg_params *p = kc;
    double k1[16], k2[16], k3[16], k4[16], yt[16];
    wg_rhs(WG_MODEL_PRINTED, p, &e[0], y0, k1);
    for (int i = 0; i < 16; i++)
        yt[i] = y0[i] + 0.5 * h * k1[i];
    wg_rhs(WG_MODEL_PRINTED, p, &e[1], yt, k2);
    for (int i = 0; i < 16; i++)
        yt[i] = y0[i] + 0.5 * h * k2[i];
    wg_rhs(WG_MODEL_PRINTED, p, &e[1], yt, k3);
    for (int i = 0; i < 16; i++)
        yt[i] = y0[i] + h * k3[i];
    wg_rhs(WG_MODEL_PRINTED, p, &e[2], yt, k4);
    for (int i = 0; i < 16; i++)
        y1[i] = y0[i] + h / 6.0 * ((k1[i] + k4[i]) + 2.0 * (k2[i] + k3[i]));
}

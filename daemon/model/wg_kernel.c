/* wg_kernel.c - specialised RK4 steps of the consistent form.
 *
 * One generic step, always inlined, instantiated for every combination of
 * the KF_* bits; the compiler removes the terms a scene does not need. The
 * excitation comes in as three entries (stage 1, stages 2-3, stage 4), so
 * the kernels call no libm. Dead zones are branch-free (min/max), or in
 * zone-locked form g = w x - zc for the event-splitting stepper. */
#include "model_internal.h"

#define INLINE static inline __attribute__((always_inline))

INLINE double dz(double x, double c)
{
    double t = x < c ? x : c;
    t = t > -c ? t : -c;
    return x - t;
}

INLINE void rhs_full(const double *restrict y, double *restrict dy, const wg_kcoef *restrict K,
                     const wg_exc *restrict e, const int LOCK, const int BJ, const int MB,
                     const int KA, const int EM)
{
    const double *c = K->c;
    double xn = (c[0] * y[0] + c[1] * y[1]) + (c[2] * y[2] + c[3] * y[3]) +
                ((c[4] * y[4] + c[5] * y[5]) + y[6]);
    double dxn = (c[0] * y[7] + c[1] * y[8]) + (c[2] * y[9] + c[3] * y[10]) +
                 ((c[4] * y[11] + c[5] * y[12]) + y[13]);
    if (EM) {
        xn -= e->te;
        dxn += e->dte;
    }
    double g = !MB ? xn : LOCK ? K->w[0] * xn - K->zc[0] : dz(xn, K->b);
    double F = K->dp * dxn + (KA ? e->kp * g : g);
    for (int i = 0; i < 6; i++) {
        double gb = !BJ ? y[i] : LOCK ? K->w[i + 1] * y[i] - K->zc[i + 1] : dz(y[i], K->bj);
        dy[i] = y[7 + i];
        dy[7 + i] = -K->d[i] * y[7 + i] - K->k[i] * gb - K->m[i] * F;
    }
    dy[6] = y[13];
    dy[13] = (e->fx - F) - K->d[6] * y[13];
}

INLINE void rk4_full(const double *restrict y0, double *restrict y1, const wg_kcoef *restrict K,
                     const wg_exc *restrict e, double h, const int LOCK, const int BJ,
                     const int MB, const int KA, const int EM)
{
    double k1[14], k2[14], k3[14], k4[14], yt[14];
    const double h2 = 0.5 * h, h6 = h / 6.0;
    rhs_full(y0, k1, K, &e[0], LOCK, BJ, MB, KA, EM);
    for (int i = 0; i < 14; i++)
        yt[i] = y0[i] + h2 * k1[i];
    rhs_full(yt, k2, K, &e[1], LOCK, BJ, MB, KA, EM);
    for (int i = 0; i < 14; i++)
        yt[i] = y0[i] + h2 * k2[i];
    rhs_full(yt, k3, K, &e[1], LOCK, BJ, MB, KA, EM);
    for (int i = 0; i < 14; i++)
        yt[i] = y0[i] + h * k3[i];
    rhs_full(yt, k4, K, &e[2], LOCK, BJ, MB, KA, EM);
    for (int i = 0; i < 14; i++)
        y1[i] = y0[i] + h6 * ((k1[i] + k4[i]) + 2.0 * (k2[i] + k3[i]));
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

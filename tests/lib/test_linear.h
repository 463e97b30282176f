/* test_linear.h - the exact periodic response of the model made linear
 * (b = b_j = 0, k_a = 0): y' = A y + b0 + Re(B e^{i psi}), psi = omega tau,
 * built from the reference RHS, solved in the frequency domain. Shared by
 * test_shoot and test_cont. */
#ifndef WG_TEST_LINEAR_H
#define WG_TEST_LINEAR_H

#include <complex.h>
#include <math.h>
#include "wormgear/wg_model.h"

enum { LIN_NS = 14 };

/* y' = A y + b0 + Re(B e^{i psi}): A column by column from the reference
 * RHS (exact: the system is linear), the forcing from two phases. */
static inline void linear_system(const wg_params *p, double *A, double *b0, double complex *B)
{
    double z[LIN_NS] = {0}, f0[LIN_NS], f[LIN_NS], g[LIN_NS];
    wg_exc e0 = {1.0, 0.0, 0.0, 0.0}, e;
    wg_rhs(WG_MODEL_CONSISTENT, p, &e0, z, f0);
    for (int j = 0; j < LIN_NS; j++) {
        z[j] = 1.0;
        wg_rhs(WG_MODEL_CONSISTENT, p, &e0, z, f);
        z[j] = 0.0;
        for (int i = 0; i < LIN_NS; i++)
            A[i * LIN_NS + j] = f[i] - f0[i];
    }
    double om = p->v[WG_P_OMEGA];
    wg_exc_eval(p, 0.0, om, &e);
    wg_rhs(WG_MODEL_CONSISTENT, p, &e, z, f);
    wg_exc_eval(p, M_PI / 2, om, &e);
    wg_rhs(WG_MODEL_CONSISTENT, p, &e, z, g);
    for (int i = 0; i < LIN_NS; i++) {
        b0[i] = i == 13 ? p->v[WG_P_F_M] : 0.0;
        B[i] = (f[i] - b0[i]) - I * (g[i] - b0[i]); /* Re(B e^{i psi}) at 0 and pi/2 */
    }
}

/* Solve M z = r (complex, n x n, destroyed) by Gaussian elimination. */
static inline void csolve(int n, double complex *M, double complex *r)
{
    for (int k = 0; k < n; k++) {
        int pv = k;
        for (int i = k + 1; i < n; i++)
            if (cabs(M[i * n + k]) > cabs(M[pv * n + k]))
                pv = i;
        for (int j = 0; j < n; j++) {
            double complex t = M[k * n + j];
            M[k * n + j] = M[pv * n + j];
            M[pv * n + j] = t;
        }
        double complex t = r[k];
        r[k] = r[pv];
        r[pv] = t;
        for (int i = k + 1; i < n; i++) {
            double complex f = M[i * n + k] / M[k * n + k];
            for (int j = k; j < n; j++)
                M[i * n + j] -= f * M[k * n + j];
            r[i] -= f * r[k];
        }
    }
    for (int k = n - 1; k >= 0; k--) {
        for (int j = k + 1; j < n; j++)
            r[k] -= M[k * n + j] * r[j];
        r[k] /= M[k * n + k];
    }
}

/* The exact periodic response at psi = 0: y_s + Re(Y), (i omega - A) Y = B. */
static inline void exact_response(const wg_params *p, double *y)
{
    double A[LIN_NS * LIN_NS], b0[LIN_NS];
    double complex B[LIN_NS], M[LIN_NS * LIN_NS], ys[LIN_NS];
    linear_system(p, A, b0, B);
    for (int i = 0; i < LIN_NS * LIN_NS; i++)
        M[i] = -A[i];
    for (int i = 0; i < LIN_NS; i++)
        ys[i] = b0[i];
    csolve(LIN_NS, M, ys); /* -A ys = b0 */
    for (int i = 0; i < LIN_NS * LIN_NS; i++)
        M[i] = (i % (LIN_NS + 1) == 0 ? I * p->v[WG_P_OMEGA] : 0.0) - A[i];
    csolve(LIN_NS, M, B);
    for (int i = 0; i < LIN_NS; i++)
        y[i] = creal(ys[i]) + creal(B[i]);
}

#endif

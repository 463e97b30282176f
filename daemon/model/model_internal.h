/* model_internal.h - shared between the model library's own files only. */
#ifndef WG_MODEL_INTERNAL_H
#define WG_MODEL_INTERNAL_H

#include "wormgear/wg_sim.h"

/* Mesh direction c (x_n = c . q) and force weights m (mass ratio times c). */
void model_mesh_vectors(int model, const wg_params *p, double c[7], double m[7]);

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

/* The consistent-form kernel for a set of KF_* bits; kc is a wg_kcoef. */
wg_kernel_fn kernel_select(unsigned kflags);

/* RK4 step of the printed form (unspecialised, for comparison); kc is the
 * wg_params. */
void kernel_printed(const double *restrict y0, double *restrict y1, const void *restrict kc,
                    const wg_exc *restrict e, double h);

#endif

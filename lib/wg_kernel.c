/* wg_kernel.c - the specialised RK4 steps for the x86-64 baseline (SSE2:
 * the bearings as three 2-wide vectors), the choice among the instruction
 * sets the library was built for (wg_kernel_avx2.c, wg_kernel_avx512.c,
 * wg_kernel_avx512vl.c: the same template, kern_tmpl.h, the same bits),
 * and the printed form's unspecialised step. */
#define KW 2
#define KSUF sse2
#include "kern_tmpl.h"

#include <stdlib.h>
#include <string.h>

extern const wg_kernel_fn kern_tab_avx2[KF_NKERNEL], kern_tab_avx512[KF_NKERNEL],
    kern_tab_avx512vl[KF_NKERNEL];
extern const wg_krun_fn krun_tab_avx2[KF_NKERNEL], krun_tab_avx512[KF_NKERNEL],
    krun_tab_avx512vl[KF_NKERNEL];
extern const wg_krun2_fn krun2_tab_avx2[KF_NKERNEL / 2], krun2_tab_avx512[KF_NKERNEL / 2],
    krun2_tab_avx512vl[KF_NKERNEL / 2];
extern const wg_kbatch_fn kbatch_tab_avx2[KF_NKERNEL / 2], kbatch_tab_avx512[KF_NKERNEL / 2],
    kbatch_tab_avx512vl[KF_NKERNEL / 2];

static const char *const isa_names[KISA_N] = {"sse2", "avx2", "avx512", "avx512vl"};

/* Each set's tables, by KISA_* (the baseline has no batched loop). */
static const wg_kernel_fn *const kern_tabs[KISA_N] = {kern_tab_sse2, kern_tab_avx2,
                                                      kern_tab_avx512, kern_tab_avx512vl};
static const wg_krun_fn *const krun_tabs[KISA_N] = {krun_tab_sse2, krun_tab_avx2,
                                                    krun_tab_avx512, krun_tab_avx512vl};
static const wg_krun2_fn *const krun2_tabs[KISA_N] = {krun2_tab_sse2, krun2_tab_avx2,
                                                      krun2_tab_avx512, krun2_tab_avx512vl};
static const wg_kbatch_fn *const kbatch_tabs[KISA_N] = {NULL, kbatch_tab_avx2,
                                                        kbatch_tab_avx512, kbatch_tab_avx512vl};

const char *kernel_isa_name(int isa)
{
    return isa >= 0 && isa < KISA_N ? isa_names[isa] : "?";
}

int kernel_isa_supported(int isa)
{
#if defined(__x86_64__) && defined(__GNUC__)
    if (isa == KISA_AVX2)
        return __builtin_cpu_supports("avx2");
    if (isa == KISA_AVX512)
        return __builtin_cpu_supports("avx512f");
    if (isa == KISA_AVX512VL)
        return __builtin_cpu_supports("avx2") && __builtin_cpu_supports("avx512f") &&
               __builtin_cpu_supports("avx512vl");
#endif
    return isa == KISA_SSE2;
}

int kernel_isa_choose(void)
{
    const char *want = getenv("WG_ISA");
    for (int isa = 0; want && isa < KISA_N; isa++)
        if (strcmp(want, isa_names[isa]) == 0 && kernel_isa_supported(isa))
            return isa;
    return kernel_isa_supported(KISA_AVX512) ? KISA_AVX512
           : kernel_isa_supported(KISA_AVX2) ? KISA_AVX2 : KISA_SSE2;
}

int kernel_isa_4wide(void)
{
    return kernel_isa_supported(KISA_AVX512VL) ? KISA_AVX512VL : KISA_AVX2;
}

int kernel_isa_one(int isa)
{
#if defined(__x86_64__) && defined(__GNUC__)
    const char *want = getenv("WG_ISA");
    if (isa == KISA_AVX512 && !(want && strcmp(want, isa_names[KISA_AVX512]) == 0) &&
        __builtin_cpu_is("intel") && kernel_isa_supported(KISA_AVX2))
        return kernel_isa_4wide();
#endif
    return isa;
}

/* A KISA_* value in range (the baseline's for any other). */
static int isa_index(int isa) { return isa > KISA_SSE2 && isa < KISA_N ? isa : KISA_SSE2; }

wg_kernel_fn kernel_select(unsigned kflags, int isa)
{
    return kern_tabs[isa_index(isa)][kflags & (KF_NKERNEL - 1)];
}

wg_krun_fn krun_select(unsigned kflags, int isa)
{
    return krun_tabs[isa_index(isa)][kflags & (KF_NKERNEL - 1)];
}

wg_krun2_fn krun2_select(unsigned kflags, int isa)
{
    const wg_krun2_fn *t = krun2_tabs[isa_index(isa)];
    return kflags & KF_BEAR ? t[kflags & (KF_NKERNEL / 2 - 1)] : NULL;
}

wg_kbatch_fn kbatch_select(unsigned kflags, int isa, int L)
{
    if (isa == KISA_AVX512 && L <= 4 && kernel_isa_supported(KISA_AVX2))
        isa = kernel_isa_4wide(); /* one 4-wide group costs less than an 8-wide vector */
    const wg_kbatch_fn *t = kbatch_tabs[isa_index(isa)];
    return t && (kflags & KF_BEAR) ? t[kflags & (KF_NKERNEL / 2 - 1)] : NULL;
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

/* wg_kernel_avx2.c - the specialised RK4 steps (kern_tmpl.h) for AVX2: the
 * six bearings in one 4-wide and one (half-used) 4-wide vector. Chosen at run time when
 * the CPU has it (kernel_isa_choose); the same bits as the baseline. */
#if defined(__x86_64__) && defined(__GNUC__)
#pragma GCC target("avx2")
#define KW 4
#define KSUF avx2
#include "kern_tmpl.h"
#else
#include "internal.h"
const wg_kernel_fn kern_tab_avx2[KF_NKERNEL];
const wg_krun_fn krun_tab_avx2[KF_NKERNEL];
const wg_krun2_fn krun2_tab_avx2[KF_NKERNEL / 2];
const wg_kbatch_fn kbatch_tab_avx2[KF_NKERNEL / 2];
#endif

/* wg_kernel_avx512.c - the specialised RK4 steps (kern_tmpl.h) for AVX-512F: the
 * six bearings in one 8-wide vector (two lanes unused). Chosen at run time when
 * the CPU has it (kernel_isa_choose); the same bits as the baseline. */
#if defined(__x86_64__) && defined(__GNUC__)
#pragma GCC target("avx512f")
#define KW 8
#define KSUF avx512
#include "kern_tmpl.h"
#else
#include "internal.h"
const wg_kernel_fn kern_tab_avx512[KF_NKERNEL];
const wg_krun_fn krun_tab_avx512[KF_NKERNEL];
const wg_krun2_fn krun2_tab_avx512[KF_NKERNEL / 2];
const wg_kbatch_fn kbatch_tab_avx512[KF_NKERNEL / 2];
#endif

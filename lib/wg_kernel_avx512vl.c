/* wg_kernel_avx512vl.c - the specialised RK4 steps (kern_tmpl.h) in AVX2's
 * form (the six bearings in one 4-wide and one half-used 4-wide vector;
 * a batch's runs in 4-wide groups) compiled with AVX-512VL, whose 32
 * vector registers hold what AVX2's 16 spill to the stack: the same
 * operations, the same bits. Chosen at run time where the CPU has
 * AVX-512VL: for a run's own kernels on an Intel CPU (kernel_isa_one) and
 * a batch of four runs or fewer (kbatch_select). */
#if defined(__x86_64__) && defined(__GNUC__)
#pragma GCC target("avx2,avx512f,avx512vl")
#define KW 4
#define KSUF avx512vl
#include "kern_tmpl.h"
#else
#include "internal.h"
const wg_kernel_fn kern_tab_avx512vl[KF_NKERNEL];
const wg_krun_fn krun_tab_avx512vl[KF_NKERNEL];
const wg_krun2_fn krun2_tab_avx512vl[KF_NKERNEL / 2];
const wg_kbatch_fn kbatch_tab_avx512vl[KF_NKERNEL / 2];
#endif

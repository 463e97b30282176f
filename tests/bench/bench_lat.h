/* bench_lat.h - latencies of single operations on this CPU, timed as
 * chains of dependent x86-64 instructions the compiler cannot fold: the
 * units bench_gsl prices the chain bound in, and bench_pair its measured
 * link. Thread CPU time (bench_common.h). */
#ifndef WG_BENCH_LAT_H
#define WG_BENCH_LAT_H

#include "bench_common.h"

typedef struct oplat {
    double add, mul, other; /* ns per dependent operation */
} oplat;

/* n x 8 dependent operations, the loop inside the asm so that the
 * compiler can neither fold the chain nor put a register copy into it (in a
 * build for AVX it does, with vmovsd, which costs a cycle a copy); in such
 * a build the VEX form, as the compiler's own code there. */
#if defined(__x86_64__) && defined(__AVX__)
#define DEP1(insn) "v" insn " %2, %0, %0\n\t"
#elif defined(__x86_64__)
#define DEP1(insn) insn " %2, %0\n\t"
#else
#error "bench_lat.h times x86-64 instructions"
#endif
#define DEP8N(insn, x, k, n)                                                              \
    do {                                                                                  \
        long cnt_ = (n);                                                                  \
        if (cnt_ > 0)                                                                     \
            __asm__("1:\n\t" DEP1(insn) DEP1(insn) DEP1(insn) DEP1(insn) DEP1(insn)       \
                    DEP1(insn) DEP1(insn) DEP1(insn) "dec %1\n\tjnz 1b"                   \
                    : "+x"(x), "+r"(cnt_) : "x"(k) : "cc");                             \
    } while (0)

static oplat dep_ns(long m)
{
    volatile double seed = 1.0;
    double x = seed, c = seed * 1e-300, y = seed, k = seed * (1.0 + 1e-15), z = seed;
    oplat r;
    double t0 = bench_now_ns();
    DEP8N("addsd", x, c, m / 8);
    double t1 = bench_now_ns();
    DEP8N("mulsd", y, k, m / 8);
    double t2 = bench_now_ns();
    DEP8N("minsd", z, k, m / 8);
    double t3 = bench_now_ns(), ops = (double)(m / 8 * 8);
    seed = x + y + z;
    r.add = (t1 - t0) / ops;
    r.mul = (t2 - t1) / ops;
    r.other = (t3 - t2) / ops;
    return r;
}

#endif

/* bench_ports - what this CPU sustains of the AVX2 batch's instructions
 * (lib/kern_batch.h, 4-wide): 256-bit multiplies, adds, loads and stores
 * a cycle, each in a loop of independent instructions. A cycle is taken
 * from a dependent multiply's latency: 3 cycles on every AMD Zen, 4 on
 * Intel's cores since Skylake (their optimization manuals), so the figures
 * are per cycle whatever the clock. (An add's latency is no such constant:
 * 3 cycles on Zen 1-4, 2 on Zen 5, whose dependent add this prints in
 * cycles too.) docs/performance.md ("The AVX2 batch against this
 * CPU's ports") sets them beside the batch's instruction counts.
 * usage: bench_ports [REPS] (default 3); exit 77 without AVX2. */
#include "bench_args.h"

#include <stdio.h>
#include <stdlib.h>
#include <time.h>

static double now(void)
{
    struct timespec t;
    clock_gettime(CLOCK_MONOTONIC, &t);
    return t.tv_sec + 1e-9 * t.tv_nsec;
}

static double buf[64 * 4] __attribute__((aligned(64))); /* L1-resident */
#define N 20000000L

#define CLOBBER8 "xmm0", "xmm1", "xmm2", "xmm3", "xmm4", "xmm5", "xmm6", "xmm7"
#define ON8(X) X(0) X(1) X(2) X(3) X(4) X(5) X(6) X(7)
#define ADD0(r) "vaddpd %%ymm0, %%ymm0, %%ymm0\n\t" /* one chain: the latency */
#define MUL0(r) "vmulpd %%ymm0, %%ymm0, %%ymm0\n\t"
#define MUL(r) "vmulpd %%ymm15, %%ymm" #r ", %%ymm" #r "\n\t" /* chain r of eight */
#define ADD(r) "vaddpd %%ymm15, %%ymm" #r ", %%ymm" #r "\n\t"
#define LOAD(r) "vmovapd " #r "*32(%0), %%ymm" #r "\n\t"
#define STORE(r) "vmovapd %%ymm" #r ", " #r "*32(%0)\n\t"

/* seconds an instruction: N iterations of an asm of per instructions */
#define TIMED(name, per, ...)                                                               \
    __attribute__((target("avx2"), noinline)) static double name(void)                      \
    {                                                                                        \
        double t = now();                                                                    \
        for (long i = 0; i < N; i++)                                                         \
            __asm__ volatile(__VA_ARGS__);                                                   \
        return (now() - t) / ((per) * (double)N);                                            \
    }
TIMED(t_dep, 8, ON8(ADD0)::: "xmm0")
TIMED(t_depmul, 8, ON8(MUL0)::: "xmm0")
TIMED(t_mul, 8, ON8(MUL)::: CLOBBER8)
TIMED(t_add, 8, ON8(ADD)::: CLOBBER8)
/* six multiply chains and six add chains, alternated */
TIMED(t_muladd, 12,
      MUL(0) ADD(8) MUL(1) ADD(9) MUL(2) ADD(10) MUL(3) ADD(11) MUL(4) ADD(12) MUL(5) ADD(13)
      ::: "xmm0", "xmm1", "xmm2", "xmm3", "xmm4", "xmm5", "xmm8", "xmm9", "xmm10", "xmm11",
      "xmm12", "xmm13")
TIMED(t_load, 8, ON8(LOAD)::"r"(buf) : CLOBBER8, "memory")
TIMED(t_store, 8, ON8(STORE)::"r"(buf) : "memory")

int main(int argc, char **argv)
{
    double nrep = 3;
    bench_arg args[] = {{"REPS", "repetitions, 1 to 100 (default 3)", 1, 100, &nrep, NULL, 0}};
    int rc = bench_args("bench_ports", "What this CPU sustains a cycle of 256-bit multiplies, "
                        "adds, loads and stores (exit 77 without AVX2).", "", argc, argv, args, 1,
                        NULL);
    if (rc >= 0)
        return rc;
    int reps = (int)nrep;
    if (!__builtin_cpu_supports("avx2")) {
        printf("bench_ports: this CPU has no AVX2: nothing to measure\n");
        return 77;
    }
    double lat = __builtin_cpu_is("amd") ? 3 : __builtin_cpu_is("intel") ? 4 : 0;
    if (!lat) {
        printf("bench_ports: neither AMD nor Intel: a dependent add's cycles unknown\n");
        return 77;
    }
    printf("bench_ports: 256-bit instructions, cycles each in a loop of independent ones "
           "(a cycle: a dependent multiply / %.0f, %s), %d reps\n", lat,
           lat == 3 ? "AMD" : "Intel", reps);
    for (int rep = 0; rep < reps; rep++) {
        double dm = t_depmul(), c = dm / lat, d = t_dep();
        printf("dependent multiply %.3f ns (a cycle %.3f ns, %.2f GHz), add %.3f ns (%.2f "
               "cycles) | cycles an instruction: mul %.2f, add %.2f, mul and add alternated "
               "%.2f, load %.2f, store %.2f\n",
               dm * 1e9, c * 1e9, 1e-9 / c, d * 1e9, d / c, t_mul() / c, t_add() / c,
               t_muladd() / c, t_load() / c, t_store() / c);
    }
    return 0;
}

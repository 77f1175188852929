/* cpu.c - which of the library's optional SIMD paths this CPU and build run. */
#include "core/cpu.h"
#include <pthread.h>

#ifndef JM_SPLAT_VARIANT
#define JM_SPLAT_VARIANT 0
#endif

static int avx512, avx2, fma;
static pthread_once_t once = PTHREAD_ONCE_INIT;
static void probe(void)
{
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    __builtin_cpu_init();
    avx512 = __builtin_cpu_supports("avx512f") && JM_SPLAT_VARIANT == 0;
    avx2 = __builtin_cpu_supports("avx2") && (JM_SPLAT_VARIANT == 0 || JM_SPLAT_VARIANT == 3);
    fma = avx2 && __builtin_cpu_supports("fma");
#endif
}

int jm_cpu_avx512(void)
{
    pthread_once(&once, probe);
    return avx512;
}

int jm_cpu_avx2(void)
{
    pthread_once(&once, probe);
    return avx2;
}

int jm_cpu_avx2_fma(void)
{
    pthread_once(&once, probe);
    return fma;
}

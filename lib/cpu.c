/* cpu.c - the one CPU dispatch: probes the vector extensions once; tests may force a lower level. */
#include "cpu.h"
#include "jetmesh_testing.h"
#include <pthread.h>
#include <stdatomic.h>

static int probed = JM_CPU_PLAIN;
static pthread_once_t once = PTHREAD_ONCE_INIT;
static _Atomic int forced = -1;

static void probe(void)
{
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    __builtin_cpu_init();
    probed = JM_CPU_SSE2;
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) probed = JM_CPU_AVX2;
    if (probed == JM_CPU_AVX2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
        __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512cd"))
        probed = JM_CPU_AVX512;
#endif
}

int jm_cpu_level(void)
{
    pthread_once(&once, probe);
    const int f = atomic_load_explicit(&forced, memory_order_relaxed);
    return f >= 0 && f < probed ? f : probed;
}

int jm_cpu_forced(void) { return atomic_load_explicit(&forced, memory_order_relaxed) >= 0; }

int jm_testing_force_cpu(int level)
{
    atomic_store(&forced, level < 0 ? -1 : level);
    return jm_cpu_level();
}

const char *jm_testing_cpu_name(void)
{
    static const char *const names[] = {"plain C", "SSE2", "AVX2 and FMA, no AVX-512", "AVX-512"};
    return names[jm_cpu_level()];
}

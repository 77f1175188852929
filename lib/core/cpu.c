/* cpu.c - the one CPU dispatch: probes the vector extensions once; tests may force a lower level. */
#include "core/cpu.h"
#include "jetmesh_testing.h"
#include <stdatomic.h>

static int probed = JM_CPU_PLAIN;
static _Atomic int forced = -1;
_Atomic int jm_cpu_now = JM_CPU_PLAIN;

/* the level from the probe and the forced one, published for jm_cpu_level */
static int publish(void)
{
    const int f = atomic_load(&forced);
    const int l = f >= 0 && f < probed ? f : probed;
    atomic_store(&jm_cpu_now, l);
    return l;
}

/* at load, before any kernel runs (a constructor: jm_cpu_level is one load) */
__attribute__((constructor)) static void probe(void)
{
#if defined(__x86_64__) && (defined(__GNUC__) || defined(__clang__))
    __builtin_cpu_init();
    probed = JM_CPU_SSE2;
    if (__builtin_cpu_supports("avx2") && __builtin_cpu_supports("fma")) probed = JM_CPU_AVX2;
    if (probed == JM_CPU_AVX2 && __builtin_cpu_supports("avx512f") && __builtin_cpu_supports("avx512vl") &&
        __builtin_cpu_supports("avx512bw") && __builtin_cpu_supports("avx512dq") && __builtin_cpu_supports("avx512cd"))
        probed = JM_CPU_AVX512;
#endif
    publish();
}

int jm_cpu_forced(void) { return atomic_load_explicit(&forced, memory_order_relaxed) >= 0; }

int jm_testing_force_cpu(int level)
{
    atomic_store(&forced, level < 0 ? -1 : level);
    return publish();
}

const char *jm_testing_cpu_name(void)
{
    static const char *const names[] = {"plain C", "SSE2", "AVX2 and FMA, no AVX-512", "AVX-512"};
    return names[jm_cpu_level()];
}

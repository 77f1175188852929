/* cpu.h - the one CPU dispatch: which vector level the library's kernels run, probed once here. */
#ifndef JETMESH_CPU_H
#define JETMESH_CPU_H
#include <stdatomic.h>

/* Every vector kernel gives the plain C's samples bit for bit (the same
 * operations per lane, -ffp-contract=off), so the level changes speed only
 * (the interior proofs' bounds may round differently, never the meshes:
 * docs/culling.md). The one-at-a-time helpers of field.c and metafinish.c
 * use SSE2 wherever the compiler targets x86-64, with no run-time choice.
 * Levels, each implying the ones below it (jetmesh_testing.h numbers them
 * alike): */
enum {
    JM_CPU_PLAIN = 0,  /* plain C kernels */
    JM_CPU_SSE2 = 1,   /* 4-wide kernels (x86-64's baseline) */
    JM_CPU_AVX2 = 2,   /* 8-wide: AVX2 and FMA */
    JM_CPU_AVX512 = 3, /* 16-wide: x86-64-v4 (AVX-512 F, VL, BW, DQ, CD) */
};

/* The level the kernels run: the CPU's best, or lower where a test forced
 * it (jm_testing_force_cpu). Probed when the library is loaded and read
 * on every kernel call (one load), so that a forced level takes effect at
 * once. */
extern _Atomic int jm_cpu_now __attribute__((visibility("hidden"))); /* set at load (cpu.c) */
static inline int jm_cpu_level(void) { return atomic_load_explicit(&jm_cpu_now, memory_order_relaxed); }
static inline int jm_cpu_avx512(void) { return jm_cpu_level() >= JM_CPU_AVX512; }
static inline int jm_cpu_avx2(void) { return jm_cpu_level() >= JM_CPU_AVX2; }
static inline int jm_cpu_sse2(void) { return jm_cpu_level() >= JM_CPU_SSE2; }
/* 1 while a test forces a level: the metasphere finish then also takes its
 * lists' overflow path (metafinish.c) */
int jm_cpu_forced(void);

/* Kernels written once in C and built for several targets, chosen by the
 * level at each call: JM_KERNEL_AVX2(sc, ret, name, body, params, args)
 * defines `sc ret name params`, which returns `body args` built for AVX2
 * where the level is AVX2 or more, else for any x86-64; JM_KERNEL_V4 adds
 * an x86-64-v4 build for the AVX-512 level, JM_KERNEL_512 has that and the
 * any-x86-64 one. body is a JM_BODY function (inlined into each build):
 * the same operations on every target (-ffp-contract=off: no FMA), so the
 * same bits. JM_NO_CLONES (ThreadSanitizer) builds the plain one only. */
#define JM_BODY static inline __attribute__((always_inline))
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(JM_NO_CLONES)
#define JM_KERNEL_TGT(tgt, ret, name, sfx, body, params, args)                                                   \
    __attribute__((target(tgt), noinline)) static ret name##_##sfx params { return body args; }
#define JM_KERNEL_AVX2(sc, ret, name, body, params, args)                                                        \
    JM_KERNEL_TGT("avx2", ret, name, avx2, body, params, args)                                                   \
    __attribute__((noinline)) static ret name##_any params { return body args; }                                 \
    sc ret name params { return jm_cpu_avx2() ? name##_avx2 args : name##_any args; }
#define JM_KERNEL_V4(sc, ret, name, body, params, args)                                                          \
    JM_KERNEL_TGT("arch=x86-64-v4", ret, name, v4, body, params, args)                                           \
    JM_KERNEL_TGT("avx2", ret, name, avx2, body, params, args)                                                   \
    __attribute__((noinline)) static ret name##_any params { return body args; }                                 \
    sc ret name params                                                                                           \
    {                                                                                                            \
        const int level = jm_cpu_level();                                                                        \
        return level >= JM_CPU_AVX512 ? name##_v4 args : level >= JM_CPU_AVX2 ? name##_avx2 args : name##_any args; \
    }
#define JM_KERNEL_512(sc, ret, name, body, params, args)                                                         \
    JM_KERNEL_TGT("avx512f", ret, name, avx512, body, params, args)                                              \
    __attribute__((noinline)) static ret name##_any params { return body args; }                                 \
    sc ret name params { return jm_cpu_avx512() ? name##_avx512 args : name##_any args; }
#else
#define JM_KERNEL_AVX2(sc, ret, name, body, params, args)                                                        \
    sc ret name params { return body args; }
#define JM_KERNEL_V4 JM_KERNEL_AVX2
#define JM_KERNEL_512 JM_KERNEL_AVX2
#endif

#endif

/* cpu.h - the one CPU dispatch: which vector level the library's kernels run, probed once here. */
#ifndef JETMESH_CPU_H
#define JETMESH_CPU_H

/* Every hand-written vector kernel gives the plain C's bits (the same
 * operations per lane, -ffp-contract=off), so the level changes speed only.
 * Levels, each implying the ones below it (jetmesh_testing.h numbers them
 * alike): */
enum {
    JM_CPU_PLAIN = 0,  /* plain C kernels */
    JM_CPU_SSE2 = 1,   /* 4-wide kernels (x86-64's baseline) */
    JM_CPU_AVX2 = 2,   /* 8-wide: AVX2 and FMA */
    JM_CPU_AVX512 = 3, /* 16-wide: x86-64-v4 (AVX-512 F, VL, BW, DQ, CD) */
};

/* The level the kernels run: the CPU's best, or lower where a test forced
 * it (jm_testing_force_cpu). Read on every kernel call, so that a forced
 * level takes effect at once. */
int jm_cpu_level(void);
static inline int jm_cpu_avx512(void) { return jm_cpu_level() >= JM_CPU_AVX512; }
static inline int jm_cpu_avx2(void) { return jm_cpu_level() >= JM_CPU_AVX2; }
static inline int jm_cpu_sse2(void) { return jm_cpu_level() >= JM_CPU_SSE2; }
/* 1 while a test forces a level: the metasphere finish then also takes its
 * lists' overflow path (metafinish.c) */
int jm_cpu_forced(void);

/* Loops the compiler builds for several targets from one C source, chosen
 * by the loader (GCC's target_clones): the same operations, so the same
 * bits, on every target. The forced level does not reach them; JM_NO_CLONES
 * builds the plain ones only (ThreadSanitizer cannot run their ifunc
 * resolvers; tests/t_splat_variants.sh compares that build's meshes). */
#if defined(__x86_64__) && defined(__GNUC__) && !defined(__clang__) && !defined(JM_NO_CLONES)
#define JM_CLONES_AVX2 __attribute__((target_clones("avx2", "default")))
#define JM_CLONES_V4 __attribute__((target_clones("arch=x86-64-v4", "avx2", "default")))
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#define JM_CLONES_512 __attribute__((target_clones("avx512f", "default")))
#define JM_CLONES_512_AVX2 __attribute__((target_clones("avx512f", "avx2", "default")))
#endif
#endif
#ifndef JM_CLONES_AVX2
#define JM_CLONES_AVX2
#define JM_CLONES_V4
#endif
#ifndef JM_CLONES_512
#define JM_CLONES_512
#define JM_CLONES_512_AVX2
#endif
#endif

/* cpu.h - which of the library's optional SIMD paths this CPU and build run. */
#ifndef JETMESH_CPU_H
#define JETMESH_CPU_H

/* 1 where the AVX-512 paths that give the same bits as the plain code run:
 * the CPU has AVX-512F and the build is not a test variant
 * (JM_SPLAT_VARIANT, tests/t_splat_variants.sh, takes the plain paths). */
int jm_cpu_avx512(void);
/* 1 where the hand-written AVX2 paths that give the same bits as the plain
 * code run: the CPU has AVX2 and the build is not a plain or SSE2 test
 * variant (JM_SPLAT_VARIANT 1 or 2). */
int jm_cpu_avx2(void);
/* 1 where jm_cpu_avx2() and the CPU has FMA too (the paths whose bounds
 * hold for fused or separate roundings alike). */
int jm_cpu_avx2_fma(void);
#endif

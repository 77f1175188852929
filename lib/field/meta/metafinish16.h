/* metafinish16.h - the metasphere finish's per-triangle kernels, 16 triangles per AVX-512 pass (8 per AVX2 pass), with the bits of metafinish.c's one-at-a-time ones. */
#ifndef JETMESH_METAFINISH16_H
#define JETMESH_METAFINISH16_H
#include <stddef.h>
#include <stdint.h>

/* a corner faces its triangle above this cosine (metafinish.c) */
#define JM_FINISH_COS_MIN 0.02f

/* 1 where the kernels below run: the CPU has AVX-512 with VL
 * (jm_cpu_avx512 and the 128-bit masked loads) and no test turned them
 * off; nothing else about them can fail. */
int jm_finish16_ok(void);

/* Triangles t0 .. t0 + 15 of idx at positions P with unit normals N: as
 * tri_sag in metafinish.c, each triangle's chord sag (x24) times its area
 * over 24 into as[l] and its area into area[l] (l = t - t0), each lane with
 * the float operations of the one-triangle code in its order. */
void jm_finish_sag16(const float *P, const float *N, const uint32_t *idx, size_t t0, float *as, float *area);

/* The first fold round on triangles t0 .. t0 + 15, as metafinish.c's
 * folds(P, N, D, v, moved) then stored_away(N, v, moved) (when facing): bit
 * l of the result set where triangle t0 + l folds, bit 16 + l where one of
 * its corners does not face its moved normal. */
uint32_t jm_finish_fold16(const float *P, const float *N, const float *D, const uint32_t *idx, size_t t0, int facing);

/* The same two kernels on 8 triangles, two a 256-bit register
 * (metafinish8.c), where jm_finish8_ok(): the CPU has AVX2. */
int jm_finish8_ok(void);
void jm_finish_sag8(const float *P, const float *N, const uint32_t *idx, size_t t0, float *as, float *area);
uint32_t jm_finish_fold8(const float *P, const float *N, const float *D, const uint32_t *idx, size_t t0, int facing);

/* Tests only (tests/test_simd_pairs.c): the widest kernels jm_meta_finish
 * may run, 16 (the default), 8 (AVX2's, not AVX-512's) or 1 (its
 * one-at-a-time code); jm_finish_width() the setting. */
void jm_finish_set_width(int lanes);
int jm_finish_width(void);
#endif

/* metafinish16.h - the metasphere finish's per-triangle kernels, 16 triangles per AVX-512 pass, with the bits of metafinish.c's one-at-a-time ones. */
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
 * tri_sag in metafinish.c, each triangle's normal (x2 area: (p0 - p2) x
 * (p1 - p0), a +0 fourth float) into C + 4 t, its chord sag (x24) times
 * its area over 24 into as[l] and its area into area[l] (l = t - t0), each
 * lane with the float operations of the one-triangle code in its order. */
void jm_finish_sag16(const float *P, const float *N, const uint32_t *idx, size_t t0, float *C, float *as,
                     float *area);

/* The first fold round on triangles t0 .. t0 + 15, as metafinish.c's
 * folds(P, N, D, v, C + 4 t) then stored_away (when facing): bit l of the
 * result set where triangle t0 + l folds, bit 16 + l where one of its
 * corners does not face its moved normal; that moved normal replaces the
 * one in C + 4 t (a +0 fourth float). */
uint32_t jm_finish_fold16(const float *P, const float *N, const float *D, const uint32_t *idx, size_t t0, float *C,
                          int facing);

/* Tests only (tests/test_simd_pairs.c): 0 turns the kernels off, so that
 * jm_meta_finish runs its one-at-a-time code; 1 (the default) on again. */
void jm_finish16_enable(int on);
#endif

/* metafinish16.h - the metasphere finish's per-triangle kernels, 16 triangles per AVX-512 pass (8 per AVX2 pass), with the bits of metafinish.c's one-at-a-time ones. */
#ifndef JETMESH_METAFINISH16_H
#define JETMESH_METAFINISH16_H
#include <stddef.h>
#include <stdint.h>

/* a corner faces its triangle above this cosine (metafinish.c) */
#define JM_FINISH_COS_MIN 0.02f

/* 1 where the kernels below run: cpu.h's level is AVX-512 (with VL, for
 * the 128-bit masked loads); nothing else about them can fail. */
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
 * (metafinish8.c), where jm_finish8_ok(): cpu.h's level is AVX2 or more. */
int jm_finish8_ok(void);
void jm_finish_sag8(const float *P, const float *N, const uint32_t *idx, size_t t0, float *as, float *area);
uint32_t jm_finish_fold8(const float *P, const float *N, const float *D, const uint32_t *idx, size_t t0, int facing);

#endif

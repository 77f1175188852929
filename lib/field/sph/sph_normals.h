/* sph_normals.h - SPH normals: the particles near a part of a block gathered in groups of 8, the kernel's gradient summed at each vertex. */
#ifndef JETMESH_SPH_NORMALS_H
#define JETMESH_SPH_NORMALS_H
#include "field/field.h"

/* SPH particles near a block, in groups of 8: x[8], y[8], z[8], weight[8]. */
typedef struct jm_soa {
    float *buf;
    size_t n, cap;    /* particles (n = SIZE_MAX: out of memory), capacity */
    jm_mem *mem;      /* counts buf (NULL: uncounted) */
} jm_soa;

/* Gathers the particles whose support reaches the box [lo, hi]
 * (sph_normals.c). */
void jm_sph_gather(const jm_grid *g, const jm_config *c, const jm_hood *hood, const float lo[3], const float hi[3],
                   jm_soa *out);
/* SPH outward unit normal at p from the gathered particles; 0 if the
 * gradient vanishes (nrm untouched). */
int jm_sph_normal(const jm_config *c, const jm_soa *s, const float p[3], float nrm[3]);
/* jm_sph_normal for the count vertices idx[] (positions pos, normals into
 * nrm, 3 floats a vertex), two at a time in one AVX-512 register where the
 * CPU has them: the same bits. */
void jm_sph_normals(const jm_config *c, const jm_soa *s, const uint32_t *idx, size_t count, const float *pos,
                    float *nrm);
#endif

/* aniso_normals.h - unit normals of the anisotropic SPH field at mesh vertices, two at a time (AVX-512) or one (C). */
#ifndef JETMESH_ANISO_NORMALS_H
#define JETMESH_ANISO_NORMALS_H
#include "field/aniso/anisotropy.h"

/* Outward unit normal at p: minus the field's gradient over the gathered
 * kernels; 0 if it vanishes (nrm untouched). The gradient sums 8 float
 * lanes (lane t the kernels t mod 8, in order), then the lanes in order. */
int jm_aniso_normal(const jm_an_list *l, const float p[3], float nrm[3]);
/* jm_aniso_normal at the vertices idx[0..count) of pos into nrm (3 floats
 * each), with the same bits (two vertices per pass where the CPU has
 * AVX-512). */
void jm_aniso_normals(const jm_an_list *l, const uint32_t *idx, size_t count, const float *pos, float *nrm);
#endif

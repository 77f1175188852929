/* aniso_normals.h - unit normals of the anisotropic SPH field at mesh vertices, each vertex settled onto the surface by a Newton step, two at a time (AVX-512) or one (C). */
#ifndef JETMESH_ANISO_NORMALS_H
#define JETMESH_ANISO_NORMALS_H
#include "field/aniso/anisotropy.h"

/* Outward unit normal at p: minus the field's gradient over the gathered
 * kernels. p is a vertex on a lattice edge (cube h) whose unit direction,
 * from its inside node to its outside node, nrm holds on entry (the
 * marching's fallback normal): p moves along it by one Newton step onto
 * the level thr, (phi - thr) / (-grad phi . e), at most a quarter cube
 * and kept within the edge (JM_T_MIN from either node). Both untouched
 * (returns 0) where the gradient vanishes. The gradient and the value phi
 * sum 8 float lanes (lane t the kernels t mod 8, in order), then the lanes
 * in order. */
int jm_aniso_normal(const jm_an_list *l, float thr, float h, float p[3], float nrm[3]);
/* jm_aniso_normal at the vertices idx[0..count) of pos into nrm (3 floats
 * each), with the same bits (two vertices per pass where the CPU has
 * AVX-512). */
void jm_aniso_normals(const jm_an_list *l, float thr, float h, const uint32_t *idx, size_t count, float *pos,
                      float *nrm);
#endif

/* uv.h - texture coordinates that depend only on world position, normal and parameters. */
#ifndef JETMESH_UV_H
#define JETMESH_UV_H
#include "core/internal.h"

/* Texture coordinates of one vertex. */
void jm_uv(const jm_config *c, const float p[3], const float n[3], float uv[2]);
/* jm_uv of nv vertices (pos, nrm: 3 floats each; uv: 2), the same values */
void jm_uv_all(const jm_config *c, const float *pos, const float *nrm, float *uv, size_t nv);
#endif

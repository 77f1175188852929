/* sph_field.h - the isotropic SPH field's stages (field_ops.h). */
#ifndef JETMESH_SPH_FIELD_H
#define JETMESH_SPH_FIELD_H
#include "field/field_ops.h"

extern const jm_field_ops jm_sph_field;
#endif

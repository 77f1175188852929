/* aniso_field.h - the anisotropic SPH field's stages (field_ops.h). */
#ifndef JETMESH_ANISO_FIELD_H
#define JETMESH_ANISO_FIELD_H
#include "field/field_ops.h"

extern const jm_field_ops jm_aniso_field;
#endif

/* meta_field.h - the metasphere field's stages (field_ops.h). */
#ifndef JETMESH_META_FIELD_H
#define JETMESH_META_FIELD_H
#include "field/field_ops.h"

extern const jm_field_ops jm_meta_field;
#endif

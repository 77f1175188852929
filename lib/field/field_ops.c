/* field_ops.c - the one place that chooses a frame's field from its configuration. */
#include "field/field_ops.h"
#include "field/sph/sph_field.h"
#include "field/aniso/aniso_field.h"
#include "field/meta/meta_field.h"

const jm_field_ops *jm_field_ops_of(const jm_config *c)
{
    if (c->field == JM_FIELD_METASPHERE) return &jm_meta_field;
    return c->aniso ? &jm_aniso_field : &jm_sph_field;
}

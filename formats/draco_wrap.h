/* draco_wrap.h - C interface to the libdraco encoder: a jm_mesh in, a compressed Draco mesh buffer out. */
#ifndef JETMESH_FORMATS_DRACO_WRAP_H
#define JETMESH_FORMATS_DRACO_WRAP_H

#include <stddef.h>
#include "reader.h" /* jmf_status */
#include "../lib/jetmesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Defaults (used for fields <= 0). Draco quantizes positions on one grid
 * over the mesh's largest extent L, so 16 bits is a step of L/65535 (error
 * at most half that per axis); normals get 10 bits (octahedral, about 0.1
 * degree) and uvs 12. Speed 5 (Draco's middle setting, the standard
 * Edgebreaker coder) encodes and decodes faster than speeds 0-4 (the
 * valence coder: 5-13% smaller files on the jet sample). The speed never
 * changes the geometry: the face list is kept exactly at every
 * speed, and whether a sliver triangle collapses (two corners on the same
 * grid point) depends on the position bits alone. Measured on the jet
 * sample (frame 99, -r 0.025 -c 0.25: 76730 vertices, shortest edge
 * 1.5e-5 over L = 4.7): 259 of 153412 triangles collapse at 16 bits at
 * every speed 0-10, 2 at 18 bits, none at 20 bits (27% larger file). */
#define JMF_DRACO_POSITION_BITS 16
#define JMF_DRACO_NORMAL_BITS 10
#define JMF_DRACO_UV_BITS 12
#define JMF_DRACO_SPEED 5
/* Per-vertex attributes (velocity, density...) as Draco GENERIC attributes:
 * each quantised over its own largest component range R, so 16 bits keep
 * every value within R/65535/2 (a velocity of range 10 m/s: 8e-5 m/s). */
#define JMF_DRACO_ATTRIBUTE_BITS 16

typedef struct jmf_draco_params {
    int position_bits; /**< 1-30; <= 0: JMF_DRACO_POSITION_BITS */
    int normal_bits;   /**< 1-30; <= 0: JMF_DRACO_NORMAL_BITS */
    int uv_bits;       /**< 1-30; <= 0: JMF_DRACO_UV_BITS */
    int speed;         /**< 0 (best compression) - 10 (fastest); < 0: JMF_DRACO_SPEED */
    int attribute_bits; /**< generic attributes: 1-30; <= 0: JMF_DRACO_ATTRIBUTE_BITS */
} jmf_draco_params;

/** A Draco-compressed mesh, owned by the caller: free with jmf_draco_blob_free(). */
typedef struct jmf_draco_blob {
    unsigned char *data;
    size_t size;
    size_t num_points; /**< points a decoder will produce */
    size_t num_faces;  /**< triangles a decoder will produce */
    int position_id;   /**< Draco unique attribute ids (for KHR_draco_mesh_compression) */
    int normal_id;     /**< -1 when the mesh has no normals */
    int uv_id;         /**< -1 when the mesh has no uvs */
    int *attribute_ids; /**< the generic attributes' unique ids, in the order given */
    size_t attribute_count;
} jmf_draco_blob;

/** Fills p with the defaults. */
void jmf_draco_params_default(jmf_draco_params *p);

/**
 * Encodes positions, normals (when present) and uvs (when present) with the
 * Edgebreaker coder. A mesh without triangles is refused (JMF_E_UNSUPPORTED):
 * the Draco coder cannot store an empty mesh. name is used in messages.
 */
jmf_status jmf_draco_encode(const jm_mesh *mesh, const jmf_draco_params *p,
                            const char *name, jmf_draco_blob *out,
                            char *err, size_t errlen);

/**
 * jmf_draco_encode with per-vertex attributes (values: components per mesh
 * vertex, 1 to 4) as Draco GENERIC attributes, each named by an attribute
 * metadata entry "name" (what draco3d's GetAttributeIdByMetadataEntry finds),
 * quantised with p->attribute_bits; their unique ids in out->attribute_ids.
 */
jmf_status jmf_draco_encode_attributes(const jm_mesh *mesh, const jmf_attribute *attrs, size_t nattrs,
                                       const jmf_draco_params *p, const char *name, jmf_draco_blob *out,
                                       char *err, size_t errlen);

/** Frees the buffer and zeroes the blob. NULL is allowed. */
void jmf_draco_blob_free(jmf_draco_blob *blob);

#ifdef __cplusplus
}
#endif
#endif

/* gltf_wrap.h - C interface to the tinygltf-based glTF 2.0 builder: a jm_mesh in, .gltf/.bin or .glb bytes out. */
#ifndef JETMESH_FORMATS_GLTF_WRAP_H
#define JETMESH_FORMATS_GLTF_WRAP_H

#include <stddef.h>
#include "../reader.h" /* jmf_status */
#include "../draco_wrap.h"
#include "../../lib/jetmesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum jmf_gltf_container {
    JMF_GLTF_SEPARATE = 0, /**< .gltf JSON + a .bin beside it (out->bin) */
    JMF_GLTF_EMBEDDED,     /**< .gltf JSON with the buffer as a base64 data: URI */
    JMF_GLTF_BINARY        /**< .glb */
} jmf_gltf_container;

typedef struct jmf_gltf_params {
    jmf_gltf_container container;
    const char *bin_uri;     /**< SEPARATE: the buffer's URI, e.g. "mesh.bin" (percent-encoded here) */
    const char *generator;   /**< asset.generator; NULL: "jetmesh " JM_VERSION_STRING */
    int z_up;                /**< rotate (x, y, z) -> (x, z, -y) (positions and normals) */
    int draco;               /**< compress with KHR_draco_mesh_compression */
    jmf_draco_params draco_params;
    const char *name;        /**< the output's name, for messages */
    const jmf_attribute *attributes; /**< per-vertex, written as "_NAME" accessors
                                          (FLOAT, SCALAR/VEC2/VEC3/VEC4; 3-vectors
                                          rotated with z_up); with draco, Draco
                                          GENERIC attributes in the compressed
                                          primitive (the extension maps "_NAME"
                                          to their ids) */
    size_t attribute_count;
} jmf_gltf_params;

/** One range of a buffer's bytes. */
typedef struct jmf_gltf_piece {
    const unsigned char *data;
    size_t size;
} jmf_gltf_piece;

/**
 * The bytes to write: free with jmf_gltf_output_free().
 * SEPARATE: main is the .gltf, bin the .bin (bin_size 0: no .bin needed).
 * EMBEDDED: main is the .gltf, bin is empty.
 * BINARY: the .glb is main, then bin, then bin_pad zero bytes (main holds
 * the GLB header, the JSON chunk and the BIN chunk's header).
 * bin is bin_pieces ranges, bin_size bytes in all, written in order: most
 * point into the mesh's own arrays (not copied), so write them before the
 * mesh changes or is freed.
 */
typedef struct jmf_gltf_output {
    unsigned char *main;
    size_t main_size;
    const jmf_gltf_piece *bin;
    size_t bin_pieces;
    size_t bin_size;
    size_t bin_pad;
    void *priv;
} jmf_gltf_output;

/**
 * Builds a glTF 2.0 asset: one scene, one node, one mesh with one triangle
 * primitive (POSITION with min/max, NORMAL, TEXCOORD_0, indices as
 * UNSIGNED_SHORT when every index is below 65535, else UNSIGNED_INT) and a
 * plain material. A mesh without triangles gives a scene with one empty
 * node, no mesh and no buffer.
 */
jmf_status jmf_gltf_build(const jm_mesh *mesh, const jmf_gltf_params *p,
                          jmf_gltf_output *out, char *err, size_t errlen);

/** Frees what jmf_gltf_build returned and zeroes out. NULL is allowed. */
void jmf_gltf_output_free(jmf_gltf_output *out);

#ifdef __cplusplus
}
#endif
#endif

/* writer.h - writes a jetmesh mesh to OBJ, glTF/GLB (tinygltf), Draco, PLY or VTK, atomically. */
#ifndef JETMESH_FORMATS_WRITER_H
#define JETMESH_FORMATS_WRITER_H

#include <stddef.h>
#include "reader.h"       /* jmf_status */
#include "atomic_file.h"
#include "../lib/jetmesh.h"

#ifdef __cplusplus
extern "C" {
#endif

typedef enum jmf_output_format {
    JMF_OUT_AUTO = 0, /**< from the extension (.obj .gltf .glb .drc .ply .vtk;
                           ".draco.glb"/".draco.gltf" mean glTF with Draco) */
    JMF_OUT_OBJ,
    JMF_OUT_GLTF,     /**< .gltf + .bin beside it (or embedded, see embed) */
    JMF_OUT_GLB,
    JMF_OUT_DRC,      /**< bare Draco mesh */
    JMF_OUT_PLY,      /**< binary little-endian PLY */
    JMF_OUT_VTK       /**< legacy VTK polydata, binary */
} jmf_output_format;

typedef struct jmf_write_options {
    jmf_output_format format; /**< JMF_OUT_AUTO by default */
    int draco;                /**< glTF/GLB: compress with KHR_draco_mesh_compression */
    int embed;                /**< .gltf: embed the buffer as a data: URI */
    int z_up;                 /**< 1: the simulation is +Z up; rotate to glTF's
                                   +Y up (x, y, z) -> (x, z, -y) for glTF/GLB */
    int draco_position_bits;  /**< default: the fewest bits from 16 to 24 at which no
                                   triangle collapses under quantisation */
    int draco_normal_bits;    /**< default 10 */
    int draco_uv_bits;        /**< default 12 */
    int draco_speed;          /**< 0-10 encoder speed; default 5 */
    const char *generator;    /**< asset.generator; default "jetmesh <version>" */
    int no_sync;              /**< 1: do not fsync outputs before renaming them */
    const jmf_attribute *attributes; /**< per-vertex attributes (values: components
                                   per mesh vertex; names of letters, digits and
                                   '_'), e.g. from jm_interpolate_attributes:
                                   glTF "_NAME" accessors (upper case; 3-vectors
                                   rotated with z_up; with Draco, GENERIC
                                   attributes in the compressed primitive), .drc
                                   GENERIC attributes named by metadata, PLY
                                   properties, VTK point data. OBJ cannot hold
                                   them: an error. */
    size_t attribute_count;
} jmf_write_options;

/**
 * Writes mesh to path. Every file is written to a temporary file beside its
 * target and renamed into place when complete, so a failure never leaves a
 * truncated file and never damages an existing one. out_bytes (may be NULL)
 * receives the bytes written (all files). On failure, err gets one line
 * naming the file and the cause.
 */
jmf_status jmf_write_mesh(const char *path, const jm_mesh *mesh,
                          const jmf_write_options *opt, size_t *out_bytes,
                          char *err, size_t errlen);

/** An output written completely to temporaries (flushed to the kernel; not
 *  yet synced or renamed into place): a .gltf's .bin comes first. */
typedef struct jmf_staged {
    jmf_atomic_file files[2];
    int count;
} jmf_staged;

/** jmf_write_mesh, stopping short of the renames: on success out_staged
 *  holds the finished temporaries, for jmf_staged_publish (renames them
 *  in order) or jmf_staged_abort (removes them). On failure nothing is
 *  left. Lets a converter write frames ahead and publish them in order. */
jmf_status jmf_write_mesh_staged(const char *path, const jm_mesh *mesh, const jmf_write_options *opt,
                                 size_t *out_bytes, jmf_staged *out_staged, char *err, size_t errlen);
/** Syncs (unless no_sync) and renames the staged files in order, as one
 *  (jmf_atomic_publish_all): a signal sees both renames or neither. */
jmf_status jmf_staged_publish(jmf_staged *s, char *err, size_t errlen);
/** Accepts NULL and an empty stage. */
void jmf_staged_abort(jmf_staged *s);

/** The format jmf_write_mesh would use for path and opt (resolves AUTO);
 *  sets *out_draco for the ".draco.glb" convention. -1 if unknown. */
int jmf_output_format_for(const char *path, const jmf_write_options *opt, int *out_draco);

/** 1 when format f (jmf_output_format; draco: glTF with Draco) can hold
 *  per-vertex attributes. */
int jmf_format_holds_attributes(int f, int draco);
/** JMF_OK when opt's attributes can be written to path in format f; else
 *  an error message naming the file and what can hold them. */
jmf_status jmf_check_attributes(const char *path, int f, int draco, const jm_mesh *mesh,
                                const jmf_write_options *opt, char *err, size_t errlen);

/** "obj", "gltf", ... */
const char *jmf_output_format_name(jmf_output_format f);
/** Parses a name as given to --format ("obj", "gltf", "glb", "drc", "ply",
 *  "vtk"); -1 if unknown. */
int jmf_output_format_parse(const char *name);

#ifdef __cplusplus
}
#endif
#endif

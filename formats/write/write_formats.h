/* write_formats.h - the C writers behind jmf_write_mesh (OBJ, PLY, VTK), each into an already opened atomic file. */
#ifndef JETMESH_FORMATS_WRITE_FORMATS_H
#define JETMESH_FORMATS_WRITE_FORMATS_H

#include <stddef.h>
#include "../atomic_file.h"
#include "../reader.h" /* jmf_attribute */
#include "../../lib/jetmesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* Each writes the whole mesh to af (normals and uvs when not NULL) and
 * returns JMF_OK, or JMF_E_IO / JMF_E_LIMIT with a one-line message in err;
 * the caller commits or aborts af. generator goes into a header comment. */

/** Wavefront OBJ: v, vt, vn, "f a/a/a" (1-based). */
jmf_status jmf_write_obj(jmf_atomic_file *af, const jm_mesh *mesh,
                         const char *generator, char *err, size_t errlen);

/** PLY, binary little-endian: x y z [nx ny nz] [s t] floats; face list uchar uint. */
jmf_status jmf_write_ply(jmf_atomic_file *af, const jm_mesh *mesh,
                         const char *generator, char *err, size_t errlen);

/** Legacy VTK 3.0 POLYDATA, binary (big-endian): POINTS, POLYGONS,
 *  POINT_DATA NORMALS and TEXTURE_COORDINATES. */
jmf_status jmf_write_vtk(jmf_atomic_file *af, const jm_mesh *mesh,
                         const char *generator, char *err, size_t errlen);

/** Per-vertex attributes (jmf_write_options.attributes) too: PLY as float
 *  vertex properties NAME (1 component) or NAME_x NAME_y NAME_z [NAME_w];
 *  VTK as a POINT_DATA FIELD array NAME with its components. */
jmf_status jmf_write_ply_attrs(jmf_atomic_file *af, const jm_mesh *mesh, const jmf_attribute *attrs,
                               size_t nattrs, const char *generator, char *err, size_t errlen);
jmf_status jmf_write_vtk_attrs(jmf_atomic_file *af, const jm_mesh *mesh, const jmf_attribute *attrs,
                               size_t nattrs, const char *generator, char *err, size_t errlen);

/** Formats v like printf("%.7g") (ties may differ in the last digit), much
 *  faster. out needs JMF_FLOAT_CHARS bytes; returns the length, NUL added. */
#define JMF_FLOAT_CHARS 16
size_t jmf_format_float(char *out, float v);

#ifdef __cplusplus
}
#endif
#endif

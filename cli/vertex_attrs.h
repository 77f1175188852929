/* vertex_attrs.h - --attributes: which per-particle arrays a run carries onto its meshes, and their interpolation per frame. */
#ifndef JETMESH_CLI_VERTEX_ATTRS_H
#define JETMESH_CLI_VERTEX_ATTRS_H

#include <stddef.h>

#include "../formats/reader.h"
#include "../lib/jetmesh.h"
#include "inputs.h"

/** --attributes all: the arrays of the first frame that reads, as a list
 *  ("velocity,density") the whole run then asks every frame for (a later
 *  frame without one of them fails, naming the file and the attribute).
 *  *out (malloc'd) is NULL when the option was not "all". 0 on success;
 *  else prints why and returns the exit status. */
int vattrs_resolve_all(const char *attributes, const jmf_read_options *read, inputs *frames, char **out);

/** The frame's attributes interpolated to mesh's vertices on ctx, the
 *  context that made mesh (jm_context_interpolate: its threads and
 *  parameters), named as in the file with any character
 *  other than a letter, digit or '_' made '_'. *out (n of them) is freed
 *  with vattrs_free. JM_OK or the library's status. */
jm_status vattrs_make(jm_context *ctx, const jmf_frame *fr, const jm_mesh *mesh, jmf_attribute **out,
                      size_t *n);
void vattrs_free(jmf_attribute *a, size_t n);

#endif

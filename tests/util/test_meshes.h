/* test_meshes.h - small closed triangle meshes built by hand for the writer tests and tools. */
#ifndef JETMESH_TESTS_TEST_MESHES_H
#define JETMESH_TESTS_TEST_MESHES_H

#include <stddef.h>
#include <stdint.h>
#include "../../lib/jetmesh.h"

/** A mesh that owns its arrays; mesh points into them. */
typedef struct test_mesh {
    jm_mesh mesh;
    float *positions, *normals, *uvs;
    uint32_t *indices;
} test_mesh;

/**
 * Builds a named mesh, all closed, outward-oriented, with unit normals and
 * uvs: "octahedron" (6 vertices), "icosphere" or "icosphere:L" (L
 * subdivisions, default 2: 162 vertices), "torus:NUxNV" (NU*NV vertices,
 * centred at (10, -5, 3), radii 2 and 0.75), "grid" (= torus:280x250, 70000
 * vertices: needs 32-bit indices), "empty" (0 vertices, 0 triangles).
 * Returns 0, or -1 for an unknown name or no memory.
 */
int test_mesh_make(const char *name, test_mesh *out);

/**
 * Copies a mesh (the library's, which its context owns and overwrites)
 * into arrays of its own; normals and uvs only where m has them. Returns
 * 0, or -1 for no memory.
 */
int test_mesh_copy(const jm_mesh *m, test_mesh *out);

/** Frees the arrays and zeroes the mesh. */
void test_mesh_free(test_mesh *tm);

#endif

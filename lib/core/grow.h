/* grow.h - arrays that grow across a frame (the mesh's outputs) without being copied. */
#ifndef JETMESH_GROW_H
#define JETMESH_GROW_H
#include "core/internal.h"

/* Like jm_realloc (counted in m, NULL on failure with p untouched), for
 * arrays that grow often and large: from JM_GROW_MAP bytes on, Linux
 * keeps them in their own mappings that grow by moving pages (mremap),
 * so neither the bytes are copied nor the pages touched again. The sizes
 * given must be those of the array's last jm_grow. */
void *jm_grow(jm_mem *m, void *p, size_t old_bytes, size_t new_bytes);
/* Frees an array of jm_grow (bytes: its size there); NULL is fine. */
void jm_grow_free(jm_mem *m, void *p, size_t bytes);

/* Does an array of this many bytes grow and shrink by moving pages
 * (no copy), so that it can grow in small steps? */
int jm_grow_moves(size_t bytes);

#define JM_GROW_MAP ((size_t)1 << 20)
#endif

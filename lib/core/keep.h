/* keep.h - a context's freed working memory, kept in size classes for its next frames: after the first, a frame as large allocates nothing. */
#ifndef JETMESH_KEEP_H
#define JETMESH_KEEP_H
#include <stddef.h>

/* Blocks of at most JM_KEEP_MAX bytes that a context frees are kept (up
 * to JM_KEEP_BUDGET bytes in all) and handed out again by its next
 * allocations of the same size class (sizes rounded up to 4 steps an
 * octave), so a frame that takes its memory as the last one did makes no
 * call to malloc or free. Like memory that malloc keeps after free, the
 * kept blocks are not counted in jm_mem (peak_bytes, max_bytes). */
#define JM_KEEP_MAX ((size_t)4 << 20)
#define JM_KEEP_BUDGET ((size_t)32 << 20)

typedef struct jm_keep jm_keep;
jm_keep *jm_keep_create(void);        /* NULL if out of memory */
void jm_keep_destroy(jm_keep *k);     /* frees every kept block; NULL allowed */
/* The bytes a block asked for bytes (<= JM_KEEP_MAX) really holds. */
size_t jm_keep_class_bytes(size_t bytes);
/* A block for bytes (<= JM_KEEP_MAX): a kept one of its class, else a new
 * one of jm_keep_class_bytes(bytes); NULL if out of memory. */
void *jm_keep_take(jm_keep *k, size_t bytes);
/* Block p of bytes asked for (from jm_keep_take) kept, or freed when the
 * budget is full. */
void jm_keep_give(jm_keep *k, void *p, size_t bytes);
#endif

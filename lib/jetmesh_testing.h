/* jetmesh_testing.h - hooks for tests and measurement only: not part of the stable API (as zstd's static-linking-only section). */
#ifndef JETMESH_TESTING_H
#define JETMESH_TESTING_H
/*
 * Nothing here is needed to mesh particles. These calls may change or go
 * in any release; they exist so that tests can reach paths the CPU or the
 * data would not take, and benchmarks can say what they measured. They are
 * process-wide and not thread-safe against frames in flight: set them
 * between frames.
 */
#include <stddef.h>
#include "jetmesh.h"

#ifdef __cplusplus
extern "C" {
#endif

/* ---- the vector kernels (lib/core/cpu.c, the library's one CPU dispatch) */
enum {
    JM_TESTING_CPU_PLAIN = 0,  /* plain C */
    JM_TESTING_CPU_SSE2 = 1,   /* 4 lanes */
    JM_TESTING_CPU_AVX2 = 2,   /* 8 lanes, AVX2 and FMA */
    JM_TESTING_CPU_AVX512 = 3, /* 16 lanes, x86-64-v4 */
};
/* Runs the kernels of level at most `level` from the next kernel call on
 * (-1: the CPU's best again) and returns the level that will run (a level
 * above the CPU's runs the CPU's). Every path gives the same bits, so the
 * meshes must not change (tests/t_splat_variants.sh; the CLI reads
 * JETMESH_TESTING_CPU). Under a forced level the
 * metasphere finish also starts its triangle lists small, to run their
 * overflow path. */
int jm_testing_force_cpu(int level);
/* The level running now, in words ("AVX-512", "AVX2 and FMA, no AVX-512",
 * "SSE2", "plain C"), for benchmark reports. */
const char *jm_testing_cpu_name(void);

/* ---- the SPH culling (docs/culling.md) */
/* on = 1 samples every node of every block (no block or node is proved
 * inside or outside first): the same mesh, slower; tests compare the two.
 * Kept in jm_params' reserved slot, where a zeroed struct leaves it off. */
static inline void jm_testing_no_culling(jm_params *p, int on) { p->reserved0 = on; }

/* ---- the SPH grid's memory (lib/grid/release.c) */
/* key_order 0 numbers an SPH grid's cells by first appearance (no release
 * possible); release 0 turns the release of particles behind the block
 * sweep off, 2 makes released pages unreadable (a read faults) until the
 * grid is freed; page, a power of two and a multiple of the system's page,
 * is the unit released (0: 2 MiB). Defaults: 1, 1, 0. */
void jm_testing_grid_mode(int key_order, int release, size_t page);

#ifdef __cplusplus
}
#endif
#endif

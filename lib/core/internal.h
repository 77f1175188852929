/* internal.h - types and helpers shared by the library's translation units (not installed). */
#ifndef JETMESH_INTERNAL_H
#define JETMESH_INTERNAL_H

#include "jetmesh.h"
#include <stdint.h>
#include <stddef.h>
#include <math.h>

/* ---- memory accounting (alloc.c): every heap byte of a context is counted */
typedef struct jm_mem {
    _Atomic size_t current;
    _Atomic size_t peak;
    size_t limit;          /* 0: none; else an allocation that would take
                              current past it fails (NULL) and sets over */
    _Atomic int over;      /* an allocation was refused for the limit */
    _Atomic size_t refused; /* the largest total such an allocation needed */
    struct jm_keep *keep;  /* a context's: its freed blocks kept for its next
                              allocations (keep.h); NULL: none */
} jm_mem;
void jm_mem_add(jm_mem *m, size_t bytes); /* count memory allocated elsewhere */
void jm_mem_sub(jm_mem *m, size_t bytes);
/* Counts bytes about to be allocated elsewhere, against the limit: 1, or 0
 * (nothing counted, over set) when it would pass the limit. */
int jm_mem_take(jm_mem *m, size_t bytes);

void *jm_alloc(jm_mem *m, size_t bytes);            /* NULL on failure or overflow */
void *jm_calloc(jm_mem *m, size_t n, size_t size);
/* Like jm_alloc, at an address a multiple of align (a power of two, a
 * multiple of sizeof(void *)); freed by jm_free. */
void *jm_alloc_aligned(jm_mem *m, size_t bytes, size_t align);
void *jm_realloc(jm_mem *m, void *p, size_t old_bytes, size_t new_bytes);
void jm_free(jm_mem *m, void *p, size_t bytes);
/* For the arrays a context keeps from frame to frame (its mesh, the
 * workers' scratch and block outputs): as jm_alloc and jm_realloc, but a
 * new block never comes from m's kept blocks (keep.h), which stay for the
 * frame's passing arrays: a frame then finds every block the last one
 * freed (a growing array would otherwise take one for good); freed, they
 * are kept like any other. */
void *jm_alloc_lasting(jm_mem *m, size_t bytes);
void *jm_realloc_lasting(jm_mem *m, void *p, size_t old_bytes, size_t new_bytes);
/* Allocates or frees, uncounted, as jm_alloc_lasting and jm_free do (for
 * memory counted elsewhere: grow.c); m may be NULL. */
void *jm_raw_alloc(jm_mem *m, size_t bytes);
void jm_raw_free(jm_mem *m, void *p, size_t bytes);
#include "core/heap_calls.h"
/* Advises the kernel to back [p, p + bytes) with huge pages where it can
 * (Linux; elsewhere nothing): fewer page faults for large arrays. */
void jm_huge_advise(void *p, size_t bytes);
/* Multiplies with overflow check; returns 0 on overflow. */
int jm_mul_size(size_t a, size_t b, size_t *out);

/* ---- thread pool (pool.c) */
typedef struct jm_pool jm_pool;
typedef void (*jm_task_fn)(void *arg, size_t item, int worker);
/* Starts n-1 helper threads (the caller is worker 0). */
jm_status jm_pool_create(int nthreads, jm_pool **out);
void jm_pool_free(jm_pool *p);
int jm_pool_threads(const jm_pool *p);
/* Runs fn(arg, i, worker) for every i in [0, n), items handed out
 * dynamically in chunks of `chunk`; returns when all are done. */
void jm_pool_run(jm_pool *p, size_t n, size_t chunk, jm_task_fn fn, void *arg);

/* ---- time */
double jm_now_ms(void);

/* ---- resolved parameters */
#define JM_BOX_BINS 32
typedef struct jm_config {
    float r;           /* radius */
    float h;           /* cube edge, world */
    float inv_h;
    jm_field field;
    jm_method method;
    float threshold;
    float sph_h;       /* smoothing length, world */
    float support;     /* sph: 2*sph_h */
    float link;        /* metasphere link distance, world */
    float margin;      /* metasphere: node values clamped below -margin/r */
    float influence;   /* radius around a particle where it affects nodes */
    float cell;        /* cell size of the particle grid */
    int block;         /* cubes per block side */
    jm_uv_mode uv_mode;
    float uv_scale;
    int uv_axis;       /* 0 x, 1 y, 2 z */
    int normals;
    int templates;
    int compensate;    /* metasphere: offset vertices by the chord sag */
    int drop_cavities; /* remove inward shells smaller than a particle */
    size_t max_bytes;
    /* sph anisotropic kernels (anisotropy.c); influence is then raised per
     * frame to the largest reach of the frame's kernels */
    int aniso;
    float an_radius;   /* PCA neighbourhood radius, world */
    float an_lambda;   /* centre smoothing */
    float an_kr, an_ks, an_kn;
    int an_neps;
    int smooth_iters;        /* post.h: feature-weighted smoothing iterations */
    int smooth_normal_iters; /* normal smoothing iterations */
    int smooth_implicit;     /* 1: the steady smoothing (smooth.c) */
    float simplify_error;    /* world units; 0 = no simplification */
    /* metasphere vertices (metavertex.c) */
    float mv_tol;      /* a piece beating a vertex's value by more moves it (units of r) */
    float mv_tau;      /* normals blend the pieces within this of the maximum (units of r) */
    float mv_reach2s;  /* no piece exceeds threshold - mv_tol farther than this (squared) from its particle */
    int mv_links;      /* 1: the pieces near a surface point are all of its winner's particle or its links */
    float mv_check;    /* metasphere: a vertex whose value is off by more is settled again (units of r) */
    float mv_inv_r;    /* metasphere: 1.0f / r, once (the pieces' evaluations) */
    /* the unit of length (units.h): every length above is in units of 2^unit;
     * particle coordinates are multiplied by unit_in = 2^-unit as they are read */
    int unit;
    float unit_in;
    int cull;          /* sph: skip blocks proven outside, nodes proven inside (cull.c, aniso_cull.c) */
    /* sph: the box pass's lines (inside_boxes.h): a[k] - b[k] s for s in
     * world units, k = min(s * box_bin, JM_BOX_BINS - 1) */
    float box_a[JM_BOX_BINS], box_b[JM_BOX_BINS], box_bin;
    /* what is meshed and kept (select.c, small_pieces.c, clip.c; jetmesh.h,
     * "Selection and clipping"), in units; 0 = off */
    int sel_box;             /* particles outside [sel_lo, sel_hi] left out */
    float sel_lo[3], sel_hi[3];
    int sel_min_group;       /* particle groups smaller than this left out */
    float sel_link;          /* two particles closer than this: one group */
    double piece_min_volume; /* mesh pieces enclosing less removed */
    int clip;                /* 1: triangles outside [clip_lo, clip_hi] removed; 2: vertices clamped */
    float clip_lo[3], clip_hi[3];
} jm_config;

jm_status jm_config_resolve(const jm_params *in, jm_config *out, jm_params *out_filled);

/* ---- cubic spline kernel (sph) */
static inline float jm_cubic_w(float q) /* without the 1/(pi h^3) factor */
{
    float a = 2.0f - q, b = 1.0f - q;
    a = a > 0.0f ? a : 0.0f; /* not fmaxf: a libm call unless -ffinite-math-only */
    b = b > 0.0f ? b : 0.0f;
    return 0.25f * a * a * a - b * b * b;
}
static inline float jm_cubic_dw(float q) /* d/dq of jm_cubic_w */
{
    float a = 2.0f - q, b = 1.0f - q;
    a = a > 0.0f ? a : 0.0f;
    b = b > 0.0f ? b : 0.0f;
    return -0.75f * a * a + 3.0f * b * b;
}
#include "core/cpu.h" /* the CPU dispatch: jm_cpu_level, JM_KERNEL_* */
/* The outward unit normal from a field gradient summed in 8 lanes (gx[l],
 * gy[l], gz[l]): minus their sum in lane order, normalised; 0 if it
 * vanishes or is not finite (nrm untouched). */
static inline int jm_normal_from_lanes8(const float *gx, const float *gy, const float *gz, float nrm[3])
{
    float o[3] = {0, 0, 0};
    for (int l = 0; l < 8; l++) {
        o[0] -= gx[l];
        o[1] -= gy[l];
        o[2] -= gz[l];
    }
    float len = sqrtf(o[0] * o[0] + o[1] * o[1] + o[2] * o[2]);
    if (!(len > 0.0f) || !isfinite(len)) return 0;
    for (int a = 0; a < 3; a++) nrm[a] = o[a] / len;
    return 1;
}

/* ---- open-addressing hash map uint64 -> uint32 (hashmap.c) */
typedef struct jm_hashmap {
    uint64_t *keys;
    uint32_t *vals;
    size_t cap;        /* power of two */
    size_t count;
    unsigned shift;
} jm_hashmap;
#define JM_HASH_EMPTY UINT64_MAX
jm_status jm_hashmap_init(jm_hashmap *m, jm_mem *mem, size_t expected);
void jm_hashmap_free(jm_hashmap *m, jm_mem *mem);
/* Returns the slot's value pointer, inserting (val = UINT32_MAX) if absent. */
uint32_t *jm_hashmap_upsert(jm_hashmap *m, uint64_t key);
/* UINT32_MAX if absent. */
static inline uint32_t jm_hashmap_get(const jm_hashmap *m, uint64_t key)
{
    size_t mask = m->cap - 1;
    size_t i = (size_t)((key * 0x9E3779B97F4A7C15ull) >> m->shift);
    for (;;) {
        uint64_t k = m->keys[i];
        if (k == key) return m->vals[i];
        if (k == JM_HASH_EMPTY) return UINT32_MAX;
        i = (i + 1) & mask;
    }
}

/* ---- particles sorted into grid cells (grid.c) */
#define JM_KEY_BITS 21
#define JM_KEY_MAX ((int64_t)1 << JM_KEY_BITS)
static inline uint64_t jm_key3(int64_t x, int64_t y, int64_t z)
{
    return ((uint64_t)z << (2 * JM_KEY_BITS)) | ((uint64_t)y << JM_KEY_BITS) | (uint64_t)x;
}

/* jm_choose_field (field_choice.c) with the candidate checks it made in
 * *out_checks (may be NULL): at most JM_CHOICE_MAX_CHECKS, whatever the
 * particles (issue 30). */
#define JM_CHOICE_MAX_CHECKS ((size_t)1 << 24)
jm_status jm_choose_field_work(const jm_params *params, const jm_particles *in, jm_field *out_field,
                               jm_method *out_method, float *out_neighbours, size_t *out_checks);

typedef struct jm_grid {
    size_t n;             /* particles */
    float *pos;           /* 3n, sorted by cell */
    float *weight;        /* sph: V_j per sorted particle */
    uint32_t *nb_start;   /* metasphere: n+1 offsets into nb */
    uint32_t *nb;         /* metasphere: neighbour sorted indices within link */
    uint32_t *nb_owner;   /* metasphere: the particle each link starts from */
    float *nb_dir;        /* metasphere: per link the unit direction x, y, z and
                             the length D */
    size_t nb_count;
    size_t ncells;
    uint32_t *cell_start; /* ncells+1 offsets into pos */
    double *cell_wsum;    /* sph: per cell, the weight sum of its particles not isolated */
    uint32_t *cell_live;  /* sph: per cell, their count */
    int32_t *cell_coord;  /* 3 per cell, absolute cell coordinates */
    jm_hashmap cells;     /* key (relative coords) -> cell index */
    int64_t origin[3];    /* cell coordinate of relative zero */
    float cell;           /* cell size */
    float inv_cell;
    float lo[3], hi[3];   /* particle bounds */
    uint8_t *isolated;    /* per sorted particle: 1 if no neighbour in reach */
    size_t n_isolated;
    float *an;            /* sph anisotropic: JM_AN_STRIDE floats per sorted
                             particle (see anisotropy.h) */
    float an_reach;       /* largest |centre - x| + ellipsoid box half-side */
    float *an_cellbox;    /* sph anisotropic: per cell, 6 floats (lo x, y,
                             z, hi x, y, z): the union of its kernels' boxes
                             (not isolated; empty: lo > hi) */
    size_t refused_bytes; /* after a JM_E_TOO_LARGE of jm_grid_build: the
                             memory it would have needed */
    uint32_t *dense;      /* when the particles' box of cells is no bigger
                             than n: its cell indices (UINT32_MAX: empty),
                             x fastest, instead of the map cells */
    int64_t dense_lo[3];  /* absolute coordinates of its first cell */
    int64_t dense_n[3];   /* its cells per axis */
    /* sph: the cells numbered in key order (z slowest), so that the block
     * sweep can release the particles behind it (jm_grid_release_below) */
    uint32_t *first_rank; /* per cell: its number in order of first
                             appearance (the isolated particles' order) */
    uint32_t *slab_first; /* slab_n + 1 entries: the first cell of each cell
                             z from slab_z0 on (the last: ncells) */
    int64_t slab_z0;
    size_t slab_n;
    uint32_t rel_cells;   /* cells released so far (a prefix) */
    size_t rel[5];        /* bytes released of pos, weight, isolated,
                             cell_start, dense (no longer counted) */
    size_t aligned_min;   /* arrays of pos, weight, isolated, cell_start and
                             dense this large or larger are page-aligned
                             (jm_alloc_aligned); 0: none */
} jm_grid;


#endif

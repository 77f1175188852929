/* block.c - meshes one block: samples its field (field_ops.h), marches its cubes, welds vertices, adds normals/UVs. */
#include "extract/block.h"
#include "field/field_ops.h"
#include "field/meta/metasplat.h"
#include "field/aniso/aniso_boxes.h"
#include "field/sph/cull.h"
#include "field/sph/inside_boxes.h"
#include "extract/tables.h"
#include "extract/hood_cells.h"
#include "extract/uv.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* bytes the inside flags' buffer holds past the block's nodes (row_configs) */
#define JM_IN_SLACK 32

/* the box passes' work buffer: the isotropic one's or the anisotropic's */
static size_t box_bytes(void)
{
    const size_t a = jm_box_work_bytes(), b = jm_aniso_box_work_bytes();
    return a > b ? a : b;
}

size_t jm_scratch_bytes(int B)
{
    size_t n = (size_t)B + 1, nn = n * n * n;
    return nn * (sizeof(float) + 1 + 15 * sizeof(uint32_t)) + JM_IN_SLACK + n * n * (1 + JM_PAD(n) * sizeof(float)) + 3 * n * sizeof(float) +
           n * n * JM_PAD(n) * sizeof(float) + JM_CULL_SPAN_BYTES(n) + box_bytes();
}

int jm_scratch_init(jm_scratch *s, int B)
{
    size_t n = (size_t)B + 1, nn = n * n * n;
    memset(s, 0, sizeof *s);
    s->B = B;
    s->f = malloc(nn * sizeof *s->f);
    s->in = calloc(1, nn + JM_IN_SLACK); /* (defined bytes past a row's end) */
    s->win = malloc(nn * sizeof *s->win);
    s->pad = malloc(n * n * JM_PAD(n) * sizeof *s->pad);
    s->rowstate = malloc(n * n);
    s->vt = malloc(nn * 7 * sizeof *s->vt);
    s->touched = malloc(nn * 7 * sizeof *s->touched);
    s->x = malloc(3 * n * sizeof(float));
    s->part = malloc(n * n * JM_PAD(n) * sizeof *s->part);
    s->span = malloc(JM_CULL_SPAN_BYTES(n));
    s->boxes = malloc(box_bytes());
    if (!s->f || !s->in || !s->win || !s->pad || !s->rowstate || !s->vt || !s->touched || !s->x || !s->part || !s->span || !s->boxes) {
        jm_scratch_free(s);
        return 0;
    }
    s->y = s->x + n;
    s->z = s->y + n;
    memset(s->vt, 0xff, nn * 7 * sizeof *s->vt);
    return 1;
}

void jm_scratch_free(jm_scratch *s)
{
    free(s->f);
    free(s->in);
    free(s->win);
    free(s->pad);
    free(s->rowstate);
    free(s->vt);
    free(s->touched);
    free(s->x);
    free(s->hood.range);
    free(s->soa.buf);
    free(s->order);
    free(s->an_list.buf);
    free(s->an_cand.idx);
    jm_probe_free(&s->probe);
    jm_roots_free(&s->roots);
    jm_mnorm_free(&s->mnorm);
    free(s->part);
    free(s->span);
    free(s->boxes);
    memset(s, 0, sizeof *s);
}

void jm_bout_reset(jm_bout *o)
{
    o->nv = o->ni = o->np = o->nb = o->cells = 0;
    o->t_field = o->t_extract = o->t_attr = 0;
    o->failed = 0;
}

void jm_bout_free(jm_bout *o, jm_mem *mem)
{
    jm_free(mem, o->pos, o->capv * 3 * sizeof(float));
    jm_free(mem, o->nrm, o->capv * 3 * sizeof(float));
    jm_free(mem, o->uv, o->capv * 2 * sizeof(float));
    jm_free(mem, o->cand, o->capv * 2 * sizeof(uint32_t));
    jm_free(mem, o->tri, o->capt * sizeof(uint32_t));
    jm_free(mem, o->pend, o->capp * 2 * sizeof(uint32_t));
    jm_free(mem, o->bmap, o->capb * 2 * sizeof(uint32_t));
    memset(o, 0, sizeof *o);
}

/* grows array *p of *cap elements of `width` bytes to hold `need` elements */
static int grow(jm_mem *mem, void **p, size_t *cap, size_t need, size_t width)
{
    if (need <= *cap) return 1;
    size_t nc = *cap ? *cap : 256;
    while (nc < need) nc *= 2;
    void *q = jm_realloc_lasting(mem, *p, *cap * width, nc * width);
    if (!q) return 0;
    *p = q;
    *cap = nc;
    return 1;
}

static int grow_vertices(jm_mem *mem, jm_bout *o)
{
    if (o->nv < o->capv) return 1;
    size_t nc = o->capv ? o->capv * 2 : 256;
    float *p = jm_realloc_lasting(mem, o->pos, o->capv * 3 * sizeof(float), nc * 3 * sizeof(float));
    if (p) o->pos = p;
    float *n = p ? jm_realloc_lasting(mem, o->nrm, o->capv * 3 * sizeof(float), nc * 3 * sizeof(float)) : NULL;
    if (n) o->nrm = n;
    float *u = n ? jm_realloc_lasting(mem, o->uv, o->capv * 2 * sizeof(float), nc * 2 * sizeof(float)) : NULL;
    if (u) o->uv = u;
    uint32_t *cd = u ? jm_realloc_lasting(mem, o->cand, o->capv * 2 * sizeof(uint32_t), nc * 2 * sizeof(uint32_t)) : NULL;
    if (cd) o->cand = cd;
    if (!p || !n || !u || !cd) {
        /* keep the accounting right: shrink back what did grow */
        if (p) o->pos = jm_realloc_lasting(mem, o->pos, nc * 3 * sizeof(float), o->capv * 3 * sizeof(float));
        if (n) o->nrm = jm_realloc_lasting(mem, o->nrm, nc * 3 * sizeof(float), o->capv * 3 * sizeof(float));
        if (u) o->uv = jm_realloc_lasting(mem, o->uv, nc * 2 * sizeof(float), o->capv * 2 * sizeof(float));
        return 0;
    }
    o->capv = nc;
    return 1;
}

/* Sorts (slot, index) pairs by slot (distinct). They are made in scan
 * order, nearly sorted, but a vertex on the block's bottom face often
 * comes a row of the face before its neighbours: a few pairs by insertion,
 * more by radix, 8 bits a pass (tmp: room for the n pairs). */
static void sort_pairs(uint32_t *p, size_t n, uint32_t *tmp)
{
    if (n < 32) {
        for (size_t i = 1; i < n; i++) {
            uint32_t k = p[2 * i], v = p[2 * i + 1];
            size_t j = i;
            while (j > 0 && p[2 * (j - 1)] > k) {
                p[2 * j] = p[2 * (j - 1)];
                p[2 * j + 1] = p[2 * (j - 1) + 1];
                j--;
            }
            p[2 * j] = k;
            p[2 * j + 1] = v;
        }
        return;
    }
    uint32_t all = 0, *src = p, *dst = tmp;
    for (size_t i = 0; i < n; i++) all |= p[2 * i];
    for (int sh = 0; sh < 32 && all >> sh; sh += 8) {
        size_t at[257] = {0};
        for (size_t i = 0; i < n; i++) at[(src[2 * i] >> sh & 255) + 1]++;
        for (int b = 0; b < 256; b++) at[b + 1] += at[b];
        for (size_t i = 0; i < n; i++) {
            const size_t o = at[src[2 * i] >> sh & 255]++;
            dst[2 * o] = src[2 * i];
            dst[2 * o + 1] = src[2 * i + 1];
        }
        uint32_t *t = src;
        src = dst;
        dst = t;
    }
    if (src != p) memcpy(p, src, 2 * n * sizeof *p);
}

/* in[i] = f[i] > thr for i in [i0, i1); returns how many are inside */
#ifdef __SSE2__
#include <emmintrin.h>
static size_t classify_row(const float *f, uint8_t *in, int i0, int i1, float thr)
{
    const __m128 t = _mm_set1_ps(thr);
    const __m128i one = _mm_set1_epi8(1), zero = _mm_setzero_si128();
    __m128i acc = zero;
    int i = i0;
    for (; i + 16 <= i1; i += 16) {
        __m128i c0 = _mm_castps_si128(_mm_cmpgt_ps(_mm_loadu_ps(f + i), t));
        __m128i c1 = _mm_castps_si128(_mm_cmpgt_ps(_mm_loadu_ps(f + i + 4), t));
        __m128i c2 = _mm_castps_si128(_mm_cmpgt_ps(_mm_loadu_ps(f + i + 8), t));
        __m128i c3 = _mm_castps_si128(_mm_cmpgt_ps(_mm_loadu_ps(f + i + 12), t));
        __m128i b = _mm_and_si128(_mm_packs_epi16(_mm_packs_epi32(c0, c1), _mm_packs_epi32(c2, c3)), one);
        _mm_storeu_si128((__m128i *)(in + i), b);
        acc = _mm_add_epi64(acc, _mm_sad_epu8(b, zero));
    }
    size_t sum = (size_t)_mm_cvtsi128_si32(acc) + (size_t)_mm_cvtsi128_si32(_mm_unpackhi_epi64(acc, acc));
    for (; i < i1; i++) {
        uint8_t v = f[i] > thr;
        in[i] = v;
        sum += v;
    }
    return sum;
}
#else
static size_t classify_row(const float *f, uint8_t *in, int i0, int i1, float thr)
{
    size_t sum = 0;
    for (int i = i0; i < i1; i++) {
        uint8_t v = f[i] > thr;
        in[i] = v;
        sum += v;
    }
    return sum;
}
#endif

/* The configurations of the B cubes of a row (corner bits: 1 x, 2 y, 4 z;
 * from the inside flags, 0 or 1, of the four node rows at its corners) into
 * cfg[0 .. B - 1]; returns the bits of the cubes the surface cuts (neither
 * 0 nor 255). Reads up to 16 bytes past the rows' B + 1 (the flags' buffer
 * holds JM_IN_SLACK more). */
#ifdef __SSE2__
static uint32_t row_configs(const uint8_t *i00, const uint8_t *i10, const uint8_t *i01, const uint8_t *i11, int B,
                            uint8_t cfg[32])
{
    uint32_t cut = 0;
    const __m128i zero = _mm_setzero_si128(), ones = _mm_cmpeq_epi8(zero, zero);
    for (int h = 0; h < B; h += 16) {
        /* flags are 0 or 1: shifts within 16-bit lanes stay in their bytes */
#define JM_LD(p, d) _mm_loadu_si128((const __m128i *)((p) + h + (d)))
        __m128i c = _mm_or_si128(JM_LD(i00, 0), _mm_slli_epi16(JM_LD(i00, 1), 1));
        c = _mm_or_si128(c, _mm_or_si128(_mm_slli_epi16(JM_LD(i10, 0), 2), _mm_slli_epi16(JM_LD(i10, 1), 3)));
        c = _mm_or_si128(c, _mm_or_si128(_mm_slli_epi16(JM_LD(i01, 0), 4), _mm_slli_epi16(JM_LD(i01, 1), 5)));
        c = _mm_or_si128(c, _mm_or_si128(_mm_slli_epi16(JM_LD(i11, 0), 6), _mm_slli_epi16(JM_LD(i11, 1), 7)));
#undef JM_LD
        _mm_storeu_si128((__m128i *)(cfg + h), c);
        const unsigned same = (unsigned)_mm_movemask_epi8(_mm_or_si128(_mm_cmpeq_epi8(c, zero), _mm_cmpeq_epi8(c, ones)));
        cut |= (uint32_t)(~same & 0xffffu) << h;
    }
    return B < 32 ? cut & ((1u << B) - 1u) : cut;
}
#else
static uint32_t row_configs(const uint8_t *i00, const uint8_t *i10, const uint8_t *i01, const uint8_t *i11, int B,
                            uint8_t cfg[32])
{
    uint32_t cut = 0;
    for (int i = 0; i < B; i++) {
        cfg[i] = (uint8_t)(i00[i] | i00[i + 1] << 1 | i10[i] << 2 | i10[i + 1] << 3 | i01[i] << 4 | i01[i + 1] << 5 |
                           i11[i] << 6 | i11[i + 1] << 7);
        if (cfg[i] != 0 && cfg[i] != 255) cut |= 1u << i;
    }
    return cut;
}
#endif


/* The field on the block's nodes, through the frame's field (field_ops.h):
 * NULL where there is nothing to mesh (no particle near, proven outside,
 * every node proven inside) or out of memory (out->failed). With culling,
 * the nodes proven inside are not sampled: *span gives each row's rest. */
static const float *sample_block(const jm_block_env *env, size_t b, jm_scratch *s, const float lo[3],
                                 const float hi[3], size_t *fs, const uint8_t **span, jm_bout *out)
{
    const jm_config *c = env->c;
    const jm_block_set *bs = env->blocks;
    const jm_field_ops *fo = env->field;
    const int n = s->B + 1;
    const int hood_ok = bs->cell_start ? jm_hood_build_listed(&s->hood, env->g, c, lo, hi, bs->cells + bs->cell_start[b],
                                                             bs->cell_start[b + 1] - bs->cell_start[b])
                                       : jm_hood_build(&s->hood, env->g, c, lo, hi);
    if (!hood_ok) { out->failed = 1; return NULL; }
    if (s->hood.particles == 0) return NULL;
    if (fo->block_prepare && !fo->block_prepare(env, s, lo, hi)) { out->failed = 1; return NULL; }
    size_t inner = 0;
    *span = NULL;
    /* proven to hold no inside node (cull.c): sampling would find none */
    if (c->cull && fo->outside(env, s, lo, hi, &inner)) return NULL;
    float proof;
    if (c->cull && fo->inside(env, s, inner, lo, hi, &proof)) {
        /* only the nodes next to those not proven inside are sampled */
        size_t keep = jm_sph_spans(s->part, n, proof, s->span);
        if (keep == 0) return NULL; /* every node inside */
        if (keep < (size_t)n * n * n) *span = s->span;
    }
    return fo->sample(env, s, n, *span, fs);
}

/* The inside flags of the n^3 nodes (fv: the field, rows fs apart; off a
 * row's span, proven inside), and per node row whether it is all outside
 * (0), all inside (1) or mixed (2) into s->rowstate. splat_rows: the
 * metasphere's rows no piece reached (metasplat.h, in rowstate until read
 * here) are all outside: their flags are not written (the marching reads
 * a row of zeros for every row all outside). Returns how many nodes are
 * inside. */
static size_t classify(jm_scratch *s, const float *fv, size_t fs, const uint8_t *span, float thr, int splat_rows)
{
    const int n = s->B + 1;
    size_t inside = 0;
    uint8_t *rs = s->rowstate;
    for (size_t r = 0; r < (size_t)n * n; r++) {
        const float *f = fv + r * fs;
        uint8_t *in = s->in + r * (size_t)n;
        if (splat_rows && rs[r] != JM_ROW_SPLAT) {
            rs[r] = 0;
            continue;
        }
        int i0 = 0, i1 = n;
        size_t sum = 0;
        if (span) {
            i0 = span[2 * r];
            i1 = span[2 * r + 1];
            memset(in, 1, (size_t)n); /* off the span: proven inside */
            sum = (size_t)(n - (i1 - i0));
        }
        sum += classify_row(f, in, i0, i1, thr);
        rs[r] = sum == 0 ? 0 : (sum == (size_t)n ? 1 : 2);
        inside += sum;
    }
    return inside;
}

/* One block's marching: its field, its lattice and what it produces. */
typedef struct {
    const jm_block_env *env;
    jm_scratch *s;
    jm_bout *out;
    const float *fv;   /* the field, rows fs apart */
    size_t fs, sn, sn2;
    float thr;
    int B, meta;
    int64_t rel[3];    /* the block's coordinates */
    size_t corner_off[8], dir_off[7];
    float inv_len[4];  /* 1 / the length of a direction with 0 to 3 unit steps */
} march_job;

/* A new vertex of this block on the edge from node na = (ni, nj, nk) along
 * dir (its vertex slot: slot); a vertex on a low face also goes into bmap,
 * for the blocks below to find. Its ref, or 0 with out->failed set. */
static inline uint32_t own_vertex(const march_job *m, size_t na, size_t slot, int dir, int ni, int nj, int nk)
{
    jm_bout *out = m->out;
    jm_scratch *s = m->s;
    jm_mem *mem = m->env->mem;
    if (!grow_vertices(mem, out)) { out->failed = 1; return 0; }
    const size_t sn = m->sn, fs = m->fs;
    size_t nb = na + m->dir_off[dir];
    const int *dv = jm_dir[dir];
    const float fa = m->fv[((size_t)nk * sn + (size_t)nj) * fs + (size_t)ni];
    const float fb = m->fv[((size_t)(nk + dv[2]) * sn + (size_t)(nj + dv[1])) * fs + (size_t)(ni + dv[0])];
    const float a[3] = {s->x[ni], s->y[nj], s->z[nk]};
    const float ab[3] = {s->x[ni + dv[0]] - a[0], s->y[nj + dv[1]] - a[1], s->z[nk + dv[2]] - a[2]};
    const float thr = m->thr;
    float tt = (thr - fa) / (fb - fa);
    if (m->meta) {
        /* the root and the position once the block's edges are all found
         * (metaroot.h) */
        uint32_t *cv = &out->cand[2 * out->nv];
        cv[0] = s->win[na];
        cv[1] = s->win[nb];
        if (!jm_roots_add(&s->roots, a, ab, fa - thr, tt, cv) ||
            !jm_probe_add(&s->probe, out->nv, (uint32_t)slot, (uint32_t)(ni | nj << 8 | nk << 16), tt, a)) {
            out->failed = 1;
            return 0;
        }
    } else {
        float tc = tt < JM_T_MIN ? JM_T_MIN : (tt > 1.0f - JM_T_MIN ? 1.0f - JM_T_MIN : tt);
        float *p = &out->pos[3 * out->nv];
        for (int q = 0; q < 3; q++) p[q] = a[q] + tc * ab[q];
    }
    /* fallback normal: along the edge, from inside to outside (the
     * metasphere's are blended from every piece near the vertex once the
     * block is done: jm_meta_normals_probe) */
    float sign = fa > thr ? 1.0f : -1.0f, inv = m->inv_len[dv[0] + dv[1] + dv[2]];
    float *nr = &out->nrm[3 * out->nv];
    for (int q = 0; q < 3; q++) nr[q] = sign * (float)dv[q] * inv;
    const uint32_t ref = (uint32_t)out->nv++;
    if (ni == 0 || nj == 0 || nk == 0) {
        if (!grow(mem, (void **)&out->bmap, &out->capb, out->nb + 1, 2 * sizeof(uint32_t))) {
            out->failed = 1;
            return 0;
        }
        out->bmap[2 * out->nb] = (uint32_t)slot;
        out->bmap[2 * out->nb + 1] = ref;
        out->nb++;
    }
    return ref;
}

/* A vertex on an edge from node (ni, nj, nk) along dir that a later block
 * owns: a pending reference to (owner block, its slot), resolved by the
 * stitching. Its ref, or 0 with out->failed set. */
static inline uint32_t pending_vertex(const march_job *m, int dir, int ni, int nj, int nk)
{
    jm_bout *out = m->out;
    const int B = m->B;
    int o[3] = {ni == B, nj == B, nk == B};
    uint64_t okey = jm_key3(m->rel[0] + o[0], m->rel[1] + o[1], m->rel[2] + o[2]);
    uint32_t owner = jm_hashmap_get(&m->env->blocks->map, okey);
    if (owner == UINT32_MAX) { out->failed = 2; return 0; }
    size_t onode = ((size_t)(nk - B * o[2]) * m->sn + (size_t)(nj - B * o[1])) * m->sn + (size_t)(ni - B * o[0]);
    if (!grow(m->env->mem, (void **)&out->pend, &out->capp, out->np + 1, 2 * sizeof(uint32_t))) {
        out->failed = 1;
        return 0;
    }
    out->pend[2 * out->np] = owner;
    out->pend[2 * out->np + 1] = (uint32_t)(onode * 7 + (size_t)dir);
    return JM_PENDING | (uint32_t)out->np++;
}

/* Cube (i, j, k) of configuration cfg (its first node nd): each distinct
 * edge's vertex once (welded through s->vt), then the triangles. 0 if it
 * failed (out->failed). */
static inline int march_cube(const march_job *m, const jm_case_table *tab, size_t nd, int i, int j, int k,
                             unsigned cfg)
{
    jm_bout *out = m->out;
    jm_scratch *s = m->s;
    const int B = m->B;
    int nt = tab->ntri[cfg];
    if (!grow(m->env->mem, (void **)&out->tri, &out->capt, out->ni + 3 * (size_t)nt, sizeof(uint32_t))) {
        out->failed = 1;
        return 0;
    }
    const uint8_t *ue = tab->uedge[cfg], *lt = tab->local[cfg];
    const int ne = tab->nedge[cfg];
    uint32_t refs[19];
    for (int q = 0; q < ne; q++) {
        int e = ue[q];
        int corner = jm_cube_edge_corner[e], dir = jm_cube_edge_dir[e];
        size_t na = nd + m->corner_off[corner];
        size_t slot = na * 7 + (size_t)dir;
        uint32_t ref = s->vt[slot];
        if (ref == UINT32_MAX) {
            int ni = i + (corner & 1), nj = j + ((corner >> 1) & 1), nk = k + ((corner >> 2) & 1);
            ref = ni < B && nj < B && nk < B ? own_vertex(m, na, slot, dir, ni, nj, nk)
                                             : pending_vertex(m, dir, ni, nj, nk);
            if (out->failed) return 0;
            s->vt[slot] = ref;
            s->touched[s->ntouched++] = (uint32_t)slot;
        }
        refs[q] = ref;
    }
    uint32_t *tri = out->tri + out->ni;
    for (int t = 0; t < 3 * nt; t++) tri[t] = refs[lt[t]];
    out->ni += 3 * (size_t)nt;
    return 1;
}

/* the inside flags of a node row all outside, and the bytes row_configs
 * reads past it (rows of at most 33 nodes) */
static const uint8_t zero_row[64 + JM_IN_SLACK];

/* Every cube the surface cuts, row by row: a row of cubes between four node
 * rows all inside or all outside alike (s->rowstate) has no surface. */
static void march(const march_job *m)
{
    const jm_scratch *s = m->s;
    const int B = m->B;
    const size_t sn = m->sn, sn2 = m->sn2;
    const uint8_t *rs = s->rowstate;
    const jm_case_table *tab = m->env->c->method == JM_METHOD_MC ? jm_table_mc() : jm_table_mt();
    for (int k = 0; k < B; k++)
        for (int j = 0; j < B; j++) {
            size_t row = ((size_t)k * sn + j) * sn;
            size_t r0 = (size_t)k * sn + j;
            uint8_t a0 = rs[r0], a1 = rs[r0 + 1], a2 = rs[r0 + sn], a3 = rs[r0 + sn + 1];
            if (a0 != 2 && a0 == a1 && a0 == a2 && a0 == a3) continue;
            const uint8_t *i00 = a0 ? s->in + row : zero_row, *i10 = a1 ? s->in + row + sn : zero_row;
            const uint8_t *i01 = a2 ? s->in + row + sn2 : zero_row, *i11 = a3 ? s->in + row + sn2 + sn : zero_row;
            uint8_t cfgs[32];
            for (uint32_t cut = row_configs(i00, i10, i01, i11, B, cfgs); cut; cut &= cut - 1) {
                const int i = __builtin_ctz(cut);
                if (!march_cube(m, tab, row + i, i, j, k, cfgs[i])) return;
            }
        }
}

/* The block's lattice: its key's coordinates (rel), its nodes' coordinates
 * (s->x, y, z) and its box [lo, hi]. */
static void block_lattice(const jm_block_env *env, size_t b, jm_scratch *s, int64_t rel[3], float lo[3], float hi[3])
{
    const jm_block_set *bs = env->blocks;
    const int B = s->B, n = B + 1;
    const uint64_t key = bs->key[b];
    const uint64_t mask = (uint64_t)JM_KEY_MAX - 1;
    rel[0] = (int64_t)(key & mask);
    rel[1] = (int64_t)((key >> JM_KEY_BITS) & mask);
    rel[2] = (int64_t)(key >> (2 * JM_KEY_BITS));
    int64_t node0[3];
    for (int a = 0; a < 3; a++) node0[a] = (rel[a] + bs->origin[a]) * B;
    float *xs[3] = {s->x, s->y, s->z};
    for (int a = 0; a < 3; a++)
        for (int i = 0; i < n; i++) xs[a][i] = (float)((double)(node0[a] + i) * (double)env->c->h);
    for (int a = 0; a < 3; a++) {
        lo[a] = xs[a][0];
        hi[a] = xs[a][B];
    }
}

void jm_block_mesh(const jm_block_env *env, size_t b, jm_scratch *s, jm_bout *out)
{
    const jm_config *c = env->c;
    const jm_field_ops *fo = env->field;
    jm_bout_reset(out);
    s->roots.n = 0;
    const int B = s->B, n = B + 1;
    march_job m = {.env = env, .s = s, .out = out, .thr = c->threshold, .B = B, .meta = fo->meta};
    float lo[3], hi[3];
    block_lattice(env, b, s, m.rel, lo, hi);
    out->cells = (size_t)B * B * B;

    double t0 = jm_now_ms();
    const uint8_t *span;
    m.fv = sample_block(env, b, s, lo, hi, &m.fs, &span, out);
    if (!m.fv) {
        out->t_field = jm_now_ms() - t0;
        return;
    }
    const size_t inside = classify(s, m.fv, m.fs, span, m.thr, fo->meta);
    double t1 = jm_now_ms();
    out->t_field = t1 - t0;
    if (inside == 0 || inside == (size_t)n * n * n) return;

    const int want_nrm = c->normals || c->compensate || c->uv_mode == JM_UV_BOX || c->uv_mode == JM_UV_SPHERICAL;
    m.sn = (size_t)n;
    m.sn2 = m.sn * m.sn;
    for (int k = 0; k < 8; k++) m.corner_off[k] = (k & 1) + ((k >> 1) & 1) * m.sn + ((k >> 2) & 1) * m.sn2;
    for (int q = 1; q < 4; q++) m.inv_len[q] = 1.0f / sqrtf((float)q);
    m.inv_len[0] = 0.0f;
    for (int d = 0; d < 7; d++) m.dir_off[d] = jm_dir[d][0] + jm_dir[d][1] * m.sn + jm_dir[d][2] * m.sn2;
    march(&m);
    for (size_t t = 0; t < s->ntouched; t++) s->vt[s->touched[t]] = UINT32_MAX;
    s->ntouched = 0;
    if (fo->vertices && !out->failed) fo->vertices(env, s, out);
    double t2 = jm_now_ms();
    out->t_extract = t2 - t1;
    if (out->failed) return;
    sort_pairs(out->bmap, out->nb, s->touched); /* (touched: free after the march) */
    if (!fo->finish(env, s, lo, hi, want_nrm, out)) { out->failed = 1; return; }
    if (c->uv_mode != JM_UV_NONE)
        jm_uv_all(c, out->pos, out->nrm, out->uv, out->nv);
    out->t_attr = jm_now_ms() - t2;
}

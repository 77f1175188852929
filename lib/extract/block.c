/* block.c - meshes one block: samples the field, marches its cubes, welds vertices, adds normals/UVs. */
#include "extract/block.h"
#include "field/aniso/aniso_boxes.h"
#include "field/aniso/aniso_cull.h"
#include "field/aniso/aniso_normals.h"
#include "field/aniso/aniso_splat.h"
#include "field/sph/cull.h"
#include "field/sph/inside_boxes.h"
#include "field/meta/metaroot.h"
#include "field/meta/metasplat.h"
#include "field/meta/metavertex.h"
#include "field/sph/splat.h"
#include "extract/tables.h"
#include <math.h>
#include <stdlib.h>
#include <string.h>

/* bytes the inside flags' buffer holds past the block's nodes (row_configs) */
#define JM_IN_SLACK 32
/* Interpolation parameters are kept this far from the edge ends, so no two
 * vertices meet at a lattice node (no zero-area triangles). */
#define JM_T_MIN 0.01f

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
    s->in = malloc(nn + JM_IN_SLACK);
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

/* Sorts (slot, index) pairs by slot. They are made in scan order, so
 * nearly sorted already: insertion sort is about linear here. */
static void sort_pairs(uint32_t *p, size_t n)
{
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
}

/* the part (of S^3, x fastest) of the block holding p */
static inline int part_of(const float p[3], const float lo[3], const float inv[3], int S)
{
    int q = 0;
    for (int a = 2; a >= 0; a--) {
        int k = (int)((p[a] - lo[a]) * inv[a]);
        q = q * S + (k < 0 ? 0 : (k >= S ? S - 1 : k));
    }
    return q;
}

/* SPH normals of the block's vertices. The block is cut into S^3 parts
 * about a support radius wide; each part gathers only the particles within
 * the support of its box, so a vertex sums over a few times the particles
 * that reach it instead of over all that reach the block (30 times more for
 * blocks three supports wide). 0 if out of memory. */
static int sph_normals(const jm_grid *g, const jm_config *c, jm_scratch *s, const float lo[3], const float hi[3],
                       jm_bout *out)
{
    int S = (int)lrintf((hi[0] - lo[0]) / c->support);
    S = S < 1 ? 1 : (S > 4 ? 4 : S);
    const size_t nv = out->nv;
    if (nv > s->cap_order) {
        uint32_t *o = jm_realloc_lasting(s->hood.mem, s->order, s->cap_order * sizeof *o, nv * sizeof *o);
        if (!o) return 0;
        s->order = o;
        s->cap_order = nv;
    }
    /* counting sort of the vertices by part */
    uint32_t start[65] = {0};
    float inv[3];
    for (int a = 0; a < 3; a++) inv[a] = (float)S / (hi[a] - lo[a]);
    for (size_t v = 0; v < nv; v++) start[part_of(&out->pos[3 * v], lo, inv, S) + 1]++;
    for (int q = 0; q < S * S * S; q++) start[q + 1] += start[q];
    uint32_t fill[64];
    memcpy(fill, start, sizeof fill);
    for (size_t v = 0; v < nv; v++) s->order[fill[part_of(&out->pos[3 * v], lo, inv, S)]++] = (uint32_t)v;
    for (int q = 0; q < S * S * S; q++) {
        if (start[q] == start[q + 1]) continue;
        int qi[3] = {q % S, (q / S) % S, q / (S * S)};
        float plo[3], phi[3];
        for (int a = 0; a < 3; a++) {
            float w = (hi[a] - lo[a]) / (float)S;
            plo[a] = qi[a] == 0 ? lo[a] : lo[a] + w * (float)qi[a];
            phi[a] = qi[a] == S - 1 ? hi[a] : lo[a] + w * (float)(qi[a] + 1);
        }
        /* a vertex of this part lies within [plo, phi] up to rounding:
         * widen by a hundredth of the support */
        for (int a = 0; a < 3; a++) {
            plo[a] -= 0.01f * c->support;
            phi[a] += 0.01f * c->support;
        }
        if (c->aniso) {
            jm_aniso_gather(g, &s->an_cand, plo, phi, &s->an_list);
            if (s->an_list.n == SIZE_MAX) return 0;
            jm_aniso_normals(&s->an_list, s->order + start[q], start[q + 1] - start[q], out->pos, out->nrm);
            continue;
        }
        jm_sph_gather(g, c, &s->hood, plo, phi, &s->soa);
        if (s->soa.n == SIZE_MAX) return 0;
        jm_sph_normals(c, &s->soa, s->order + start[q], start[q + 1] - start[q], out->pos, out->nrm);
    }
    return 1;
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

/* The block's metasphere vertices on their edges (metaroot.c): each root
 * for jm_meta_probe (its point, pt), the vertex kept from the nodes */
static void meta_roots(const jm_grid *g, const jm_config *c, jm_scratch *s, jm_bout *out)
{
    jm_roots *r = &s->roots;
    jm_roots_solve(g, c, r);
    for (size_t v = 0; v < r->n; v++) {
        const float tt = r->t[v], tc = tt < JM_T_MIN ? JM_T_MIN : (tt > 1.0f - JM_T_MIN ? 1.0f - JM_T_MIN : tt);
        const float a[3] = {r->ax[v], r->ay[v], r->az[v]}, ab[3] = {r->bx[v], r->by[v], r->bz[v]};
        float *pt = &s->probe.pt[3 * v], *p = &out->pos[3 * v];
        s->probe.t[v] = tt;
        for (int q = 0; q < 3; q++) {
            pt[q] = a[q] + tt * ab[q];
            p[q] = a[q] + tc * ab[q];
        }
    }
    r->n = 0;
}

void jm_block_mesh(const jm_block_env *env, size_t b, jm_scratch *s, jm_bout *out)
{
    const jm_config *c = env->c;
    const jm_grid *g = env->g;
    const jm_block_set *bs = env->blocks;
    jm_bout_reset(out);
    s->roots.n = 0;
    const int B = s->B, n = B + 1;
    const uint64_t key = bs->key[b];
    const uint64_t mask = (uint64_t)JM_KEY_MAX - 1;
    const int64_t rel[3] = {(int64_t)(key & mask), (int64_t)((key >> JM_KEY_BITS) & mask),
                            (int64_t)(key >> (2 * JM_KEY_BITS))};
    int64_t node0[3];
    for (int a = 0; a < 3; a++) node0[a] = (rel[a] + bs->origin[a]) * B;
    float *xs[3] = {s->x, s->y, s->z};
    for (int a = 0; a < 3; a++)
        for (int i = 0; i < n; i++) xs[a][i] = (float)((double)(node0[a] + i) * (double)c->h);
    const float lo[3] = {s->x[0], s->y[0], s->z[0]}, hi[3] = {s->x[B], s->y[B], s->z[B]};
    out->cells = (size_t)B * B * B;

    double t0 = jm_now_ms();
    const int hood_ok = bs->cell_start ? jm_hood_build_listed(&s->hood, g, c, lo, hi, bs->cells + bs->cell_start[b],
                                                             bs->cell_start[b + 1] - bs->cell_start[b])
                                       : jm_hood_build(&s->hood, g, c, lo, hi);
    if (!hood_ok) { out->failed = 1; return; }
    if (s->hood.particles == 0) return;
    /* anisotropic kernels: the ones reaching the block (and the normals'
     * part boxes, a hundredth of a support wider), looked at from here on */
    if (c->aniso && !jm_aniso_candidates(g, &s->hood, lo, hi, 0.02f * c->support, &s->an_cand)) {
        out->failed = 1;
        return;
    }
    size_t inner = 0;
    if (c->cull && (c->aniso ? jm_aniso_block_outside(g, c, &s->an_cand, lo, hi, &inner)
                             : jm_sph_block_outside(g, c, &s->hood, lo, hi, &inner))) {
        /* proven to hold no inside node (cull.c): sampling would find none
         * and return here below, with nothing to mesh */
        out->t_field = jm_now_ms() - t0;
        return;
    }
    size_t fs;
    const float *fv;
    const uint8_t *span = NULL;
    const int an_boxes = c->aniso && c->cull && jm_aniso_boxes_apply(c, inner, lo, hi);
    if (c->cull && (an_boxes || jm_sph_block_full(c, inner, lo, hi))) {
        /* the SPH field, a block a third full of fluid or more: partial
         * sums or boxes prove nodes inside; only the nodes next to the
         * others are sampled (cull.c, aniso_cull.c, aniso_boxes.c) */
        float proof = c->threshold;
        if (an_boxes) proof = jm_aniso_boxes(g, c, &s->an_cand, s->x, s->y, s->z, n, s->boxes, s->part);
        else if (c->aniso) jm_aniso_partial(g, c, &s->an_cand, s->x, s->y, s->z, n, s->part);
        else if (jm_sph_boxes_apply(c, inner, lo, hi)) { /* JM_BOX_FILL full, fine lattice */
            proof = jm_sph_box_threshold(c, &s->hood);
            jm_sph_boxes(g, c, &s->hood, s->x, s->y, s->z, n, s->boxes, s->part);
        } else {
            proof = jm_sph_partial_threshold(c, &s->hood);
            jm_sph_partial(g, c, &s->hood, s->x, s->y, s->z, n, s->part);
        }
        size_t keep = jm_sph_spans(s->part, n, proof, s->span);
        if (keep == 0) {
            out->t_field = jm_now_ms() - t0;
            return; /* every node inside */
        }
        if (keep < (size_t)n * n * n) span = s->span;
        if (c->aniso) jm_aniso_sample(g, c, &s->an_cand, s->x, s->y, s->z, n, span, s->pad);
        else jm_sph_sample(g, c, &s->hood, s->x, s->y, s->z, n, span, s->pad);
        fv = s->pad;
        fs = JM_PAD(n);
    } else if (c->aniso) {
        jm_aniso_sample(g, c, &s->an_cand, s->x, s->y, s->z, n, NULL, s->pad);
        fv = s->pad;
        fs = JM_PAD(n);
    } else {
        fv = jm_field_sample(g, c, &s->hood, s->x, s->y, s->z, n, s->f, s->win, s->rowstate, s->pad, &fs);
    }
    const float thr = c->threshold;
    const size_t nn = (size_t)n * n * n;
    size_t inside = 0;
    /* inside flags, and per node row whether it is all outside (0), all
     * inside (1) or mixed (2) */
    uint8_t *rs = s->rowstate;
    /* the metasphere's rows no piece reached (metasplat.h, in rowstate
     * until read here) are all outside */
    const int splat_rows = c->field == JM_FIELD_METASPHERE;
    if (splat_rows) memset(s->in, 0, nn);
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
    double t1 = jm_now_ms();
    out->t_field = t1 - t0;
    if (inside == 0 || inside == nn) return;

    const int meta = c->field == JM_FIELD_METASPHERE;
    const jm_case_table *tab = c->method == JM_METHOD_MC ? jm_table_mc() : jm_table_mt();
    const int want_nrm = c->normals || c->compensate || c->uv_mode == JM_UV_BOX || c->uv_mode == JM_UV_SPHERICAL;
    jm_mem *mem = env->mem;
    const size_t sn = (size_t)n, sn2 = sn * sn;
    size_t corner_off[8];
    for (int k = 0; k < 8; k++) corner_off[k] = (k & 1) + ((k >> 1) & 1) * sn + ((k >> 2) & 1) * sn2;
    /* 1 / the length of a direction with 1, 2 or 3 unit steps */
    float inv_len[4];
    for (int m = 1; m < 4; m++) inv_len[m] = 1.0f / sqrtf((float)m);
    inv_len[0] = 0.0f;
    size_t dir_off[7];
    for (int d = 0; d < 7; d++) dir_off[d] = jm_dir[d][0] + jm_dir[d][1] * sn + jm_dir[d][2] * sn2;

    /* node rows that are all inside or all outside (rs, above): a row of
     * cubes between four such rows, all alike, has no surface */
    for (int k = 0; k < B; k++)
        for (int j = 0; j < B; j++) {
            size_t row = ((size_t)k * sn + j) * sn;
            size_t r0 = (size_t)k * sn + j;
            uint8_t a0 = rs[r0], a1 = rs[r0 + 1], a2 = rs[r0 + sn], a3 = rs[r0 + sn + 1];
            if (a0 != 2 && a0 == a1 && a0 == a2 && a0 == a3) continue;
            const uint8_t *i00 = s->in + row, *i10 = i00 + sn, *i01 = i00 + sn2, *i11 = i01 + sn;
            uint8_t cfgs[32];
            for (uint32_t cut = row_configs(i00, i10, i01, i11, B, cfgs); cut; cut &= cut - 1) {
                const int i = __builtin_ctz(cut);
                size_t nd = row + i;
                const unsigned cfg_here = cfgs[i];
                int nt = tab->ntri[cfg_here];
                if (!grow(mem, (void **)&out->tri, &out->capt, out->ni + 3 * (size_t)nt, sizeof(uint32_t))) {
                    out->failed = 1;
                    goto done;
                }
                /* each distinct edge's vertex once, then the triangles */
                const uint8_t *ue = tab->uedge[cfg_here], *lt = tab->local[cfg_here];
                const int ne = tab->nedge[cfg_here];
                uint32_t refs[19];
                for (int q = 0; q < ne; q++) {
                    int e = ue[q];
                    int corner = jm_cube_edge_corner[e], dir = jm_cube_edge_dir[e];
                    size_t na = nd + corner_off[corner];
                    size_t slot = na * 7 + (size_t)dir;
                    uint32_t ref = s->vt[slot];
                    if (ref == UINT32_MAX) {
                        int ni = i + (corner & 1), nj = j + ((corner >> 1) & 1), nk = k + ((corner >> 2) & 1);
                        if (ni < B && nj < B && nk < B) {
                            if (!grow_vertices(mem, out)) { out->failed = 1; goto done; }
                            size_t nb = na + dir_off[dir];
                            const int *dv = jm_dir[dir];
                            const float fa = fv[((size_t)nk * sn + (size_t)nj) * fs + (size_t)ni];
                            const float fb = fv[((size_t)(nk + dv[2]) * sn + (size_t)(nj + dv[1])) * fs + (size_t)(ni + dv[0])];
                            const float a[3] = {s->x[ni], s->y[nj], s->z[nk]};
                            const float ab[3] = {s->x[ni + dv[0]] - a[0], s->y[nj + dv[1]] - a[1], s->z[nk + dv[2]] - a[2]};
                            float tt = (thr - fa) / (fb - fa);
                            uint32_t *cv = meta ? &out->cand[2 * out->nv] : NULL;
                            if (meta) {
                                /* the root and the position once the
                                 * block's edges are all found (metaroot.h) */
                                cv[0] = s->win[na];
                                cv[1] = s->win[nb];
                                if (!jm_roots_add(&s->roots, a, ab, fa - thr, tt, cv) ||
                                    !jm_probe_add(&s->probe, out->nv, (uint32_t)slot, (uint32_t)(ni | nj << 8 | nk << 16), tt, a)) {
                                    out->failed = 1;
                                    goto done;
                                }
                            } else {
                                float tc = tt < JM_T_MIN ? JM_T_MIN : (tt > 1.0f - JM_T_MIN ? 1.0f - JM_T_MIN : tt);
                                float *p = &out->pos[3 * out->nv];
                                for (int q = 0; q < 3; q++) p[q] = a[q] + tc * ab[q];
                            }
                            /* fallback normal: along the edge, from inside to outside */
                            float sign = fa > thr ? 1.0f : -1.0f, inv = inv_len[dv[0] + dv[1] + dv[2]];
                            float *nr = &out->nrm[3 * out->nv];
                            for (int a = 0; a < 3; a++) nr[a] = sign * (float)dv[a] * inv;
                            /* (the metasphere's are blended from every
                             * piece near the vertex once the block is done:
                             * jm_meta_normals_probe) */
                            ref = (uint32_t)out->nv++;
                            if (ni == 0 || nj == 0 || nk == 0) {
                                if (!grow(mem, (void **)&out->bmap, &out->capb, out->nb + 1, 2 * sizeof(uint32_t))) {
                                    out->failed = 1;
                                    goto done;
                                }
                                out->bmap[2 * out->nb] = (uint32_t)slot;
                                out->bmap[2 * out->nb + 1] = ref;
                                out->nb++;
                            }
                        } else {
                            int o[3] = {ni == B, nj == B, nk == B};
                            uint64_t okey = jm_key3(rel[0] + o[0], rel[1] + o[1], rel[2] + o[2]);
                            uint32_t owner = jm_hashmap_get(&bs->map, okey);
                            if (owner == UINT32_MAX) { out->failed = 2; goto done; }
                            size_t onode = ((size_t)(nk - B * o[2]) * sn + (size_t)(nj - B * o[1])) * sn +
                                           (size_t)(ni - B * o[0]);
                            if (!grow(mem, (void **)&out->pend, &out->capp, out->np + 1, 2 * sizeof(uint32_t))) {
                                out->failed = 1;
                                goto done;
                            }
                            out->pend[2 * out->np] = owner;
                            out->pend[2 * out->np + 1] = (uint32_t)(onode * 7 + (size_t)dir);
                            ref = JM_PENDING | (uint32_t)out->np++;
                        }
                        s->vt[slot] = ref;
                        s->touched[s->ntouched++] = (uint32_t)slot;
                    }
                    refs[q] = ref;
                }
                uint32_t *tri = out->tri + out->ni;
                for (int t = 0; t < 3 * nt; t++) tri[t] = refs[lt[t]];
                out->ni += 3 * (size_t)nt;
            }
        }
done:
    for (size_t t = 0; t < s->ntouched; t++) s->vt[s->touched[t]] = UINT32_MAX;
    s->ntouched = 0;
    if (meta && !out->failed) meta_roots(g, c, s, out);
    double t2 = jm_now_ms();
    out->t_extract = t2 - t1;
    if (out->failed) return;
    if (meta && !jm_meta_probe(g, c, &s->hood, &s->probe, want_nrm ? &s->mnorm : NULL, B, s->x, s->y, s->z, s->f,
                               out->pos, out->cand, out->nv)) {
        out->failed = 1;
        return;
    }
    if (meta && want_nrm && !jm_meta_normals_finish(g, c, &s->hood, &s->probe, &s->mnorm, B, s->x, s->y, s->z,
                                                    out->pos, out->nrm, out->nv)) {
        out->failed = 1;
        return;
    }
    sort_pairs(out->bmap, out->nb);
    if (!meta && want_nrm && out->nv && !sph_normals(g, c, s, lo, hi, out)) { out->failed = 1; return; }
    if (c->uv_mode != JM_UV_NONE)
        jm_uv_all(c, out->pos, out->nrm, out->uv, out->nv);
    out->t_attr = jm_now_ms() - t2;
}

/* test_select_clip.c - the particle box, small particle groups, small mesh pieces and the mesh clip box: what they keep, what they remove, closedness, the same bytes for any thread count, the ranges refused. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../formats/reader.h"
#include "../lib/core/internal.h"
#include "../lib/post/small_pieces.h"
#include "util/meshcheck.h"
#include "util/shared_data.h"

#define R 0.025f

/* particles: xyz grows by add_* */
typedef struct cloud {
    float *xyz;
    size_t n, cap;
} cloud;

static void add(cloud *c, float x, float y, float z)
{
    if (c->n == c->cap) {
        c->cap = c->cap ? 2 * c->cap : 256;
        c->xyz = realloc(c->xyz, 3 * c->cap * sizeof *c->xyz);
        assert_non_null(c->xyz);
    }
    c->xyz[3 * c->n] = x;
    c->xyz[3 * c->n + 1] = y;
    c->xyz[3 * c->n + 2] = z;
    c->n++;
}

/* a k x k x k block at spacing 2r from corner (x, y, z), jittered a little */
static void add_block(cloud *c, int k, float x, float y, float z, unsigned seed)
{
    for (int i = 0; i < k; i++)
        for (int j = 0; j < k; j++)
            for (int l = 0; l < k; l++)
                add(c, x + 2 * R * i + 0.1f * R * (mc_randf(&seed) - 0.5f), y + 2 * R * j, z + 2 * R * l);
}

/* meshes in with p (threads t); the mesh's arrays copied out */
typedef struct out {
    float *pos, *nrm;
    uint32_t *idx;
    size_t nv, nt;
    jm_stats st;
    jm_mesh m; /* pointers into the copies */
} out;

static jm_status mesh_of(const jm_params *p0, int threads, const float *xyz, size_t n, out *o)
{
    jm_params p = *p0;
    p.threads = threads;
    jm_context *ctx = NULL;
    memset(o, 0, sizeof *o);
    jm_status s = jm_context_create(&p, &ctx);
    if (s != JM_OK) return s;
    jm_particles in = {xyz, n, 0, NULL};
    jm_mesh m;
    s = jm_mesh_particles(ctx, &in, &m, &o->st);
    if (s == JM_OK) {
        o->nv = m.vertex_count;
        o->nt = m.triangle_count;
        o->pos = malloc(3 * o->nv * sizeof(float) + 4);
        o->nrm = malloc(3 * o->nv * sizeof(float) + 4);
        o->idx = malloc(3 * o->nt * sizeof(uint32_t) + 4);
        if (o->nv) memcpy(o->pos, m.positions, 3 * o->nv * sizeof(float));
        if (o->nv && m.normals) memcpy(o->nrm, m.normals, 3 * o->nv * sizeof(float));
        if (o->nt) memcpy(o->idx, m.indices, 3 * o->nt * sizeof(uint32_t));
        o->m = m;
        o->m.positions = o->pos;
        o->m.normals = m.normals ? o->nrm : NULL;
        o->m.uvs = NULL;
        o->m.indices = o->idx;
    }
    jm_context_free(ctx);
    return s;
}

static void out_free(out *o)
{
    free(o->pos);
    free(o->nrm);
    free(o->idx);
}

static void same_mesh(const out *a, const out *b)
{
    assert_int_equal(a->nv, b->nv);
    assert_int_equal(a->nt, b->nt);
    assert_memory_equal(a->pos, b->pos, 3 * a->nv * sizeof(float));
    assert_memory_equal(a->nrm, b->nrm, 3 * a->nv * sizeof(float));
    assert_memory_equal(a->idx, b->idx, 3 * a->nt * sizeof(uint32_t));
}

/* a frame whose every particle is removed gives an empty mesh whose normals
 * and uvs are NULL exactly when not asked for, on a fresh context and after
 * a frame with a mesh alike: a writer's layout (a PLY header) does not
 * depend on what the context meshed before */
static void test_empty_layout(void **state)
{
    (void)state;
    cloud c = {0};
    add_block(&c, 3, 0, 0, 0, 5);
    for (int f = 0; f < 2; f++)
        for (int asked = 0; asked < 2; asked++) {
            jm_params p = {0};
            p.radius = R;
            p.field = f ? JM_FIELD_SPH : JM_FIELD_METASPHERE;
            p.no_normals = !asked;
            p.uv_mode = asked ? JM_UV_SPHERICAL : JM_UV_NONE;
            jm_params q = p;
            q.min_piece_particles = 1000; /* removes all 27 */
            jm_context *fresh = NULL, *used = NULL;
            assert_int_equal(jm_context_create(&q, &fresh), JM_OK);
            assert_int_equal(jm_context_create(&p, &used), JM_OK);
            jm_particles in = {c.xyz, c.n, 0, NULL};
            jm_mesh m;
            assert_int_equal(jm_mesh_particles(used, &in, &m, NULL), JM_OK); /* a mesh first */
            assert_true(m.vertex_count > 0);
            assert_int_equal(jm_context_set_params(used, &q), JM_OK);
            for (int k = 0; k < 2; k++) {
                assert_int_equal(jm_mesh_particles(k ? used : fresh, &in, &m, NULL), JM_OK);
                assert_int_equal(m.vertex_count, 0);
                assert_true((m.normals != NULL) == asked);
                assert_true((m.uvs != NULL) == asked);
            }
            jm_context_free(fresh);
            jm_context_free(used);
        }
    free(c.xyz);
}

/* two blocks far apart: a box around the first meshes exactly what the
 * first alone meshes; a box around no particle meshes nothing */
static void test_particle_box(void **state)
{
    (void)state;
    for (int f = 0; f < 2; f++) {
        cloud c = {0};
        add_block(&c, 6, 0, 0, 0, 1);
        const size_t first = c.n;
        add_block(&c, 5, 1, 0, 0, 2);
        jm_params p = {0};
        p.radius = R;
        p.field = f ? JM_FIELD_SPH : JM_FIELD_METASPHERE;
        out alone, boxed, boxed2, none;
        assert_int_equal(mesh_of(&p, 1, c.xyz, first, &alone), JM_OK);
        for (int k = 0; k < 3; k++) {
            p.particle_aabb_min[k] = -0.1f;
            p.particle_aabb_max[k] = 0.5f;
        }
        assert_int_equal(mesh_of(&p, 1, c.xyz, c.n, &boxed), JM_OK);
        assert_int_equal(mesh_of(&p, 2, c.xyz, c.n, &boxed2), JM_OK);
        assert_int_equal(boxed.st.particles, first);
        assert_true(alone.nt > 100);
        same_mesh(&alone, &boxed);
        same_mesh(&boxed, &boxed2);
        /* nothing inside: no surface */
        p.particle_aabb_min[0] = 0.6f;
        p.particle_aabb_max[0] = 0.9f;
        assert_int_equal(mesh_of(&p, 1, c.xyz, c.n, &none), JM_OK);
        assert_int_equal(none.nt, 0);
        assert_int_equal(none.st.particles, 0);
        out_free(&alone); out_free(&boxed); out_free(&boxed2); out_free(&none);
        free(c.xyz);
    }
}

/* a block, a chain of particles 0.9 link distances apart, a cluster of 4
 * and 3 loners: at min_piece_particles 5 the block and the chain stay (the
 * same mesh as theirs alone), the cluster and the loners go */
static void test_small_groups(void **state)
{
    (void)state;
    for (int f = 0; f < 2; f++) {
        cloud c = {0};
        add_block(&c, 5, 0, 0, 0, 3);
        const float L = f ? 4 * R : (float)M_PI * R; /* sph: support 2h = 4r; metasphere: pi r */
        for (int i = 0; i < 6; i++) add(&c, 0.6f + 0.9f * L * i, 0, 0);
        const size_t keep = c.n;
        for (int i = 0; i < 4; i++) add(&c, 0, 0.6f + 1.5f * R * (i & 1), 1.5f * R * (i >> 1));
        add(&c, 0, 0, 0.8f);
        add(&c, 0.5f, 0.5f, 0.5f);
        add(&c, -0.5f, 0.5f, 0.5f);
        jm_params p = {0};
        p.radius = R;
        p.field = f ? JM_FIELD_SPH : JM_FIELD_METASPHERE;
        out ref, sel, sel2;
        assert_int_equal(mesh_of(&p, 1, c.xyz, keep, &ref), JM_OK);
        p.min_piece_particles = 5;
        assert_int_equal(mesh_of(&p, 1, c.xyz, c.n, &sel), JM_OK);
        assert_int_equal(mesh_of(&p, 2, c.xyz, c.n, &sel2), JM_OK);
        assert_int_equal(sel.st.particles, keep);
        same_mesh(&ref, &sel);
        same_mesh(&sel, &sel2);
        /* 6: the chain (6 particles) stays, 7: it goes too */
        out six, seven;
        p.min_piece_particles = 6;
        assert_int_equal(mesh_of(&p, 1, c.xyz, c.n, &six), JM_OK);
        assert_int_equal(six.st.particles, keep);
        p.min_piece_particles = 7;
        assert_int_equal(mesh_of(&p, 1, c.xyz, c.n, &seven), JM_OK);
        assert_int_equal(seven.st.particles, 125);
        out_free(&ref); out_free(&sel); out_free(&sel2); out_free(&six); out_free(&seven);
        free(c.xyz);
    }
}

/* a block and isolated droplets (sphere templates, 4.19 r^3 each): at
 * min_piece_volume 20 r^3 the droplets go, the block stays whole and
 * closed; the same bytes on 1 and 2 threads */
static void test_small_pieces(void **state)
{
    (void)state;
    cloud c = {0};
    add_block(&c, 5, 0, 0, 0, 4);
    for (int i = 0; i < 5; i++) add(&c, 0.5f + 0.3f * i, 0.5f, 0.5f);
    jm_params p = {0};
    p.radius = R;
    p.field = JM_FIELD_SPH;
    out all, block, kept, kept2;
    assert_int_equal(mesh_of(&p, 1, c.xyz, c.n, &all), JM_OK);
    assert_int_equal(mesh_of(&p, 1, c.xyz, 125, &block), JM_OK);
    mc_report ra, rb, rk;
    assert_true(mc_check(&all.m, &ra));
    assert_true(mc_check(&block.m, &rb));
    assert_int_equal(ra.components, rb.components + 5);
    p.min_piece_volume = 20.0f;
    assert_int_equal(mesh_of(&p, 1, c.xyz, c.n, &kept), JM_OK);
    assert_int_equal(mesh_of(&p, 2, c.xyz, c.n, &kept2), JM_OK);
    same_mesh(&kept, &kept2);
    assert_true(mc_check(&kept.m, &rk));
    assert_int_equal(rk.components, rb.components);
    assert_int_equal(kept.nt, block.nt);
    assert_true(fabs(rk.volume - rb.volume) < 1e-9);
    assert_true(kept.st.ms_post > 0.0);
    /* a volume above the block's: nothing left */
    out none;
    p.min_piece_volume = (float)(1.01 * rb.volume / ((double)R * R * R));
    assert_int_equal(mesh_of(&p, 1, c.xyz, c.n, &none), JM_OK);
    assert_int_equal(none.nt, 0);
    out_free(&all); out_free(&block); out_free(&kept); out_free(&kept2); out_free(&none);
    free(c.xyz);
}

/* an axis-aligned cube of edge e at o, outward (inward: flipped) */
static void add_cube(float *pos, uint32_t *idx, size_t *nv, size_t *nt, const float o[3], float e, int inward)
{
    static const int q[6][4] = {{0, 2, 3, 1}, {4, 5, 7, 6}, {0, 1, 5, 4}, {2, 6, 7, 3}, {0, 4, 6, 2}, {1, 3, 7, 5}};
    const uint32_t b = (uint32_t)*nv;
    for (int v = 0; v < 8; v++) {
        pos[3 * *nv] = o[0] + e * (float)(v & 1);
        pos[3 * *nv + 1] = o[1] + e * (float)((v >> 1) & 1);
        pos[3 * *nv + 2] = o[2] + e * (float)((v >> 2) & 1);
        (*nv)++;
    }
    for (int f = 0; f < 6; f++) {
        const int t[2][3] = {{q[f][0], q[f][1], q[f][2]}, {q[f][0], q[f][2], q[f][3]}};
        for (int k = 0; k < 2; k++) {
            idx[3 * *nt] = b + (uint32_t)t[k][0];
            idx[3 * *nt + 1] = b + (uint32_t)(inward ? t[k][2] : t[k][1]);
            idx[3 * *nt + 2] = b + (uint32_t)(inward ? t[k][1] : t[k][2]);
            (*nt)++;
        }
    }
}

/* jm_drop_small_pieces on cubes: a small blob with a cavity inside goes
 * with its cavity; a big blob keeps its own cavity */
static void test_cavity_in_small_piece(void **state)
{
    (void)state;
    float pos[3 * 8 * 6];
    uint32_t idx[3 * 12 * 6];
    size_t nv = 0, nt = 0;
    const float big[3] = {10, 0, 0}, bigcav[3] = {12, 2, 2}, small[3] = {0, 0, 0}, smallcav[3] = {0.5f, 0.5f, 0.5f};
    add_cube(pos, idx, &nv, &nt, small, 2, 0);      /* volume 8 */
    add_cube(pos, idx, &nv, &nt, big, 10, 0);       /* volume 1000 */
    add_cube(pos, idx, &nv, &nt, smallcav, 1, 1);   /* -1, inside the small one */
    add_cube(pos, idx, &nv, &nt, bigcav, 1, 1);     /* -1, inside the big one */
    jm_mem mem;
    memset(&mem, 0, sizeof mem);
    size_t removed = 0, ni = 3 * nt;
    assert_true(jm_drop_small_pieces(&mem, NULL, pos, NULL, NULL, idx, &nv, &ni, 100.0, &removed));
    assert_int_equal(removed, 1);
    assert_int_equal(nv, 16);
    assert_int_equal(ni, 3 * 24);
    jm_mesh m = {pos, NULL, NULL, idx, nv, ni / 3, {0, 0, 0}, {0, 0, 0}};
    mc_report r;
    mc_check(&m, &r);
    assert_true(r.closed && r.edge_manifold);
    assert_int_equal(r.components, 2);
    assert_true(fabs(r.volume - 999.0) < 1e-6); /* the big cube less its cavity */
    for (size_t v = 0; v < nv; v++) assert_true(pos[3 * v] >= 10.0f);
    assert_int_equal(mem.current, 0);
}

static int in_box(const float *p, const float lo[3], const float hi[3])
{
    return p[0] >= lo[0] && p[0] <= hi[0] && p[1] >= lo[1] && p[1] <= hi[1] && p[2] >= lo[2] && p[2] <= hi[2];
}

/* the clip box through a block: without clamping every vertex lies in the
 * box and the mesh is open; with it, closed, manifold, in the box, about
 * half the volume, the cut's vertices facing +x; 1 and 2 threads alike */
static void test_clip(void **state)
{
    (void)state;
    cloud c = {0};
    add_block(&c, 8, 0, 0, 0, 5);
    for (int i = 0; i < 3; i++) add(&c, 0.2f + 0.3f * i, 0.6f, 0.2f); /* droplets beyond the cut in y */
    jm_params p = {0};
    p.radius = R;
    p.field = JM_FIELD_SPH;
    p.method = JM_METHOD_MC;
    out full, cut, cut2, closed, closed2;
    assert_int_equal(mesh_of(&p, 1, c.xyz, c.n, &full), JM_OK);
    mc_report rf, rc, rk;
    assert_true(mc_check(&full.m, &rf));
    const float lo[3] = {-1, -1, -1}, hi[3] = {0.18f, 0.5f, 1};
    memcpy(p.mesh_aabb_min, lo, sizeof lo);
    memcpy(p.mesh_aabb_max, hi, sizeof hi);
    assert_int_equal(mesh_of(&p, 1, c.xyz, c.n, &cut), JM_OK);
    assert_int_equal(mesh_of(&p, 2, c.xyz, c.n, &cut2), JM_OK);
    same_mesh(&cut, &cut2);
    assert_true(cut.nt > 100 && cut.nt < full.nt);
    for (size_t v = 0; v < cut.nv; v++) assert_true(in_box(cut.pos + 3 * v, lo, hi));
    mc_check(&cut.m, &rc);
    assert_false(rc.closed); /* open along the cut */
    assert_true(rc.edge_manifold && rc.all_referenced);
    p.mesh_aabb_clamp = 1;
    assert_int_equal(mesh_of(&p, 1, c.xyz, c.n, &closed), JM_OK);
    assert_int_equal(mesh_of(&p, 2, c.xyz, c.n, &closed2), JM_OK);
    same_mesh(&closed, &closed2);
    assert_true(mc_check(&closed.m, &rk));
    assert_int_equal(rk.components, 1); /* the droplets beyond y = 0.5 gone whole */
    size_t on_cut = 0;
    for (size_t v = 0; v < closed.nv; v++) {
        assert_true(in_box(closed.pos + 3 * v, lo, hi));
        if (closed.pos[3 * v] == hi[0]) {
            on_cut++;
            if (closed.pos[3 * v + 1] > 0.0f && closed.pos[3 * v + 2] > 0.0f && closed.pos[3 * v + 1] < 0.3f &&
                closed.pos[3 * v + 2] < 0.3f) /* inside the cut face: its normal */
                assert_true(closed.nrm[3 * v] == 1.0f && closed.nrm[3 * v + 1] == 0.0f && closed.nrm[3 * v + 2] == 0.0f);
        }
    }
    assert_true(on_cut > 50);
    /* the block reaches from about -r to 0.375 + r in x: the cut keeps about half */
    const double frac = rk.volume / rf.volume;
    assert_true(frac > 0.40 && frac < 0.55);
    out_free(&full); out_free(&cut); out_free(&cut2); out_free(&closed); out_free(&closed2);
    free(c.xyz);
}

/* every option at once on a real frame: the same bytes for 1 and 3
 * threads, and the frame scaled by 2^10 (its boxes too) gives the mesh
 * scaled by 2^10 */
static void test_real_frame_all(void **state)
{
    (void)state;
    jmf_frame f;
    char err[512];
    if (test_read_shared("splashsurf/dam_break_frame_9_6859_particles.bgeo", NULL, &f, err, sizeof err) != 1) {
        fprintf(stderr, "skipping: %s\n", err);
        skip();
    }
    jm_params p = {0};
    p.radius = R;
    p.field = JM_FIELD_SPH;
    p.method = JM_METHOD_MC;
    float lo[3], hi[3];
    for (int k = 0; k < 3; k++) {
        lo[k] = INFINITY;
        hi[k] = -INFINITY;
    }
    for (size_t i = 0; i < f.count; i++)
        for (int k = 0; k < 3; k++) {
            lo[k] = fminf(lo[k], f.xyz[3 * i + k]);
            hi[k] = fmaxf(hi[k], f.xyz[3 * i + k]);
        }
    for (int k = 0; k < 3; k++) {
        p.particle_aabb_min[k] = lo[k] + 0.1f * (hi[k] - lo[k]);
        p.particle_aabb_max[k] = hi[k];
        p.mesh_aabb_min[k] = lo[k] + 0.2f * (hi[k] - lo[k]);
        p.mesh_aabb_max[k] = hi[k] - 0.1f * (hi[k] - lo[k]);
    }
    p.min_piece_particles = 10;
    p.min_piece_volume = 30.0f;
    p.mesh_aabb_clamp = 1;
    out a, b, s;
    assert_int_equal(mesh_of(&p, 1, f.xyz, f.count, &a), JM_OK);
    assert_int_equal(mesh_of(&p, 3, f.xyz, f.count, &b), JM_OK);
    same_mesh(&a, &b);
    mc_report r;
    assert_true(mc_check(&a.m, &r));
    assert_true(a.st.particles < f.count && a.nt > 1000);
    for (size_t v = 0; v < a.nv; v++) assert_true(in_box(a.pos + 3 * v, p.mesh_aabb_min, p.mesh_aabb_max));
    /* scaled */
    float *big = malloc(3 * f.count * sizeof *big);
    for (size_t i = 0; i < 3 * f.count; i++) big[i] = ldexpf(f.xyz[i], 10);
    jm_params q = p;
    q.radius = ldexpf(R, 10);
    for (int k = 0; k < 3; k++) {
        q.particle_aabb_min[k] = ldexpf(p.particle_aabb_min[k], 10);
        q.particle_aabb_max[k] = ldexpf(p.particle_aabb_max[k], 10);
        q.mesh_aabb_min[k] = ldexpf(p.mesh_aabb_min[k], 10);
        q.mesh_aabb_max[k] = ldexpf(p.mesh_aabb_max[k], 10);
    }
    assert_int_equal(mesh_of(&q, 2, big, f.count, &s), JM_OK);
    assert_int_equal(s.nv, a.nv);
    assert_memory_equal(s.idx, a.idx, 3 * a.nt * sizeof(uint32_t));
    for (size_t i = 0; i < 3 * a.nv; i++) assert_true(s.pos[i] == ldexpf(a.pos[i], 10));
    out_free(&a); out_free(&b); out_free(&s);
    free(big);
    jmf_frame_free(&f);
}

static void refused(const jm_params *p, const char *field)
{
    jm_param_problem pr;
    assert_int_equal(jm_params_check(p, &pr), JM_E_INVALID_ARGUMENT);
    assert_string_equal(pr.field, field);
    jm_context *ctx = NULL;
    assert_int_equal(jm_context_create(p, &ctx), JM_E_INVALID_ARGUMENT);
}

static void test_ranges(void **state)
{
    (void)state;
    jm_params p = {0};
    p.radius = R;
    p.particle_aabb_max[0] = p.particle_aabb_max[1] = p.particle_aabb_max[2] = 1;
    assert_int_equal(jm_params_check(&p, NULL), JM_OK); /* from the origin */
    p.particle_aabb_min[1] = 1;
    refused(&p, "particle_aabb_max[1]");
    p.particle_aabb_min[1] = NAN;
    refused(&p, "particle_aabb_min[1]");
    p.particle_aabb_min[1] = 0;
    p.mesh_aabb_clamp = 1;
    refused(&p, "mesh_aabb_clamp"); /* no clip box */
    p.mesh_aabb_min[2] = 2;
    p.mesh_aabb_max[0] = p.mesh_aabb_max[1] = p.mesh_aabb_max[2] = 1;
    refused(&p, "mesh_aabb_max[2]");
    p.mesh_aabb_min[2] = -INFINITY;
    refused(&p, "mesh_aabb_min[2]");
    p.mesh_aabb_min[2] = 0;
    assert_int_equal(jm_params_check(&p, NULL), JM_OK);
    p.mesh_aabb_clamp = 2;
    refused(&p, "mesh_aabb_clamp");
    p.mesh_aabb_clamp = 0;
    p.min_piece_particles = -1;
    refused(&p, "min_piece_particles");
    p.min_piece_particles = 0;
    p.min_piece_volume = -1;
    refused(&p, "min_piece_volume");
    p.min_piece_volume = INFINITY;
    refused(&p, "min_piece_volume");
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_particle_box),
        cmocka_unit_test(test_small_groups),
        cmocka_unit_test(test_small_pieces),
        cmocka_unit_test(test_empty_layout),
        cmocka_unit_test(test_cavity_in_small_piece),
        cmocka_unit_test(test_clip),
        cmocka_unit_test(test_real_frame_all),
        cmocka_unit_test(test_ranges),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

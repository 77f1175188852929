/* test_simd_pairs.c - the AVX-512 paths that take two particles, two vertices, eight matrices or sixteen triangles per pass give the bits of their one-at-a-time paths. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

/* internal (white-box test): the paths under test and the switch between them */
#include "../lib/field/aniso/aniso_moments.h"
#include "../lib/extract/tables.h"
#include "../lib/field/aniso/aniso_normals.h"
#include "../lib/core/cpu.h"
#include "../lib/jetmesh_testing.h"
#include "../lib/field/meta/metafinish16.h"
#include "../lib/field/meta/metafinish.h"
#include "../lib/core/sym3.h"

static float frand(unsigned *s)
{
    *s = *s * 1103515245u + 12345u;
    return (float)((*s >> 8) & 0xFFFFFF) / (float)0x1000000;
}

static void say_path(void)
{
    /* on a CPU without AVX-512 both sides run the same C path: the test
     * then checks only the batching */
    print_message("AVX-512 paths %s\n", jm_cpu_avx512() ? "on" : "off (not on this CPU or build)");
}

/* Symmetric matrices of every kind the covariances give, and the awkward
 * ones: diagonal (no rotation at all), zero, repeated eigenvalues, an entry
 * already zero (that rotation skipped), tiny and huge scales, and runs that
 * end after different numbers of sweeps side by side. */
static void test_eigen_batch_bits(void **state)
{
    (void)state;
    say_path();
    enum { N = 203 };
    static double a[N][6], val[N][3], vec[N][9];
    unsigned s = 7;
    for (int i = 0; i < N; i++) {
        for (int e = 0; e < 6; e++) a[i][e] = 2.0 * frand(&s) - 1.0;
        a[i][0] += 2.0, a[i][3] += 2.0, a[i][5] += 2.0;
        switch (i % 9) {
        case 0: a[i][1] = a[i][2] = a[i][4] = 0.0; break;          /* diagonal */
        case 1: memset(a[i], 0, sizeof a[i]); break;                /* zero */
        case 2: a[i][0] = a[i][3] = a[i][5] = 1.0; a[i][1] = a[i][2] = a[i][4] = 0.0; break;
        case 3: a[i][2] = 0.0; break;                               /* one rotation skipped */
        case 4: for (int e = 0; e < 6; e++) a[i][e] *= 1e-9; break; /* tiny */
        case 5: for (int e = 0; e < 6; e++) a[i][e] *= 1e12; break; /* huge */
        case 6: a[i][1] = 1e-17; a[i][2] = a[i][4] = 0.0; break;   /* converged at once */
        case 7: a[i][0] = a[i][3]; a[i][5] = a[i][0]; break;        /* equal diagonal */
        default: break;
        }
    }
    /* every batch size, so that every lane count runs */
    for (int n = 1; n <= 17; n++) {
        for (int i0 = 0; i0 + n <= N; i0 += n) {
            jm_sym3_eigen_n(n, (const double(*)[6])a + i0, val + i0, vec + i0);
            for (int i = i0; i < i0 + n; i++) {
                double v1[3], e1[9];
                jm_sym3_eigen(a[i], v1, e1);
                if (memcmp(v1, val[i], sizeof v1) || memcmp(e1, vec[i], sizeof e1))
                    fail_msg("matrix %d (batch of %d): the batch differs from one at a time", i, n);
            }
        }
    }
}

/* Neighbourhoods of random points around two particles: points at the
 * particle itself (d2 = 0: weight, no neighbour), at exactly the radius (no
 * weight), far away, and the far padding. */
static void test_moments_pair_bits(void **state)
{
    (void)state;
    enum { CAP = 8 * 60 };
    static float xs[CAP], ys[CAP], zs[CAP];
    unsigned s = 11;
    const float Rn = 0.2f;
    /* the near count's radius half r_n, its band as jm_an_near_radius's */
    const jm_an_radii rad = {Rn * Rn, 1.0f / Rn, 0.25f * Rn * Rn, 1.0f / (0.25f * Rn * Rn * 0.4375f)};
    int banded = 0;
    for (int round = 0; round < 200; round++) {
        const size_t m = 1 + (size_t)(frand(&s) * (CAP - 8)), groups = (m + 7) / 8;
        const float p[3] = {frand(&s) * 0.1f, frand(&s) * 0.1f, frand(&s) * 0.1f};
        const float q[3] = {p[0] + 0.05f * frand(&s), p[1] - 0.05f * frand(&s), p[2]};
        for (size_t t = 0; t < m; t++) {
            xs[t] = p[0] + 0.5f * (2 * frand(&s) - 1);
            ys[t] = p[1] + 0.5f * (2 * frand(&s) - 1);
            zs[t] = p[2] + 0.5f * (2 * frand(&s) - 1);
            if (t % 13 == 0) xs[t] = p[0], ys[t] = p[1], zs[t] = p[2];
            if (t % 17 == 0) xs[t] = p[0] + Rn, ys[t] = p[1], zs[t] = p[2];
            if (t % 23 == 0) xs[t] = p[0] + 0.5f * Rn, ys[t] = p[1], zs[t] = p[2]; /* the near radius */
            if (t % 19 == 0) xs[t] = q[0], ys[t] = q[1], zs[t] = q[2];
        }
        for (size_t t = m; t < 8 * groups; t++) xs[t] = ys[t] = zs[t] = 1e30f;
        double a2[JM_AN_MOMENTS], b2[JM_AN_MOMENTS], a1[JM_AN_MOMENTS], b1[JM_AN_MOMENTS];
        jm_an_moments2(xs, ys, zs, groups, p, q, &rad, a2, b2);
        jm_an_moments(xs, ys, zs, groups, p, &rad, a1);
        jm_an_moments(xs, ys, zs, groups, q, &rad, b1);
        if (memcmp(a1, a2, sizeof a1) || memcmp(b1, b2, sizeof b1))
            fail_msg("round %d (%zu points): the pair differs from one at a time", round, m);
        if (!(a1[0] > 0.0)) fail_msg("round %d: no weight at all (the test would prove nothing)", round);
        banded += a1[11] != floor(a1[11]); /* a neighbour in the near count's band */
    }
    if (banded < 100) fail_msg("only %d rounds had a neighbour in the near band", banded);
}

/* Random kernels (positive definite M, amplitudes), padded as
 * jm_aniso_gather pads; vertices near and far, and one on a kernel's centre
 * (q = 0: no gradient term, a value term), in odd and even counts; each
 * vertex on a lattice edge: the normals and the settled positions the same
 * bits one at a time and in pairs, every vertex moved along its edge and
 * kept within it. */
static void test_normals_pair_bits(void **state)
{
    (void)state;
    enum { KER = 8 * 12, NV = 41 };
    static float buf[KER / 8 * JM_AN_GROUP];
    unsigned s = 5;
    int moved = 0, clamped = 0; /* steps inside the edge, and held at its ends (counted on x edges) */
    jm_an_list l = {buf, 0, KER, NULL};
    for (int round = 0; round < 100; round++) {
        l.n = 1 + (size_t)(frand(&s) * (KER - 1));
        for (size_t m = 0; m < (l.n + 7) / 8 * 8; m++) {
            float *b = buf + JM_AN_GROUP * (m / 8) + m % 8;
            if (m >= l.n) { /* jm_aniso_gather's padding */
                for (int f = 0; f < 10; f++) b[8 * f] = 0.0f;
                b[0] = b[8] = b[16] = 1e30f;
                b[24] = 1.0f;
                continue;
            }
            for (int a = 0; a < 3; a++) b[8 * a] = 0.2f * frand(&s);
            const float g0 = 20.0f + 10.0f * frand(&s), g1 = 20.0f + 10.0f * frand(&s), c = 5.0f * frand(&s);
            b[24] = g0 * g0, b[32] = c, b[40] = 0.5f * c, b[48] = g1 * g1, b[56] = 0.0f, b[64] = g0 * g1;
            b[72] = 0.5f + frand(&s);
        }
        float pos[3 * NV], p1[3 * NV], p2[3 * NV], n1[3 * NV], n2[3 * NV], e[3 * NV];
        uint32_t idx[NV];
        const size_t nv = 1 + (size_t)(frand(&s) * (NV - 1));
        const float h = 0.02f; /* vertices on lattice edges of cube h, e their directions (inside to outside) */
        for (size_t v = 0; v < nv; v++) {
            idx[v] = (uint32_t)(nv - 1 - v); /* not in order */
            const int *dv = jm_dir[(int)(frand(&s) * 6.999f)];
            const float t = 0.01f + 0.98f * frand(&s), sign = frand(&s) < 0.5f ? -1.0f : 1.0f;
            const float len = sqrtf((float)(dv[0] + dv[1] + dv[2]));
            for (int a = 0; a < 3; a++) {
                const float node = (float)(int)(frand(&s) * 10.0f) * h - 0.02f + (v % 7 == 0 ? 5.0f : 0.0f);
                pos[3 * v + a] = node + t * h * (float)dv[a];
                e[3 * v + a] = sign * (float)dv[a] / len;
            }
            if (v == 1) /* kernel 0 centred on vertex 1, among the others: q = 0 there */
                for (int a = 0; a < 3; a++) buf[8 * a] = pos[3 + a];
        }
        memcpy(p1, pos, 3 * nv * sizeof *pos);
        memcpy(p2, pos, 3 * nv * sizeof *pos);
        memcpy(n1, e, 3 * nv * sizeof *e);
        memcpy(n2, e, 3 * nv * sizeof *e);
        const float thr = 0.5f;
        for (size_t v = 0; v < nv; v++) jm_aniso_normal(&l, thr, h, &p1[3 * (size_t)idx[v]], &n1[3 * (size_t)idx[v]]);
        jm_aniso_normals(&l, thr, h, idx, nv, p2, n2);
        if (memcmp(n1, n2, 3 * nv * sizeof *n1)) fail_msg("round %d (%zu kernels, %zu vertices): pairs differ", round, l.n, nv);
        if (memcmp(p1, p2, 3 * nv * sizeof *p1))
            fail_msg("round %d (%zu kernels, %zu vertices): settled positions differ", round, l.n, nv);
        for (size_t v = 0; v < nv; v++) {
            /* along its edge only, and within it */
            float d[3], dd = 0.0f, de = 0.0f;
            for (int a = 0; a < 3; a++) d[a] = p1[3 * v + a] - pos[3 * v + a], dd += d[a] * d[a], de += d[a] * e[3 * v + a];
            if (dd > 0.0f && fabsf(de * de - dd) > 1e-3f * dd) fail_msg("round %d: vertex %zu left its edge's line", round, v);
            for (int a = 0; a < 3; a++) {
                if (e[3 * v + a] == 0.0f) continue;
                const double x = (double)p1[3 * v + a] / h, u = x - floor(x);
                if (u < 0.0099 || u > 0.9901) fail_msg("round %d: vertex %zu left its edge (%g)", round, v, u);
                clamped += dd > 0.0f && (u < 0.0101 || u > 0.9899) && a == 0;
                moved += dd > 0.0f && u > 0.0101 && u < 0.9899 && a == 0;
            }
        }
    }
    if (moved < 50 || clamped < 50) fail_msg("%d free and %d clamped steps: the test would prove little", moved, clamped);
}

/* The metasphere finish (jm_meta_finish: chord-sag offsets, fold rounds,
 * normals turned to face their triangles) with its 16-triangle (AVX-512)
 * and 8-triangle (AVX2) kernels and without: a wavy sheet whose normals are tilted at random, some far enough
 * to fold triangles and to face away from them, in triangle counts that
 * leave tails of every length; its last vertex in the last triangle (the
 * masked loads' edge). */
static void test_finish_kernel_bits(void **state)
{
    (void)state;
    enum { SIDE = 24, NV = SIDE * SIDE, NT = 2 * (SIDE - 1) * (SIDE - 1) };
    static float pos[3 * NV], nrm[3 * NV], p1[3 * NV], n1[3 * NV], p2[3 * NV], n2[3 * NV];
    static uint32_t idx[3 * NT];
    unsigned s = 11;
    size_t folds_seen = 0;
    for (int round = 0; round < 40; round++) {
        const float tilt = 0.1f + 1.5f * frand(&s);
        for (int j = 0; j < SIDE; j++)
            for (int i = 0; i < SIDE; i++) {
                float *p = pos + 3 * (j * SIDE + i), *n = nrm + 3 * (j * SIDE + i);
                p[0] = 0.1f * (float)i + 0.02f * frand(&s);
                p[1] = 0.1f * (float)j + 0.02f * frand(&s);
                p[2] = 0.05f * sinf(0.7f * (float)i) * cosf(0.5f * (float)j) + 0.01f * frand(&s);
                n[0] = tilt * (2.0f * frand(&s) - 1.0f);
                n[1] = tilt * (2.0f * frand(&s) - 1.0f);
                n[2] = frand(&s) < 0.05f ? -1.0f : 1.0f;
                const float l = sqrtf(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
                for (int a = 0; a < 3; a++) n[a] /= l;
            }
        size_t nt = 0;
        for (int j = 0; j + 1 < SIDE; j++)
            for (int i = 0; i + 1 < SIDE; i++) {
                const uint32_t a = (uint32_t)(j * SIDE + i), b = a + 1, c = a + SIDE, d = c + 1;
                const uint32_t t[6] = {a, b, d, a, d, c};
                memcpy(idx + 3 * nt, t, sizeof t);
                nt += 2;
            }
        /* a tail of any length: drop some of the first triangles (the last,
         * with the last vertex, stays) */
        const size_t drop = (size_t)round % 16, n = nt - drop;
        const uint32_t *tri = idx + 3 * drop;
        memcpy(p1, pos, sizeof pos), memcpy(n1, nrm, sizeof nrm);
        const int compensate = round % 4 != 3, facing = round % 4 != 2;
        jm_testing_force_cpu(JM_TESTING_CPU_SSE2); /* the one-at-a-time code */
        assert_int_equal(jm_meta_finish(NULL, NULL, p1, n1, NV, tri, n, compensate, facing, 0.03f), 1);
        /* the AVX2 kernels, then the AVX-512 ones (each where the CPU has
         * them; else the one-at-a-time code again) */
        for (int lanes = 8; lanes <= 16; lanes *= 2) {
            jm_testing_force_cpu(lanes == 8 ? JM_TESTING_CPU_AVX2 : JM_TESTING_CPU_AVX512);
            memcpy(p2, pos, sizeof pos), memcpy(n2, nrm, sizeof nrm);
            assert_int_equal(jm_meta_finish(NULL, NULL, p2, n2, NV, tri, n, compensate, facing, 0.03f), 1);
            if (memcmp(p1, p2, sizeof p1) || memcmp(n1, n2, sizeof n1))
                fail_msg("round %d (%zu triangles, compensate %d, facing %d): the %d-triangle kernels differ", round,
                         n, compensate, facing, lanes);
        }
        /* the finish did something: positions moved and normals turned */
        size_t moved = 0;
        for (size_t k = 0; k < 3 * NV; k++) moved += p1[k] != pos[k] || n1[k] != nrm[k];
        folds_seen += moved > 0;
    }
    jm_testing_force_cpu(-1);
    if (folds_seen < 30) fail_msg("the finish changed too few meshes (%zu of 40): the test would prove little", folds_seen);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_eigen_batch_bits),
        cmocka_unit_test(test_moments_pair_bits),
        cmocka_unit_test(test_normals_pair_bits),
        cmocka_unit_test(test_finish_kernel_bits),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

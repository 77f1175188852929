/* test_cull.c - the SPH field sampled only near the surface gives the same mesh bytes as every node sampled, on real frames. */
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
#include "../lib/jetmesh.h"
#include "util/cull_check.h"
#include "util/shared_data.h"

/* culled (1 and 2 threads) against every node sampled: the same bytes */
static void same_bytes(const char *what, const jm_params *p, const float *xyz, size_t count)
{
    size_t nt = 0;
    char err[512];
    if (cull_same_bytes(what, p, xyz, count, &nt, err, sizeof err) != 0) fail_msg("%s", err);
    printf("%s: %zu triangles, the same bytes culled and not\n", what, nt);
}

static void test_real_frames_same_bytes(void **state)
{
    (void)state;
    const char *files[] = {
        "derived/dam_break_frame_23_24389_particles.xyz",
        "splashsurf/bunny_frame_14_7705_particles.vtk",
        "splashsurf/double_dam_break_frame_26_4732_particles.vtk",
        "splashsurf/ParticleData_Random_1000.vtk",
        "splashsurf/hilbert2_7954_particles.vtk",
    };
    int ran = 0;
    for (size_t k = 0; k < sizeof files / sizeof files[0]; k++) {
        jmf_frame fr;
        char err[512];
        int got = test_read_shared(files[k], NULL, &fr, err, sizeof err);
        if (got < 0) fail_msg("%s", err);
        if (!got) continue;
        for (int me = JM_METHOD_MT; me <= JM_METHOD_MC; me++) {
            /* the reference case (cube r/2, threshold 0.6), then a coarser
             * lattice, a thinner threshold and a shorter kernel (other
             * block sizes, other sub-box splits) */
            const float cube[] = {0.5f, 0.75f, 0.5f, 1.0f}, thr[] = {0.6f, 0.6f, 0.25f, 0.9f},
                        sl[] = {2.0f, 2.0f, 1.6f, 1.2f};
            for (int v = 0; v < 4; v++) {
                if (k >= 2 && v == 0) continue; /* the big cases on the two bench frames only */
                jm_params p = {0};
                p.radius = 0.025f;
                p.field = JM_FIELD_SPH;
                p.method = (jm_method)me;
                p.cube_size = cube[v];
                p.threshold = thr[v];
                p.smoothing_length = sl[v];
                char what[256];
                snprintf(what, sizeof what, "%s %s cube %.2f thr %.2f h %.1f", files[k], me == JM_METHOD_MC ? "mc" : "mt",
                         cube[v], thr[v], sl[v]);
                same_bytes(what, &p, fr.xyz, fr.count);
            }
        }
        jmf_frame_free(&fr);
        ran++;
    }
    if (!ran) {
        printf("skipping: ../shared/data not found\n");
        skip();
    }
}

/* a lattice block with holes and a lone pair: culling next to cavities,
 * thin walls and particles on block faces */
static void test_block_with_holes(void **state)
{
    (void)state;
    const float r = 0.025f;
    size_t n = 0;
    float *xyz = cull_holed_block(r, &n);
    assert_non_null(xyz);
    for (int me = JM_METHOD_MT; me <= JM_METHOD_MC; me++) {
        jm_params p = {0};
        p.radius = r;
        p.field = JM_FIELD_SPH;
        p.method = (jm_method)me;
        same_bytes(me == JM_METHOD_MC ? "block with holes, mc" : "block with holes, mt", &p, xyz, n);
        p.threshold = 0.35f;
        p.cube_size = 0.4f;
        same_bytes(me == JM_METHOD_MC ? "block with holes, mc, thr 0.35, cube 0.4" : "block with holes, mt, thr 0.35, cube 0.4",
                   &p, xyz, n);
    }
    free(xyz);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_block_with_holes),
        cmocka_unit_test(test_real_frames_same_bytes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

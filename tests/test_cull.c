/* test_cull.c - the SPH field sampled only near the surface gives the same mesh bytes as every node sampled, on real frames. */
#include <setjmp.h>
#include <stdarg.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>

#include "../lib/jetmesh.h"
#include "util/cull_check.h"

/* Culled (1 and 2 threads) against every node sampled: the same bytes.
 * Variants: the reference case (cube r/2, threshold 0.6), then a coarser
 * lattice, a thinner threshold and a shorter kernel (other block sizes,
 * other sub-box splits). */
#define VARIANTS 4
#define ANISOTROPIC 0
static int fill_case(size_t k, int me, int v, jm_params *p, char *what, size_t whatsz)
{
    const float cube[] = {0.5f, 0.75f, 0.5f, 1.0f}, thr[] = {0.6f, 0.6f, 0.25f, 0.9f}, sl[] = {2.0f, 2.0f, 1.6f, 1.2f};
    if (k >= 2 && v == 0) return 0; /* the big cases on the two bench frames only */
    p->radius = 0.025f;
    p->field = JM_FIELD_SPH;
    p->method = (jm_method)me;
    p->cube_size = cube[v];
    p->threshold = thr[v];
    p->smoothing_length = sl[v];
    snprintf(what, whatsz, "%s %s cube %.2f thr %.2f h %.1f", cull_frames[k], me == JM_METHOD_MC ? "mc" : "mt", cube[v],
             thr[v], sl[v]);
    return 1;
}

static void test_real_frames_same_bytes(void **state)
{
    (void)state;
    char err[512];
    const int rc = cull_real_frames(VARIANTS, fill_case, err, sizeof err);
    if (rc < 0) fail_msg("%s", err);
    if (rc > 0) {
        printf("skipping: ../shared/data not found\n");
        skip();
    }
}

/* a lattice block with holes and a lone pair: culling next to cavities,
 * thin walls and particles on block faces */
static void test_block_with_holes(void **state)
{
    (void)state;
    char err[512];
    if (cull_holed_block_cases(ANISOTROPIC, err, sizeof err) != 0) fail_msg("%s", err);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_block_with_holes),
        cmocka_unit_test(test_real_frames_same_bytes),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

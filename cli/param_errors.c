/* param_errors.c - explains refused meshing parameters, oversized frames and empty meshes by the options that set them. */
#include "param_errors.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "domain_advice.h"
#include "platform.h"

static const struct {
    const char *field, *option;
} options[] = {
    {"radius", "--radius"},
    {"cube_size", "--cube-size"},
    {"field", "--field"},
    {"method", "--method"},
    {"threshold", "--threshold"},
    {"smoothing_length", "--smoothing-length"},
    {"link_distance", "--link-distance"},
    {"aniso_radius", "--anisotropic-radius"},
    {"anisotropic", "--anisotropic"},
    {"smooth_iterations", "--smooth"},
    {"smooth_normal_iterations", "--smooth-normals"},
    {"smooth_implicit", "--smooth-implicit"},
    {"simplify_error", "--simplify"},
    {"threads", "--threads"},
    {"uv_mode", "--uv"},
    {"uv_scale", "--uv-scale"},
    {"uv_axis", "--uv-axis"},
    {"particle_aabb_min", "--particle-aabb-min"},
    {"particle_aabb_max", "--particle-aabb-max"},
    {"mesh_aabb_min", "--mesh-aabb-min"},
    {"mesh_aabb_max", "--mesh-aabb-max"},
    {"mesh_aabb_clamp", "--mesh-aabb-clamp-vertices"},
    {"min_piece_particles", "--min-piece-particles"},
    {"min_piece_volume", "--min-piece-volume"},
};

const char *param_option_name(const char *field)
{
    if (!field)
        return "the parameters";
    /* an array's element ("mesh_aabb_max[1]"): the array's option */
    const size_t n = strcspn(field, "[");
    for (size_t i = 0; i < sizeof options / sizeof options[0]; i++)
        if (strlen(options[i].field) == n && strncmp(options[i].field, field, n) == 0)
            return options[i].option;
    return field;
}

/* A box refused for its minimum not below its maximum on one axis: both
 * options and the axis in words. 1 if pr was such a problem. */
static int describe_box(const jm_params *p, const jm_param_problem *pr, char *msg, size_t len)
{
    const char *b = strchr(pr->field, '[');
    const int mesh = strncmp(pr->field, "mesh_aabb_", 10) == 0;
    if (!b || !pr->min_excluded || !isfinite(pr->min) || !(strncmp(pr->field, "particle_aabb_max", 17) == 0 || mesh))
        return 0;
    const int k = b[1] - '0';
    const float *lo = mesh ? p->mesh_aabb_min : p->particle_aabb_min, *hi = mesh ? p->mesh_aabb_max : p->particle_aabb_max;
    snprintf(msg, len,
             "%s %g,%g,%g and %s %g,%g,%g: on %c the minimum %g is not below the maximum %g; accepted: a box whose "
             "minimum is below its maximum on every axis",
             mesh ? "--mesh-aabb-min" : "--particle-aabb-min", (double)lo[0], (double)lo[1], (double)lo[2],
             mesh ? "--mesh-aabb-max" : "--particle-aabb-max", (double)hi[0], (double)hi[1], (double)hi[2], "xyz"[k],
             (double)lo[k], (double)hi[k]);
    return 1;
}

int param_errors_describe(const jm_params *p, char *msg, size_t len)
{
    jm_param_problem pr;
    if (jm_params_check(p, &pr) == JM_OK)
        return 0;
    if (describe_box(p, &pr, msg, len))
        return -1;
    snprintf(msg, len, "%s %g is out of range; accepted: %s", param_option_name(pr.field), pr.value,
             pr.accepted);
    return -1;
}

static double cube_in_force(const jm_params *p)
{
    return p->cube_size > 0 ? (double)p->cube_size : 0.5;
}

/* The smallest cube size 2, 4, 8... times the current one (at most 100)
 * whose estimate is at most limit (0: any the library accepts). 1 if found. */
static int cube_that_fits(const jm_params *p, const jm_particles *parts, size_t limit, double *out_cube,
                          size_t *out_bytes)
{
    for (double c = cube_in_force(p) * 2; c <= 100.0; c *= 2) {
        jm_params q = *p;
        q.cube_size = (float)c;
        q.max_bytes = 0;
        jm_context *ctx = NULL;
        size_t est = 0;
        int ok = jm_context_create(&q, &ctx) == JM_OK && jm_estimate_bytes(ctx, parts, &est) == JM_OK;
        jm_context_free(ctx);
        if (ok && (!limit || est <= limit)) {
            *out_cube = c;
            *out_bytes = est;
            return 1;
        }
    }
    return 0;
}

void param_errors_too_large(char *msg, size_t len, const char *path, const jm_params *p,
                            const jm_particles *parts, size_t est, size_t max_memory)
{
    char b1[32], b2[32], b3[32], hint[160] = "";
    size_t phys = platform_physical_memory();
    double cube = cube_in_force(p), fit = 0;
    size_t fit_bytes = 0;
    /* what must fit: the limit, and the machine whatever the limit */
    size_t target = max_memory && (!phys || max_memory < phys) ? max_memory : phys;
    if (cube_that_fits(p, parts, target, &fit, &fit_bytes)) {
        snprintf(hint, sizeof hint, "; --cube-size %g would need about %s", fit,
                 platform_format_bytes(fit_bytes, b3, sizeof b3));
    } else if (est && target && est > target) {
        /* even the coarsest lattice does not fit: the memory is in the
         * particles themselves (for the metasphere, its neck links, 24
         * bytes each, to every particle within the link distance), which
         * no cube size changes */
        jm_params q = *p;
        q.cube_size = 100.0f;
        q.max_bytes = 0;
        jm_context *ctx = NULL;
        size_t coarse = 0;
        int ok = jm_context_create(&q, &ctx) == JM_OK && jm_estimate_bytes(ctx, parts, &coarse) == JM_OK;
        jm_context_free(ctx);
        if (ok && coarse > target) {
            /* the links are to blame when the same particles without them
             * (the sph field's estimate) would fit */
            int meta = p->field == JM_FIELD_DEFAULT || p->field == JM_FIELD_METASPHERE;
            if (meta) {
                jm_params sph = q;
                sph.field = JM_FIELD_SPH;
                sph.method = JM_METHOD_DEFAULT;
                sph.threshold = 0.0f;
                sph.exact_surface = 0;
                size_t plain = 0;
                meta = jm_context_create(&sph, &ctx) == JM_OK && jm_estimate_bytes(ctx, parts, &plain) == JM_OK &&
                       plain <= target;
                jm_context_free(ctx);
            }
            const char *over = max_memory && target == max_memory ? "the limit of" : "this machine's";
            platform_format_bytes(est, b1, sizeof b1);
            platform_format_bytes(target, b2, sizeof b2);
            if (meta)
                snprintf(msg, len,
                         "%s: %zu particles need about %s of working memory, most of it the metasphere's links "
                         "between particles within --link-distance times -r of each other, over %s %s at any "
                         "--cube-size: -r %g is far too large for their spacing: use a smaller -r (or "
                         "--link-distance), or --field sph",
                         path, parts->count, b1, over, b2, (double)p->radius);
            else
                snprintf(msg, len,
                         "%s: %zu particles need about %s of working memory, over %s %s at any --cube-size: "
                         "raise --max-memory where the machine allows",
                         path, parts->count, b1, over, b2);
            return;
        }
    }
    if (est && phys && est > phys)
        snprintf(msg, len,
                 "%s: %zu particles need about %s of working memory at --cube-size %g, more than this "
                 "machine has (%s): use a larger --cube-size%s",
                 path, parts->count, platform_format_bytes(est, b1, sizeof b1), cube,
                 platform_format_bytes(phys, b2, sizeof b2), hint);
    else if (est && max_memory && est > max_memory)
        snprintf(msg, len,
                 "%s: %zu particles need about %s of working memory at --cube-size %g, over the limit "
                 "of %s: raise --max-memory (this machine has %s) or use a larger --cube-size%s",
                 path, parts->count, platform_format_bytes(est, b1, sizeof b1), cube,
                 platform_format_bytes(max_memory, b2, sizeof b2),
                 phys ? platform_format_bytes(phys, b3, sizeof b3) : "an unknown amount", hint);
    else
        snprintf(msg, len,
                 "%s: %zu particles over a lattice far too fine for their spread (--cube-size %g): use "
                 "a larger --cube-size%s",
                 path, parts->count, cube, hint);
}

void param_errors_domain(char *msg, size_t len, const char *path, const jm_params *p, const jm_particles *parts)
{
    size_t stride = parts->stride ? parts->stride : 3 * sizeof(float);
    double far = 0.0;
    for (size_t i = 0; i < parts->count; i++) {
        float x[3];
        memcpy(x, (const char *)parts->xyz + i * stride, sizeof x);
        for (int a = 0; a < 3; a++)
            if (fabs((double)x[a]) > far)
                far = fabs((double)x[a]);
    }
    double cube = cube_in_force(p) * (double)p->radius;
    if (far > JM_MAX_CUBES_FROM_ORIGIN * cube)
        domain_advice(msg, len, path, p, parts);
    else
        snprintf(msg, len,
                 "%s: outside the numeric domain: with -r %g and coordinates up to %g the mesh would reach "
                 "beyond the float range (about 8.5e37 with a margin): use a larger unit of length "
                 "(see jetmesh(1), LIMITS)",
                 path, (double)p->radius, far);
}

void param_errors_warn_empty(long index, const char *path, size_t particles, const jm_params *p)
{
    int sph = p->field == JM_FIELD_SPH;
    double t = p->threshold != 0 ? (double)p->threshold : (sph ? 0.6 : 0.0);
    fprintf(stderr,
            "jetmesh: warning: frame %ld (%s): %zu particles gave an empty mesh: the field nowhere "
            "reaches --threshold %g on the lattice (%s); a threshold nearer the default (%s) or a "
            "smaller --cube-size (now %g) gives a surface\n",
            index, path, particles, t, sph ? "sph: about 1 inside bulk fluid, less in thin sheets"
                                           : "metasphere: 1 at a particle's centre",
            sph ? "0.6" : "0", cube_in_force(p));
}

void param_errors_warn_no_particles(long index, const char *path, size_t dropped)
{
    if (dropped)
        fprintf(stderr,
                "jetmesh: warning: frame %ld (%s): all %zu particles were dropped (--drop-invalid): its mesh is "
                "empty\n",
                index, path, dropped);
    else
        fprintf(stderr,
                "jetmesh: warning: frame %ld (%s): the file holds no particles (a CSV with only its header, a "
                "VTU without a <Piece>, a count of 0): its mesh is empty\n",
                index, path);
}

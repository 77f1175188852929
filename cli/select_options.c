/* select_options.c - reads the options that choose what is meshed and kept (particle box, small pieces, mesh clip box), for convert and bench (their names and help: mesh_options.c). */
#include "select_options.h"

#include <limits.h>
#include <string.h>

#include "numbers.h"
#include "options.h"
#include "param_errors.h"

/* "X,Y,Z": three finite numbers. 0 or -1. */
static int parse_xyz(const char *arg, float out[3])
{
    char buf[256];
    size_t n = strlen(arg);
    if (n == 0 || n >= sizeof buf)
        return -1;
    memcpy(buf, arg, n + 1);
    char *s = buf;
    for (int k = 0; k < 3; k++) {
        char *comma = strchr(s, ',');
        if ((k < 2) != (comma != NULL))
            return -1;
        if (comma)
            *comma = '\0';
        double v;
        if (cli_parse_double(s, &v) != 0 || v < -3.4e38 || v > 3.4e38)
            return -1;
        out[k] = (float)v;
        s = comma ? comma + 1 : s;
    }
    return 0;
}

int select_option(const char *cmd, int c, const char *arg, jm_params *p, select_given *g)
{
    static const char *const box_name[4] = {"--particle-aabb-min", "--particle-aabb-max", "--mesh-aabb-min",
                                            "--mesh-aabb-max"};
    float *box[4] = {p->particle_aabb_min, p->particle_aabb_max, p->mesh_aabb_min, p->mesh_aabb_max};
    int *given[4] = {&g->pmin, &g->pmax, &g->mmin, &g->mmax};
    double d;
    long l;
    switch (c) {
    case SO_PAABB_MIN:
    case SO_PAABB_MAX:
    case SO_MAABB_MIN:
    case SO_MAABB_MAX: {
        const int k = c - SO_PAABB_MIN;
        if (parse_xyz(arg, box[k]) != 0)
            return options_usage_error(cmd, "%s needs X,Y,Z: three numbers separated by commas (e.g. -1,0,-1), not '%s'",
                                       box_name[k], arg);
        *given[k] = 1;
        return OPTIONS_RUN;
    }
    case SO_MAABB_CLAMP: p->mesh_aabb_clamp = 1; return OPTIONS_RUN;
    case SO_MIN_PARTICLES:
        if (cli_parse_long(arg, 0, INT_MAX, &l) != 0)
            return options_usage_error(cmd, "--min-piece-particles must be a whole number from 0 (off) to %d, not '%s'",
                                       INT_MAX, arg);
        p->min_piece_particles = (int)l;
        return OPTIONS_RUN;
    case SO_MIN_VOLUME:
        if (cli_parse_double(arg, &d) != 0 || !(d >= 0) || d > 1e30)
            return options_usage_error(cmd, "--min-piece-volume must be a number from 0 (off) to 1e30 (times R^3), not '%s'",
                                       arg);
        p->min_piece_volume = (float)d;
        return OPTIONS_RUN;
    default: return options_usage_error(cmd, "internal: option %d is not a selection option", c);
    }
}

int select_any(const jm_params *p)
{
    jm_params q;
    memset(&q, 0, sizeof q);
    select_copy(&q, p);
    q.min_piece_particles = q.min_piece_particles > 1 ? q.min_piece_particles : 0;
    static const jm_params zero;
    return memcmp(q.particle_aabb_min, zero.particle_aabb_min, sizeof q.particle_aabb_min) != 0 ||
           memcmp(q.particle_aabb_max, zero.particle_aabb_max, sizeof q.particle_aabb_max) != 0 ||
           memcmp(q.mesh_aabb_min, zero.mesh_aabb_min, sizeof q.mesh_aabb_min) != 0 ||
           memcmp(q.mesh_aabb_max, zero.mesh_aabb_max, sizeof q.mesh_aabb_max) != 0 || q.min_piece_particles ||
           q.min_piece_volume > 0.0f;
}

void select_copy(jm_params *dst, const jm_params *src)
{
    memcpy(dst->particle_aabb_min, src->particle_aabb_min, sizeof dst->particle_aabb_min);
    memcpy(dst->particle_aabb_max, src->particle_aabb_max, sizeof dst->particle_aabb_max);
    memcpy(dst->mesh_aabb_min, src->mesh_aabb_min, sizeof dst->mesh_aabb_min);
    memcpy(dst->mesh_aabb_max, src->mesh_aabb_max, sizeof dst->mesh_aabb_max);
    dst->mesh_aabb_clamp = src->mesh_aabb_clamp;
    dst->min_piece_particles = src->min_piece_particles;
    dst->min_piece_volume = src->min_piece_volume;
}

int select_finish(const char *cmd, const jm_params *p, const select_given *g)
{
    if (g->pmin != g->pmax)
        return options_usage_error(cmd, "%s needs %s too: the particle box is given by both corners",
                                   g->pmin ? "--particle-aabb-min" : "--particle-aabb-max",
                                   g->pmin ? "--particle-aabb-max" : "--particle-aabb-min");
    if (g->mmin != g->mmax)
        return options_usage_error(cmd, "%s needs %s too: the clip box is given by both corners",
                                   g->mmin ? "--mesh-aabb-min" : "--mesh-aabb-max",
                                   g->mmin ? "--mesh-aabb-max" : "--mesh-aabb-min");
    const float *lo[2] = {p->particle_aabb_min, p->mesh_aabb_min}, *hi[2] = {p->particle_aabb_max, p->mesh_aabb_max};
    const int on[2] = {g->pmin, g->mmin};
    for (int b = 0; b < 2; b++) {
        int zero = 1;
        for (int k = 0; k < 3; k++) zero &= lo[b][k] == 0.0f && hi[b][k] == 0.0f;
        if (on[b] && zero) /* the library would take it for no box */
            return options_usage_error(cmd, "%s 0,0,0 and %s 0,0,0: the box is empty: its minimum must be below "
                                            "its maximum on every axis",
                                       b ? "--mesh-aabb-min" : "--particle-aabb-min",
                                       b ? "--mesh-aabb-max" : "--particle-aabb-max");
    }
    if (p->mesh_aabb_clamp && !g->mmin)
        return options_usage_error(cmd, "--mesh-aabb-clamp-vertices needs the clip box: --mesh-aabb-min X,Y,Z "
                                        "--mesh-aabb-max X,Y,Z");
    /* the ranges, as the library checks them, alone (the other members
     * are checked when the context is made) */
    jm_params q;
    memset(&q, 0, sizeof q);
    q.radius = 1.0f;
    select_copy(&q, p);
    char msg[512];
    if (param_errors_describe(&q, msg, sizeof msg) != 0)
        return options_usage_error(cmd, "%s", msg);
    return OPTIONS_RUN;
}

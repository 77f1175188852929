/* generate.c - `jetmesh generate SCENE`: writes the jet, block or spray scenes, one file per frame, atomically. */
#include "generate.h"

#include <errno.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../formats/atomic_file.h"
#include "options.h"
#include "platform.h"
#include "scenes.h"
#include "sequence.h"
#include "signals.h"

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), m = strlen(suffix);
    return n > m && strcmp(s + n - m, suffix) == 0;
}

/* Writes the particles as "x,y,z" CSV (with a header line) or raw
 * little-endian float32 XYZ; atomically. 0 or -1 (message printed). */
static int write_points(const char *path, const scene_points *pts, int xyz)
{
    char err[512];
    if (platform_make_dirs(path, 1) != 0) {
        fprintf(stderr, "jetmesh generate: %s: cannot create its directory: %s\n", path,
                strerror(errno));
        return -1;
    }
    jmf_atomic_file af;
    if (jmf_atomic_open(&af, path, err, sizeof err) != JMF_OK) {
        fprintf(stderr, "jetmesh generate: %s\n", err);
        return -1;
    }
    if (xyz) {
        for (size_t i = 0; i < 3 * pts->count; i++) {
            uint32_t u;
            memcpy(&u, &pts->xyz[i], 4);
            unsigned char b[4] = {(unsigned char)u, (unsigned char)(u >> 8),
                                  (unsigned char)(u >> 16), (unsigned char)(u >> 24)};
            fwrite(b, 1, 4, af.fp);
        }
    } else {
        fputs("x,y,z\n", af.fp);
        for (size_t i = 0; i < pts->count; i++) {
            char num[3][64];
            for (int a = 0; a < 3; a++) {
                snprintf(num[a], sizeof num[a], "%.6f", (double)pts->xyz[3 * i + a]);
                if (strcmp(num[a], "-0.000000") == 0) /* no negative zeros in the files */
                    strcpy(num[a], "0.000000");
            }
            fprintf(af.fp, "%s,%s,%s\n", num[0], num[1], num[2]);
        }
    }
    if (jmf_atomic_commit(&af, err, sizeof err) != JMF_OK) {
        fprintf(stderr, "jetmesh generate: %s\n", err);
        return -1;
    }
    return 0;
}

int cmd_generate(int argc, char **argv)
{
    generate_options o;
    int rc = options_parse_generate(argc, argv, &o);
    if (rc == OPTIONS_DONE)
        return 0;
    if (rc != OPTIONS_RUN)
        return 2;
    int xyz = ends_with(o.output, ".xyz");
    if (!xyz && !ends_with(o.output, ".csv"))
        return options_usage_error("generate", "the output must end in .csv or .xyz, not '%s'",
                                   o.output);
    int jet = strcmp(o.scene, "jet") == 0;
    int tmpl = seq_is_template(o.output);
    if (seq_kind_of(o.output) == SEQ_INVALID)
        return options_usage_error("generate", "'%s' has more than one frame placeholder", o.output);
    seq_range fr = o.frames;
    if (!fr.set) {
        long last = jet ? SCENE_JET_FRAMES - 1 : 0;
        fr.start = jet && tmpl ? 0 : last;
        fr.end = last;
        fr.step = 1;
        fr.set = 1;
    }
    if (!tmpl && fr.end != fr.start)
        return options_usage_error("generate",
                                   "several frames need {} or %%03d in the output name, like jet_{}.csv");
    if (fr.end > 100000000L)
        return options_usage_error("generate", "frame numbers go up to 100000000");
    signals_install_cleanup();
    for (long f = fr.start; f <= fr.end; f += fr.step) {
        scene_points pts = {0};
        int s;
        if (jet)
            s = scene_jet((int)f, o.radius, &pts);
        else if (strcmp(o.scene, "block") == 0)
            s = scene_block(o.count, o.radius, o.seed + (uint64_t)f, &pts);
        else if (strcmp(o.scene, "ball") == 0)
            s = scene_ball(o.count, o.radius, o.seed + (uint64_t)f, &pts);
        else if (strcmp(o.scene, "droplets") == 0)
            s = scene_droplets(o.count, o.radius, o.seed + (uint64_t)f, &pts);
        else
            s = scene_spray(o.count, o.radius, o.seed + (uint64_t)f, &pts);
        if (s != 0) {
            fprintf(stderr, "jetmesh generate: out of memory for %s\n", o.scene);
            return 3;
        }
        char *path = tmpl ? seq_substitute(o.output, f, NULL) : strdup(o.output);
        if (!path) {
            scene_points_free(&pts);
            fprintf(stderr, "jetmesh generate: out of memory\n");
            return 3;
        }
        int w = write_points(path, &pts, xyz);
        if (w == 0 && !o.quiet)
            printf("frame %ld: %zu particles -> %s\n", f, pts.count, path);
        free(path);
        scene_points_free(&pts);
        if (w != 0)
            return 1;
        if (fr.end - f < fr.step)
            break;
    }
    if (!o.quiet)
        fflush(stdout);
    return 0;
}

/* meshquality.c - prints a mesh's figures as one JSON line: smoothness, distance and outline pull-in against a raw mesh, pieces, normals, sphere. */
#include <math.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../util/meshmetrics.h"

static void usage(void)
{
    fprintf(stderr,
            "usage: meshquality MESH.obj [--ref RAW.obj] [-r R] [--sphere] [--pixel P] [--quick]\n"
            "  MESH, RAW   Wavefront OBJ (jetmesh -o x.obj, splashsurf's ssbench -o x.obj)\n"
            "  --ref RAW   the raw mesh the figures of distance, outline and pieces compare against\n"
            "  -r R        particle radius: lengths are printed in units of R (default 0.025)\n"
            "  --sphere    the largest piece is a ball: its radial deviation and normals\n"
            "  --pixel P   the outline raster's pixel, relative to R (default 0.1)\n"
            "  --quick     no distances of RAW's vertices from MESH (ref_dist_*: -1)\n"
            "Figures (lengths in R):\n"
            "  dihedral_mean_deg  mean angle between the normals of the two triangles of an edge\n"
            "  dist_p99           99th percentile of the distance of MESH's vertices from RAW's surface\n"
            "  ref_dist_p99       ... of RAW's vertices from MESH's surface\n"
            "  pull_in            outline pull-in: MESH and RAW projected along x, y and z; the largest\n"
            "                     distance of a pixel of RAW's silhouette from MESH's silhouette\n"
            "  pull_in_p99        99th percentile of that distance over the pixels of RAW's outline\n"
            "  push_out           the largest distance of MESH's silhouette outside RAW's\n"
            "  bbox_pull_in       the largest inward move of a side of the bounding box\n"
            "  volume_change      (volume - RAW's) / RAW's\n"
            "  pieces, lost, extra  outer shells; RAW's without a match in MESH (nearest centroid\n"
            "                     within twice its largest principal extent, at least 2 R), MESH's unmatched\n"
            "  min_piece_volume   least volume ratio of a matched piece (under85: how many under 0.85)\n"
            "  min_piece_round    least ratio of roundness (smallest / largest principal extent)\n"
            "  normals_p95_deg, normals_away  vertex normals against their fans' normals\n"
            "  radial_sd, sphere_normals_p95_deg  with --sphere\n");
}

int main(int argc, char **argv)
{
    const char *path = NULL, *refp = NULL;
    double R = 0.025, pixel = 0.1;
    int sphere = 0, quick = 0;
    for (int i = 1; i < argc; i++) {
        if (!strcmp(argv[i], "--ref") && i + 1 < argc) refp = argv[++i];
        else if (!strcmp(argv[i], "-r") && i + 1 < argc) R = atof(argv[++i]);
        else if (!strcmp(argv[i], "--pixel") && i + 1 < argc) pixel = atof(argv[++i]);
        else if (!strcmp(argv[i], "--sphere")) sphere = 1;
        else if (!strcmp(argv[i], "--quick")) quick = 1;
        else if (argv[i][0] != '-' && !path) path = argv[i];
        else {
            usage();
            return 2;
        }
    }
    if (!path || !(R > 0) || !(pixel > 0)) {
        usage();
        return 2;
    }
    char err[512];
    mm_mesh m, ref;
    if (mm_read_obj(path, &m, err, sizeof err) || (refp && mm_read_obj(refp, &ref, err, sizeof err))) {
        fprintf(stderr, "meshquality: %s\n", err);
        return 1;
    }
    double dmean, d95, n95, away, vol = mm_volume(&m);
    mm_dihedral(&m, &dmean, &d95);
    mm_normals(&m, &n95, &away);
    mm_piece *pc;
    uint32_t *lab = NULL;
    size_t np = mm_pieces(&m, &pc, &lab), outer = 0;
    for (size_t k = 0; k < np; k++) outer += pc[k].volume > 0;
    printf("{\"vertices\":%zu,\"triangles\":%zu,\"volume\":%.9g,\"area\":%.9g,\"dihedral_mean_deg\":%.4f,"
           "\"dihedral_p95_deg\":%.3f,\"pieces\":%zu,\"inner_shells\":%zu,\"normals_p95_deg\":%.3f,"
           "\"normals_away\":%.6f",
           m.nv, m.nt, vol, mm_area(&m), dmean, d95, outer, np - outer, n95, away);
    if (sphere && np > 0) {
        uint32_t big = 0;
        for (size_t k = 1; k < np; k++)
            if (pc[k].volume > pc[big].volume) big = (uint32_t)k;
        double sd, a95;
        mm_sphere(&m, lab, big, &sd, &a95);
        printf(",\"radial_sd\":%.4f,\"sphere_normals_p95_deg\":%.3f", sd / R, a95);
    }
    if (refp) {
        double p50, p99, mx, r50, r99, rmx, pull, pull99, push, vref = mm_volume(&ref);
        mm_distances(&m, &ref, &p50, &p99, &mx);
        if (quick) r50 = r99 = rmx = -R;
        else mm_distances(&ref, &m, &r50, &r99, &rmx);
        mm_outline(&ref, &m, pixel * R, &pull, &pull99, &push);
        mm_piece *pr;
        size_t nr = mm_pieces(&ref, &pr, NULL);
        mm_match mt;
        mm_match_pieces(pr, nr, pc, np, 2 * R, &mt);
        printf(",\"dist_p50\":%.4f,\"dist_p99\":%.4f,\"dist_max\":%.4f,\"ref_dist_p99\":%.4f,\"ref_dist_max\":%.4f,"
               "\"pull_in\":%.4f,\"pull_in_p99\":%.4f,\"push_out\":%.4f,\"bbox_pull_in\":%.4f,"
               "\"volume_change\":%.6f,\"ref_pieces\":%zu,\"lost\":%zu,\"extra\":%zu,\"min_piece_volume\":%.4f,"
               "\"under85\":%zu,\"min_piece_round\":%.4f,\"worst_piece_at\":[%.5g,%.5g,%.5g],"
               "\"least_round_at\":[%.5g,%.5g,%.5g],\"least_round\":[%.4f,%.4f]",
               p50 / R, p99 / R, mx / R, r99 / R, rmx / R, pull / R, pull99 / R, push / R, mm_bbox_pull(&ref, &m) / R,
               (vol - vref) / vref, mt.ref_pieces, mt.lost, mt.extra, mt.min_volume, mt.under85, mt.min_round,
               mt.worst_c[0], mt.worst_c[1], mt.worst_c[2], mt.round_c[0], mt.round_c[1], mt.round_c[2],
               mt.round_ref, mt.round_m);
        free(pr);
        mm_mesh_free(&ref);
    }
    printf("}\n");
    free(pc);
    free(lab);
    mm_mesh_free(&m);
    return 0;
}

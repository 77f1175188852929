/* shells.c - meshes a frame (or a generated sheet) isotropic and anisotropic and prints its shells: nesting, volumes, normals. */
#include <math.h>
#include <stdint.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../formats/reader.h"
#include "../../lib/jetmesh.h"
#include "../util/meshcheck.h"
#include "../util/sheets.h"

typedef struct {
    uint64_t key;
    uint32_t tri;
} half_edge;
static int cmp_he(const void *a, const void *b)
{
    const half_edge *x = a, *y = b;
    return x->key < y->key ? -1 : x->key > y->key;
}
static void face_normal(const jm_mesh *m, size_t t, double n[3])
{
    const uint32_t *i = m->indices + 3 * t;
    const float *a = m->positions + 3 * i[0], *b = m->positions + 3 * i[1], *c = m->positions + 3 * i[2];
    double u[3], w[3];
    for (int k = 0; k < 3; k++) u[k] = (double)b[k] - a[k], w[k] = (double)c[k] - a[k];
    n[0] = u[1] * w[2] - u[2] * w[1];
    n[1] = u[2] * w[0] - u[0] * w[2];
    n[2] = u[0] * w[1] - u[1] * w[0];
    double l = sqrt(n[0] * n[0] + n[1] * n[1] + n[2] * n[2]);
    for (int k = 0; k < 3; k++) n[k] = l > 0 ? n[k] / l : 0;
}
/* the mean angle between the normals of triangles sharing an edge, degrees */
static double mean_dihedral(const jm_mesh *m)
{
    size_t nt = m->triangle_count, nh = 3 * nt, pairs = 0;
    half_edge *h = malloc((nh ? nh : 1) * sizeof *h);
    if (!h) return NAN;
    for (size_t t = 0; t < nt; t++)
        for (int e = 0; e < 3; e++) {
            uint32_t a = m->indices[3 * t + e], b = m->indices[3 * t + (e + 1) % 3];
            h[3 * t + e].key = a < b ? (uint64_t)a << 32 | b : (uint64_t)b << 32 | a;
            h[3 * t + e].tri = (uint32_t)t;
        }
    qsort(h, nh, sizeof *h, cmp_he);
    double sum = 0;
    for (size_t k = 0; k + 1 < nh; k++)
        if (h[k].key == h[k + 1].key) {
            double n1[3], n2[3];
            face_normal(m, h[k].tri, n1);
            face_normal(m, h[k + 1].tri, n2);
            double c = n1[0] * n2[0] + n1[1] * n2[1] + n1[2] * n2[2];
            sum += acos(c > 1 ? 1 : (c < -1 ? -1 : c));
            pairs++;
            k++;
        }
    free(h);
    return pairs ? sum / pairs * 180 / M_PI : 0;
}

static void usage(void)
{
    fprintf(stderr, "usage: shells INPUT [-r R] [--cube C] [--mt] [-j N] [--only-aniso]\n"
                    "  INPUT: a particle file, or sheet:LAYERS[:JITTER[:SEED[:GAP]]] (GAP > 0: droplets\n"
                    "  over the sheet, < 0: beside its rim)\n"
                    "Prints, for the isotropic and the anisotropic SPH field: triangles, shells, inner\n"
                    "shells (enclosed by another) and their area in r^2, negative shells, volume, and\n"
                    "the corners whose normal faces away from their triangle.\n");
}

int main(int argc, char **argv)
{
    if (argc < 2) {
        usage();
        return 2;
    }
    float r = 0.025f, cube = 0.5f;
    int mt = 0, threads = 1, only = 0;
    float kr = 0, ks = 0;
    for (int i = 2; i < argc; i++) {
        if (!strcmp(argv[i], "-r") && i + 1 < argc) r = strtof(argv[++i], NULL);
        else if (!strcmp(argv[i], "--cube") && i + 1 < argc) cube = strtof(argv[++i], NULL);
        else if (!strcmp(argv[i], "-j") && i + 1 < argc) threads = atoi(argv[++i]);
        else if (!strcmp(argv[i], "--mt")) mt = 1;
        else if (!strcmp(argv[i], "--kr") && i + 1 < argc) kr = strtof(argv[++i], NULL);
        else if (!strcmp(argv[i], "--ks") && i + 1 < argc) ks = strtof(argv[++i], NULL);
        else if (!strcmp(argv[i], "--only-aniso")) only = 1;
        else {
            usage();
            return 2;
        }
    }
    float *xyz = NULL;
    size_t n = 0;
    jmf_frame fr;
    memset(&fr, 0, sizeof fr);
    if (!strncmp(argv[1], "sheet:", 6)) {
        int layers = 1;
        float jit = 0, gap = 0;
        unsigned seed = 1;
        int side = 24;
        sscanf(argv[1] + 6, "%d:%f:%u:%f:%d", &layers, &jit, &seed, &gap, &side);
        /* gap > 0: droplets over the sheet; gap < 0: beside its rim */
        n = test_sheet(layers, side, r, jit * r, seed, gap > 0 ? 1 : (gap < 0 ? 2 : 0), fabsf(gap), &xyz, NULL);
    } else {
        char err[512];
        jmf_read_options o;
        memset(&o, 0, sizeof o);
        if (jmf_read_particles(argv[1], &o, &fr, err, sizeof err) != JMF_OK) {
            fprintf(stderr, "shells: %s\n", err);
            return 1;
        }
        xyz = fr.xyz;
        n = fr.count;
    }
    double v0 = 0;
    mc_shell *iso_list = NULL;
    size_t iso_n = 0;
    for (int an = only; an <= 1; an++) {
        jm_params p;
        memset(&p, 0, sizeof p);
        p.radius = r;
        p.field = JM_FIELD_SPH;
        p.method = mt ? JM_METHOD_MT : JM_METHOD_MC;
        p.cube_size = cube;
        p.threads = threads;
        p.anisotropic = an;
        if (an) p.aniso_max_ratio = kr, p.aniso_scale = ks;
        jm_context *ctx = NULL;
        jm_mesh m;
        jm_particles in = {xyz, n, 0, NULL};
        if (jm_context_create(&p, &ctx) != JM_OK || jm_mesh_particles(ctx, &in, &m, NULL) != JM_OK) {
            fprintf(stderr, "shells: meshing failed\n");
            return 3;
        }
        mc_shells s;
        mc_report rep;
        int ok = mc_check(&m, &rep);
        mc_shell *list;
        mc_shell_check(&m, &s, &list);
        if (!an) v0 = s.volume;
        printf("%s %-5s dihedral %.2f deg tris %7zu shells %4zu inner %zu (area %.0f r^2, vol %.1f r^3) negative %zu volume %.1f r^3"
               "%s corners away %.2f %%%s\n",
               argv[1], an ? "aniso" : "iso", mean_dihedral(&m), m.triangle_count, s.components, s.inner, s.inner_area / (r * r),
               s.inner_volume / (r * r * r), s.negative, s.volume / (r * r * r), "", 100.0 * s.corners_away / (double)(s.corners ? s.corners : 1),
               ok ? "" : " NOT CLOSED");
        if (an && !only) printf("    volume aniso/iso %.3f\n", s.volume / v0);
        /* the isotropic mesh's small shells (droplets): the anisotropic shells
         * meeting each one's box, and their volume */
        if (an && iso_list) {
            size_t lost = 0, kept = 0;
            double worst = 1e9;
            for (size_t k = 0; k < iso_n; k++) {
                const mc_shell *d = &iso_list[k];
                if (d->inner || d->volume > 200 * r * r * r) continue;
                double v = 0;
                int hits = 0;
                for (size_t e = 0; e < s.components; e++) {
                    const mc_shell *a = &list[e];
                    if (a->inner || a->volume > 400 * r * r * r || a->hi[0] < d->lo[0] || a->lo[0] > d->hi[0] || a->hi[1] < d->lo[1] ||
                        a->lo[1] > d->hi[1] || a->hi[2] < d->lo[2] || a->lo[2] > d->hi[2])
                        continue;
                    hits++;
                    v += a->volume;
                }
                if (!hits) {
                    lost++;
                    printf("    droplet lost or merged: %.2f r^3 at (%.3f %.3f %.3f)\n", d->volume / (r * r * r),
                           0.5 * (d->lo[0] + d->hi[0]), 0.5 * (d->lo[1] + d->hi[1]), 0.5 * (d->lo[2] + d->hi[2]));
                } else {
                    kept++;
                    if (v / d->volume < worst) worst = v / d->volume;
                }
            }
            printf("    droplets (iso shells under 200 r^3): kept %zu (least volume ratio %.2f), lost or merged %zu\n",
                   kept, kept ? worst : 0.0, lost);
        }
        for (size_t k = 0; k < s.components; k++)
            if ((list[k].volume < 200 * r * r * r && getenv("SHELLS_VERBOSE")) || list[k].inner)
                printf("    shell %zu: volume %.2f r^3 area %.1f r^2%s at (%.3f %.3f %.3f), %zu particle centres inside\n", k,
                       list[k].volume / (r * r * r), list[k].area / (r * r), list[k].inner ? " inner" : "",
                       0.5 * (list[k].lo[0] + list[k].hi[0]), 0.5 * (list[k].lo[1] + list[k].hi[1]),
                       0.5 * (list[k].lo[2] + list[k].hi[2]), list[k].inner ? mc_points_in_shell(&m, k, xyz, n) : 0);
        if (!an) {
            iso_list = list;
            iso_n = s.components;
        } else
            free(list);
        jm_context_free(ctx);
    }
    free(iso_list);
    if (fr.xyz) jmf_frame_free(&fr);
    else free(xyz);
    return 0;
}

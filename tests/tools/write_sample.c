/* write_sample.c - writes a hand-built test mesh to a file with jmf_write_mesh, for the writer shell tests. */
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../../formats/writer.h"
#include "../util/test_meshes.h"

static void usage(void)
{
    fprintf(stderr,
            "usage: write_sample MESH OUT [options]\n"
            "  MESH: octahedron | icosphere[:L] | torus:NUxNV | grid | empty\n"
            "  --format F        obj gltf glb drc ply vtk (default: from OUT)\n"
            "  --draco           Draco-compress glTF/GLB\n"
            "  --bits P,N,U      Draco quantization bits (positions, normals, uvs)\n"
            "  --speed S         Draco encoder speed 1-10\n"
            "  --z-up            rotate +Z up to glTF's +Y up\n"
            "  --embed           .gltf with the buffer embedded\n"
            "  --no-normals, --no-uvs\n"
            "  --positions FILE  also dump the positions as written (raw float32, z-up applied)\n"
            "Prints {\"vertices\", \"triangles\", \"min\", \"max\", \"bytes\"} of the source mesh.\n");
}

int main(int argc, char **argv)
{
    if (argc < 3) {
        usage();
        return 2;
    }
    jmf_write_options opt;
    memset(&opt, 0, sizeof opt);
    const char *dump = NULL;
    int no_normals = 0, no_uvs = 0;
    for (int i = 3; i < argc; i++) {
        const char *a = argv[i];
        if (strcmp(a, "--format") == 0 && i + 1 < argc) {
            int f = jmf_output_format_parse(argv[++i]);
            if (f < 0) {
                fprintf(stderr, "write_sample: unknown format %s\n", argv[i]);
                return 2;
            }
            opt.format = (jmf_output_format)f;
        } else if (strcmp(a, "--draco") == 0) {
            opt.draco = 1;
        } else if (strcmp(a, "--bits") == 0 && i + 1 < argc) {
            if (sscanf(argv[++i], "%d,%d,%d", &opt.draco_position_bits, &opt.draco_normal_bits,
                       &opt.draco_uv_bits) != 3) {
                fprintf(stderr, "write_sample: --bits wants P,N,U\n");
                return 2;
            }
        } else if (strcmp(a, "--speed") == 0 && i + 1 < argc) {
            opt.draco_speed = atoi(argv[++i]);
        } else if (strcmp(a, "--z-up") == 0) {
            opt.z_up = 1;
        } else if (strcmp(a, "--embed") == 0) {
            opt.embed = 1;
        } else if (strcmp(a, "--no-normals") == 0) {
            no_normals = 1;
        } else if (strcmp(a, "--no-uvs") == 0) {
            no_uvs = 1;
        } else if (strcmp(a, "--positions") == 0 && i + 1 < argc) {
            dump = argv[++i];
        } else {
            usage();
            return 2;
        }
    }
    test_mesh tm;
    if (test_mesh_make(argv[1], &tm) != 0) {
        fprintf(stderr, "write_sample: unknown mesh %s\n", argv[1]);
        return 2;
    }
    if (no_normals) tm.mesh.normals = NULL;
    if (no_uvs) tm.mesh.uvs = NULL;

    char err[512];
    size_t bytes = 0;
    jmf_status st = jmf_write_mesh(argv[2], &tm.mesh, &opt, &bytes, err, sizeof err);
    if (st != JMF_OK) {
        fprintf(stderr, "write_sample: %s\n", err);
        test_mesh_free(&tm);
        return 1;
    }
    const jm_mesh *m = &tm.mesh;
    if (dump) {
        FILE *f = fopen(dump, "wb");
        for (size_t i = 0; f && i < m->vertex_count; i++) {
            const float *p = m->positions + 3 * i;
            float q[3] = {p[0], opt.z_up ? p[2] : p[1], opt.z_up ? -p[1] : p[2]};
            fwrite(q, sizeof q, 1, f);
        }
        if (!f || fclose(f) != 0) {
            fprintf(stderr, "write_sample: cannot write %s\n", dump);
            return 1;
        }
    }
    printf("{\"vertices\": %zu, \"triangles\": %zu, \"min\": [%.9g, %.9g, %.9g], "
           "\"max\": [%.9g, %.9g, %.9g], \"bytes\": %zu}\n",
           m->vertex_count, m->triangle_count, m->bounds_min[0], m->bounds_min[1],
           m->bounds_min[2], m->bounds_max[0], m->bounds_max[1], m->bounds_max[2], bytes);
    test_mesh_free(&tm);
    return 0;
}

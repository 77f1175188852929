/* to_xyz.c - writes the particles of any frame jetmesh reads as raw float32 XYZ (the input splashsurf's ssbench takes). */
#include <stdio.h>
#include <stdlib.h>

#include "../../formats/reader.h"

int main(int argc, char **argv)
{
    if (argc != 3) {
        fprintf(stderr, "usage: to_xyz FRAME OUT.xyz\n");
        return 2;
    }
    jmf_read_options opt = {0};
    jmf_frame fr;
    char err[512];
    if (jmf_read_particles(argv[1], &opt, &fr, err, sizeof err) != JMF_OK) {
        fprintf(stderr, "to_xyz: %s\n", err);
        return 1;
    }
    FILE *f = fopen(argv[2], "wb");
    /* raw little-endian float32 triples: the machines this runs on are little-endian */
    int bad = !f || fwrite(fr.xyz, 3 * sizeof(float), fr.count, f) != fr.count;
    if (f && fclose(f) != 0) bad = 1;
    if (bad) fprintf(stderr, "to_xyz: cannot write %s\n", argv[2]);
    jmf_frame_free(&fr);
    return bad ? 1 : 0;
}

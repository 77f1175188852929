/* shared_data.c - test helper: reads a particle frame from the shared data folder (../shared/data or $JETMESH_SHARED/data). */
#include "shared_data.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

int test_read_shared(const char *rel, const jmf_read_options *opt, jmf_frame *fr, char *err, size_t errlen)
{
    const char *shared = getenv("JETMESH_SHARED");
    char path[1024];
    snprintf(path, sizeof path, "%s/data/%s", shared ? shared : "../shared", rel);
    jmf_read_options defaults;
    memset(&defaults, 0, sizeof defaults);
    memset(fr, 0, sizeof *fr);
    jmf_status s = jmf_read_particles(path, opt ? opt : &defaults, fr, err, errlen);
    if (s == JMF_E_IO) return 0;
    return s == JMF_OK ? 1 : -1;
}

/* pvd.c - writes the ParaView collection (.pvd) of a VTK or PLY sequence: one DataSet per frame with its time. */
#include "pvd.h"

#include <limits.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../formats/atomic_file.h"

char *pvd_path_for(const char *output)
{
    size_t n = strlen(output);
    char *p = malloc(n + 16);
    if (!p)
        return NULL;
    const char *slash = strrchr(output, '/');
    if (n && output[n - 1] == '/') {
        snprintf(p, n + 16, "%ssequence.pvd", output);
        return p;
    }
    /* the part before the placeholder ({} or %...d), else before the extension */
    const char *ph = strstr(output, "{}");
    if (!ph) {
        ph = strchr(slash ? slash : output, '%');
    }
    size_t stem;
    if (ph) {
        stem = (size_t)(ph - output);
    } else {
        const char *dot = strrchr(output, '.');
        stem = dot && (!slash || dot > slash) ? (size_t)(dot - output) : n;
    }
    while (stem > 0 && (output[stem - 1] == '_' || output[stem - 1] == '-' || output[stem - 1] == '.'))
        stem--;
    if (stem == 0 || output[stem - 1] == '/') {
        memcpy(p, output, stem);
        strcpy(p + stem, "sequence.pvd");
        return p;
    }
    memcpy(p, output, stem);
    strcpy(p + stem, ".pvd");
    return p;
}

static void xml_escaped(FILE *f, const char *s)
{
    for (; *s; s++) {
        switch (*s) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        default: fputc(*s, f); break;
        }
    }
}

int pvd_write(const char *path, char *const *files, const double *times, size_t n, int no_sync, char *err,
              size_t errlen)
{
    jmf_atomic_file af;
    if (jmf_atomic_open(&af, path, err, errlen) != JMF_OK)
        return -1;
    af.no_sync = no_sync;
    const char *slash = strrchr(path, '/');
    size_t dirlen = slash ? (size_t)(slash - path) + 1 : 0;
    fputs("<?xml version=\"1.0\"?>\n"
          "<VTKFile type=\"Collection\" version=\"0.1\" byte_order=\"LittleEndian\">\n"
          "  <Collection>\n", af.fp);
    for (size_t i = 0; i < n; i++) {
        const char *f = files[i];
        char abs[PATH_MAX];
        if (dirlen && strncmp(f, path, dirlen) == 0)
            f += dirlen; /* relative to the .pvd */
        else if (dirlen && f[0] != '/' && realpath(files[i], abs))
            f = abs;
        fprintf(af.fp, "    <DataSet timestep=\"%.17g\" group=\"\" part=\"0\" file=\"", times[i]);
        xml_escaped(af.fp, f);
        fputs("\"/>\n", af.fp);
    }
    fputs("  </Collection>\n</VTKFile>\n", af.fp);
    if (ferror(af.fp)) {
        snprintf(err, errlen, "%s: write error", path);
        jmf_atomic_abort(&af);
        return -1;
    }
    return jmf_atomic_commit(&af, err, errlen) == JMF_OK ? 0 : -1;
}

/* vertex_attrs.c - --attributes: resolves "all" from the first frame and interpolates each frame's arrays to its vertices. */
#include "vertex_attrs.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>

#include "convert.h"

int vattrs_resolve_all(const char *attributes, const jmf_read_options *read, inputs *in, char **out)
{
    const seq_list *frames = in->frames;
    *out = NULL;
    if (!attributes || strcasecmp(attributes, "all") != 0)
        return EXIT_ALL_OK;
    for (size_t i = 0; i < frames->count && i < 8; i++) {
        jmf_read_options o = *read;
        jmf_frame fr;
        char err[1024];
        o.attributes = "all";
        if (inputs_read(in, i, &o, &fr, err, sizeof err, NULL) != JMF_OK)
            continue; /* it fails in its turn */
        size_t len = 1;
        for (size_t k = 0; k < fr.attribute_count; k++)
            len += strlen(fr.attributes[k].name) + 1;
        char *list = malloc(len);
        if (!list) {
            jmf_frame_free(&fr);
            fprintf(stderr, "jetmesh convert: out of memory\n");
            return EXIT_RESOURCE;
        }
        list[0] = '\0';
        for (size_t k = 0; k < fr.attribute_count; k++) {
            if (k) strcat(list, ",");
            strcat(list, fr.attributes[k].name);
        }
        if (fr.attribute_count == 0) {
            fprintf(stderr, "jetmesh convert: --attributes all: %s has no per-particle arrays besides the "
                            "positions (and ids)\n", frames->items[i].path);
            free(list);
            jmf_frame_free(&fr);
            return EXIT_SOME_FAILED;
        }
        jmf_frame_free(&fr);
        *out = list;
        return EXIT_ALL_OK;
    }
    return EXIT_ALL_OK; /* no frame reads: each fails in its turn */
}

void vattrs_free(jmf_attribute *a, size_t n)
{
    for (size_t i = 0; a && i < n; i++) {
        free(a[i].name);
        free(a[i].values);
    }
    free(a);
}

jm_status vattrs_make(jm_context *ctx, const jmf_frame *fr, const jm_mesh *mesh, jmf_attribute **out,
                      size_t *n)
{
    *out = NULL;
    *n = 0;
    if (fr->attribute_count == 0)
        return JM_OK;
    jmf_attribute *va = calloc(fr->attribute_count, sizeof *va);
    jm_attribute *ja = calloc(fr->attribute_count, sizeof *ja);
    jm_status s = va && ja ? JM_OK : JM_E_OUT_OF_MEMORY;
    for (size_t k = 0; !s && k < fr->attribute_count; k++) {
        const jmf_attribute *fa = &fr->attributes[k];
        va[k].name = strdup(fa->name);
        va[k].components = fa->components;
        va[k].values = malloc((mesh->vertex_count ? mesh->vertex_count : 1) * (size_t)fa->components * sizeof(float));
        if (!va[k].name || !va[k].values) {
            s = JM_E_OUT_OF_MEMORY;
            break;
        }
        for (char *c = va[k].name; *c; c++)
            if (!((*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9')))
                *c = '_';
        ja[k].components = fa->components;
        ja[k].particle_values = fa->values;
        ja[k].vertex_values = va[k].values;
    }
    if (!s) {
        jm_particles in = {fr->xyz, fr->count, 0, fr->ids};
        s = jm_context_interpolate(ctx, &in, mesh->positions, mesh->vertex_count, ja, fr->attribute_count);
    }
    free(ja);
    if (s) {
        vattrs_free(va, va ? fr->attribute_count : 0);
        return s;
    }
    *out = va;
    *n = fr->attribute_count;
    return JM_OK;
}

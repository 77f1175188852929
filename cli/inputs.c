/* inputs.c - each frame's input read once where it can be read only once (standard input, pipes, FIFOs), its bytes kept for the run's later reads. */
#include "inputs.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>

int inputs_init(inputs *in, const seq_list *frames, size_t max_bytes)
{
    memset(in, 0, sizeof *in);
    in->frames = frames;
    in->max_bytes = max_bytes;
    in->kept = calloc(frames->count ? frames->count : 1, sizeof *in->kept);
    in->n = in->kept ? frames->count : 0;
    return in->kept ? 0 : -1;
}

int inputs_once(const char *path)
{
    struct stat st;
    if (strcmp(path, "-") == 0)
        return 1;
    return stat(path, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
}

static int same_options(const jmf_read_options *a, const jmf_read_options *b)
{
    return a->format == b->format && a->drop_invalid == b->drop_invalid &&
           (a->attributes == b->attributes ||
            (a->attributes && b->attributes && strcmp(a->attributes, b->attributes) == 0));
}

void inputs_hold(inputs *in, size_t i, const jmf_read_options *opt, jmf_frame *fr, double ms)
{
    inputs_kept *k = &in->kept[i];
    if (k->held)
        jmf_frame_free(&k->frame);
    k->frame = *fr;
    k->held_opt = *opt;
    k->held_ms = ms;
    k->held = 1;
    memset(fr, 0, sizeof *fr);
}

jmf_status inputs_read(inputs *in, size_t i, const jmf_read_options *opt, jmf_frame *out, char *err, size_t errlen,
                       double *ms)
{
    const char *path = in->frames->items[i].path;
    inputs_kept *k = &in->kept[i];
    if (ms)
        *ms = 0;
    if (k->held) {
        k->held = 0;
        if (same_options(opt, &k->held_opt)) {
            *out = k->frame;
            memset(&k->frame, 0, sizeof k->frame);
            if (err && errlen)
                err[0] = '\0';
            if (ms)
                *ms = k->held_ms;
            return JMF_OK;
        }
        jmf_frame_free(&k->frame);
    }
    if (k->state == 0 && inputs_once(path)) {
        jmf_read_options whole = *opt;
        whole.max_bytes = in->max_bytes;
        jmf_status st = jmf_read_input(path, &whole, &k->data, &k->size, err, errlen);
        if (st) {
            k->failed = st;
            k->error = strdup(err);
            k->state = 2;
        } else {
            k->state = 1;
        }
    }
    if (k->state == 2) {
        memset(out, 0, sizeof *out);
        snprintf(err, errlen, "%s", k->error ? k->error : "cannot read");
        return k->failed;
    }
    if (k->state == 1)
        return jmf_read_particles_mem(k->data, k->size, jmf_input_name(path), opt, out, err, errlen);
    return jmf_read_particles(path, opt, out, err, errlen);
}

void inputs_release(inputs *in, size_t i)
{
    if (!in->kept)
        return;
    free(in->kept[i].data);
    free(in->kept[i].error);
    if (in->kept[i].held)
        jmf_frame_free(&in->kept[i].frame);
    in->kept[i].held = 0;
    in->kept[i].data = NULL;
    in->kept[i].error = NULL;
    in->kept[i].size = 0;
    /* state stays: a released once-input is not read again */
}

void inputs_free(inputs *in)
{
    for (size_t i = 0; i < in->n; i++)
        inputs_release(in, i);
    free(in->kept);
    in->kept = NULL;
    in->n = 0;
}

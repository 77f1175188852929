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
    return in->kept ? 0 : -1;
}

int inputs_once(const char *path)
{
    struct stat st;
    if (strcmp(path, "-") == 0)
        return 1;
    return stat(path, &st) == 0 && !S_ISREG(st.st_mode) && !S_ISDIR(st.st_mode);
}

jmf_status inputs_read(inputs *in, size_t i, const jmf_read_options *opt, jmf_frame *out, char *err, size_t errlen)
{
    const char *path = in->frames->items[i].path;
    inputs_kept *k = &in->kept[i];
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
    in->kept[i].data = NULL;
    in->kept[i].error = NULL;
    in->kept[i].size = 0;
    /* state stays: a released once-input is not read again */
}

void inputs_free(inputs *in)
{
    for (size_t i = 0; in->kept && i < in->frames->count; i++)
        inputs_release(in, i);
    free(in->kept);
    in->kept = NULL;
}

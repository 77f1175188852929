/* inputs.h - each frame's input read once where it can be read only once (standard input, pipes, FIFOs), its bytes kept for the run's later reads. */
#ifndef JETMESH_CLI_INPUTS_H
#define JETMESH_CLI_INPUTS_H

#include <stddef.h>

#include "../formats/reader.h"
#include "sequence.h"

/*
 * A run reads the first frame more than once (the field choice, the
 * --attributes all list, the conversion) and may read a frame again alone
 * when it was over its share of --max-memory. A regular file is simply
 * opened again; standard input ("-"), a pipe, a FIFO or a device would give
 * nothing (or block) the second time, so its bytes are read once, at its
 * first read, and kept until the frame has been reported (issue 30).
 * Every frame's reads go through inputs_read; one thread at a time per
 * frame (the farm hands a frame to one worker).
 */
typedef struct inputs_kept {
    void *data;          /* the bytes, once read */
    size_t size;
    int state;           /* 0 not read (or a regular file), 1 kept, 2 failed */
    jmf_status failed;   /* state 2: the read's status and message */
    char *error;
    int held;            /* frame: the particles read by inputs_hold's caller */
    jmf_frame frame;
    jmf_read_options held_opt;
    double held_ms;
} inputs_kept;

typedef struct inputs {
    const seq_list *frames;
    inputs_kept *kept;   /* one per frame of frames */
    size_t n;            /* how many */
    size_t max_bytes;    /* the run's whole --max-memory: a kept input is read
                            against it, never against a worker's share */
} inputs;

/** 0, or -1 when out of memory. */
int inputs_init(inputs *in, const seq_list *frames, size_t max_bytes);
/** 1 if path can be read only once: "-", or not a regular file (a FIFO,
 *  a character device, a socket). */
int inputs_once(const char *path);
/** Reads frame i (of in->frames) as jmf_read_particles does; *ms (may be
 *  NULL) gets the milliseconds a held frame's read took, else 0. */
jmf_status inputs_read(inputs *in, size_t i, const jmf_read_options *opt, jmf_frame *out, char *err, size_t errlen,
                       double *ms);
/** Keeps the particles of frame i, read with opt in ms milliseconds, for its
 *  next inputs_read with the same options (format, drop_invalid, the same
 *  attributes): the field choice's read of the first frame is not done
 *  again for its conversion. Takes *fr (zeroed). */
void inputs_hold(inputs *in, size_t i, const jmf_read_options *opt, jmf_frame *fr, double ms);
/** Frame i will not be read again: its kept bytes go. */
void inputs_release(inputs *in, size_t i);
void inputs_free(inputs *in);

#endif

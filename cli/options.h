/* options.h - command-line parsing of `jetmesh convert` and `jetmesh generate`, and their --help texts. */
#ifndef JETMESH_CLI_OPTIONS_H
#define JETMESH_CLI_OPTIONS_H

#include <stddef.h>
#include <stdint.h>
#include <stdio.h>

#include "../formats/reader.h"
#include "../formats/writer.h"
#include "../lib/jetmesh.h"
#include "option_common.h"
#include "sequence.h"
#include "shard.h"

/* What a parse function returns. */
#define OPTIONS_RUN 0   /* go on */
#define OPTIONS_DONE -1 /* --help or --version was printed: exit 0 */

typedef struct convert_options {
    jm_params params;        /* radius, cube size, field, ... (0 = default) */
    jmf_read_options read;   /* input format, drop_invalid, max_bytes */
    jmf_write_options write; /* output format, draco, embed, z_up, bits */
    int format_given;        /* --format was given */
    char **inputs;           /* the operands (into argv) */
    size_t ninputs;
    const char *output;      /* -o */
    seq_range frames;        /* --frames */
    const char *stats_path;  /* --stats FILE.csv|FILE.json */
    const char *stats_svg;   /* --stats-svg FILE.svg */
    int keep_going, resume, quiet, verbose;
    int threshold_given;
    size_t max_memory;       /* bytes; 0 = no limit */
    int frame_jobs;          /* --frame-jobs: frames at once; 0 = auto */
    int field_auto;          /* --field auto (the default): chosen from the
                                first frame by jm_choose_field */
    shard_spec shard;        /* --shard I/N: this process's share (count 0: all) */
    /* sequences for Blender, ParaView and the web (vertex_attrs.c, pvd.c,
       formats/gltf/gltf_anim.h) */
    const char *attributes;  /* --attributes LIST|all: per-particle arrays
                                carried onto the vertices; NULL none */
    char *attributes_all;    /* "all" resolved from the first frame (owned) */
    int animate;             /* --animate: every frame into the one -o file */
    double fps;              /* --fps (default 24) */
    double time_step;        /* --time-step: .pvd time per frame number;
                                0 = 1 / fps */
    int pvd;                 /* --pvd: a .pvd beside a VTK/PLY sequence */
} convert_options;

/* The most frames converted at once (each may hold two finished outputs
 * waiting for their turn: see convert.c). */
#define CONVERT_MAX_FRAME_JOBS 16

typedef struct generate_options {
    const char *scene;  /* "jet", "block" or "spray" */
    size_t count;       /* N of block and spray */
    double radius;      /* -r, default 0.025 */
    uint64_t seed;      /* --seed, default 1 */
    seq_range frames;   /* --frames */
    const char *output; /* -o */
    int quiet;
} generate_options;

/** Parses argv (argv[0] = "convert"). Fills o and returns OPTIONS_*. */
int options_parse_convert(int argc, char **argv, convert_options *o);

/** Parses argv (argv[0] = "generate"). */
int options_parse_generate(int argc, char **argv, generate_options *o);

void options_convert_help(FILE *f);
void options_generate_help(FILE *f);


/** The default --max-memory: half the physical memory (0 if unknown). */
size_t options_default_max_memory(void);


#endif

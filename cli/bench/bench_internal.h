/* bench_internal.h - the records shared by the files of `jetmesh bench`: inputs, options, cases and their stages. */
#ifndef JETMESH_CLI_BENCH_INTERNAL_H
#define JETMESH_CLI_BENCH_INTERNAL_H

#include <stddef.h>
#include <stdint.h>

#include "../../formats/reader.h"
#include "../../lib/jetmesh.h"
#include "../names.h"
#include "bench_stats.h"

#define BENCH_MAX_LIST 16 /* values of one list option (--cube-size, --threads) */

/* ------------------------------------------------------------------ */
/* Inputs: a synthetic scene or a file, loaded into memory once.       */

typedef enum { IN_JET, IN_BLOCK, IN_SPRAY, IN_FILE } input_kind;

typedef struct bench_input {
    input_kind kind;
    size_t n;          /* block/spray N */
    int frame;         /* jet frame */
    const char *path;  /* IN_FILE: into argv */
    char name[96];     /* "jet", "block:100000", or the file's base name */
    float *xyz;
    uint32_t *ids;
    size_t count;
    int loaded;        /* 1 loaded, -1 failed */
    char err[300];
} bench_input;

/* ------------------------------------------------------------------ */
/* Stages: what every run is timed by (write: not part of total).      */

enum { ST_TOTAL, ST_PREPARE, ST_FIELD, ST_EXTRACT, ST_ATTR, ST_WALL, ST_WRITE, ST_POST, ST_COUNT };

/* ------------------------------------------------------------------ */
/* Cases: one input x field x method x cube size x templates x threads. */

typedef struct bench_case {
    size_t input;
    jm_field field;
    jm_method method;
    double cube;
    int threads;      /* asked for */
    int templates;    /* 1 on, 0 off (no_templates) */
    jm_params params; /* in force, defaults filled in */
    int ran, ok;
    char err[320];
    size_t reps;
    bench_summary st[ST_COUNT];
    int has_write;
    size_t write_bytes;
    jm_stats last;
    size_t lib_peak, rss_peak;
    int rss_reset;              /* 1: the RSS peak was reset before the case */
    double speedup_threads;     /* vs. the same case with 1 thread; 0 = none */
    double speedup_templates;   /* no_templates median / this median; 0 = none */
    int flicker_frames;         /* --flicker: frames measured (0: none) */
    double flicker_p99, flicker_max; /* their distances from translated copies, in r */
} bench_case;

/* ------------------------------------------------------------------ */
/* Options.                                                            */

typedef enum { TPL_AUTO, TPL_ON, TPL_OFF, TPL_BOTH } tpl_mode;

/* --field sph-aniso (names.h) */
#define BENCH_FIELD_SPH_ANISO CLI_FIELD_SPH_ANISO

typedef struct bench_opts {
    bench_input inputs[64];
    size_t ninputs;
    jm_field fields[3]; /* JM_FIELD_* or BENCH_FIELD_SPH_ANISO */
    size_t nfields;
    jm_method methods[2];
    size_t nmethods;
    double cubes[BENCH_MAX_LIST];
    size_t ncubes;
    int threads[BENCH_MAX_LIST];
    size_t nthreads;
    double radius;      /* -r: scenes are generated with it */
    jm_params params;   /* the other meshing options (mesh_options.h) and the
                           selection options (select_options.h); the lists
                           above and the templates are set per case */
    int flicker;        /* --flicker K: frames of the flicker figure; 0 off */
    double min_time;
    long repeat, warmup, max_repeat;
    tpl_mode templates;
    int write_format; /* -1: no --write */
    int write_draco;
    char write_ext[16];
    const char *write_dir;
    int json;
    const char *json_out;
    uint64_t seed;
    jmf_read_options read;
    int quiet;
} bench_opts;

#endif

/* sequence.h - frame sequences: input patterns ({} and %04d), --frames ranges and output path templating. */
#ifndef JETMESH_CLI_SEQUENCE_H
#define JETMESH_CLI_SEQUENCE_H

#include <stddef.h>

/*
 * Rules (documented in man/jetmesh.1):
 *
 *   frame_{}.vtk    matches the existing files whose {} part is one or more
 *                   digits; the index is that number; sorted by index
 *                   (natural order: frame_2 before frame_10).
 *   frame_%04d.vtk  printf style (%d, %Nd, %0Nd): with --frames, names
 *                   exactly the frames of the range (a missing one is an
 *                   error when it is read); without, the existing files
 *                   whose name the pattern prints back exactly.
 *   a plain path    the index is the number after "frame" in its name
 *                   (any case, one optional _ - . or space between:
 *                   frame_26_4732_particles.vtk is 26), else the last run
 *                   of digits of its name without extension (fluid_0026.bgeo
 *                   is 26), else its position (from 0) among the inputs on
 *                   the command line.
 *   --frames START:END[:STEP]  END is inclusive; "N" alone is N:N. It
 *                   selects indices from every input.
 * Frames keep the order of the inputs on the command line; the frames of
 * one pattern are in index order.
 *
 * Outputs: {} is replaced by the frame number as written in the input's
 * name (padding kept: jet_007.csv -> out_007.glb), or by the plain index
 * when the name has no number; %0Nd by the index printed that way. A
 * directory output gets DIR/<input name without extension>.<ext>.
 */

/* The most frames one run may plan (about 600 bytes each while it runs):
 * a printf pattern with --frames may name no more, nor may all inputs
 * together. Longer simulations are split with --frames ranges or --shard. */
#define SEQ_MAX_FRAMES 1000000

typedef struct seq_range {
    long start, end, step; /* end inclusive, step >= 1 */
    int set;               /* 0: no range given: every frame */
} seq_range;

typedef struct seq_frame {
    char *path;   /* input file */
    long index;   /* frame number */
    char *digits; /* the number as written in the file name ("007"), or NULL */
} seq_frame;

typedef struct seq_list {
    seq_frame *items;
    size_t count, cap;
} seq_list;

typedef enum seq_kind {
    SEQ_PLAIN = 0, /* no placeholder */
    SEQ_BRACES,    /* one {} */
    SEQ_PRINTF,    /* one %d, %Nd or %0Nd (and %% for a literal %) */
    SEQ_INVALID    /* more than one placeholder */
} seq_kind;

/** Parses "START:END[:STEP]" or "N". 0 on success; -1 with a message. */
int seq_range_parse(const char *text, seq_range *out, char *err, size_t errlen);

/** 1 if the range selects index (always 1 for an unset range). */
int seq_range_contains(const seq_range *r, long index);

/** What kind of pattern s is. */
seq_kind seq_kind_of(const char *s);

/** Compares two strings with runs of digits compared by value. */
int seq_natural_cmp(const char *a, const char *b);

/** The number in a plain file name (without directory and extension): the
 *  digits after "frame", else the last run of digits. 1 if found (*index,
 *  *digits malloc'd). */
int seq_number_in_name(const char *path, long *index, char **digits);

/**
 * Expands the inputs into frames (appended to out), as described above.
 * 0 on success; -1 with a message (no match, bad pattern, out of memory).
 */
int seq_expand(char *const *inputs, size_t n, const seq_range *range,
               seq_list *out, char *err, size_t errlen);

/** Appends one frame (copies the strings). 0 or -1 (out of memory). */
int seq_list_add(seq_list *l, const char *path, long index, const char *digits);

/** Frees the frames and zeroes the list. */
void seq_list_free(seq_list *l);

/** 1 if s contains a {} or printf placeholder (one output per frame). */
int seq_is_template(const char *s);

/** Replaces the placeholder of tmpl for one frame; malloc'd, NULL if no memory. */
char *seq_substitute(const char *tmpl, long index, const char *digits);

/** The name of path without directory and without its last extension
 *  (and without ".gz" first): "a/b/frame_1.csv.gz" -> "frame_1". malloc'd. */
char *seq_stem(const char *path);

/** DIR/<stem of input>.<ext>; malloc'd. */
char *seq_in_directory(const char *dir, const char *input, const char *ext);

#endif

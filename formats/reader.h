/* reader.h - reads one particle frame from a file or memory: CSV, XYZ, VTK, VTU, BGEO, PLY, gzip or not. */
#ifndef JETMESH_FORMATS_READER_H
#define JETMESH_FORMATS_READER_H

#include <stddef.h>
#include <stdint.h>

#ifdef __cplusplus
extern "C" {
#endif

/** Results of the format layer (readers and writers). 0 is success. */
typedef enum jmf_status {
    JMF_OK = 0,
    JMF_E_IO,          /**< missing path, a directory, read/write error, disk full */
    JMF_E_FORMAT,      /**< malformed or truncated content, wrong magic, NaN */
    JMF_E_UNSUPPORTED, /**< a valid file of a kind or variant we do not read */
    JMF_E_NOMEM,       /**< allocation failed or a size overflowed */
    JMF_E_LIMIT        /**< over a size limit given in the options */
} jmf_status;

typedef enum jmf_input_format {
    JMF_IN_AUTO = 0, /**< magic first (gzip is unwrapped), then extension */
    JMF_IN_CSV,
    JMF_IN_XYZ,      /**< raw little-endian float32 x,y,z triples */
    JMF_IN_VTK,      /**< legacy VTK, ASCII or binary, 4.x and 5.1 */
    JMF_IN_VTU,      /**< VTK XML unstructured grid */
    JMF_IN_BGEO,     /**< Houdini BgeoV 5 as partio/SPlisHSPlasH write it */
    JMF_IN_PLY       /**< PLY ASCII / binary LE / binary BE, vertex x y z */
} jmf_input_format;

typedef struct jmf_read_options {
    jmf_input_format format; /**< JMF_IN_AUTO by default */
    int drop_invalid;        /**< 1: skip particles with NaN/inf coordinates and
                                  count them in jmf_frame.dropped; 0: error */
    size_t max_bytes;        /**< refuse inputs whose decoded size exceeds this;
                                  0 = no limit */
    const char *attributes;  /**< per-particle arrays to read besides the
                                  positions: NULL none (the default), "all",
                                  or names separated by commas ("velocity,
                                  density"; case-insensitive). See
                                  jmf_attribute. */
} jmf_read_options;

/** The most components, all the attributes of a frame together, that a
 *  read keeps (what jm_interpolate_attributes carries in one call): an
 *  attribute beyond them is refused (JMF_E_UNSUPPORTED) where the file
 *  declares it, before any value is read. */
#define JMF_MAX_ATTRIBUTE_COMPONENTS 64

/**
 * One per-particle array of a frame (jmf_read_options.attributes), e.g.
 * "velocity" with 3 components. Where they come from: VTK point-data
 * SCALARS/VECTORS/NORMALS and FIELD arrays, VTU PointData DataArrays, BGEO
 * point attributes (float/int/vector), PLY vertex properties and CSV columns.
 * In PLY and CSV, properties NAME_x NAME_y NAME_z (also .x or x/y/z after
 * the name) make one 3-component NAME, and vx vy vz make "velocity". 1 to 4
 * components each, at most JMF_MAX_ATTRIBUTE_COMPONENTS in all. A named
 * attribute the file lacks, one whose length differs
 * from the particle count, and a non-finite value are errors naming the
 * file and the attribute (drop_invalid drops the particle instead of the
 * last).
 */
typedef struct jmf_attribute {
    char *name;
    int components;          /**< 1 to 4 */
    float *values;           /**< components per particle, particle order */
} jmf_attribute;

/** One frame of particles, owned by the caller: free with jmf_frame_free(). */
typedef struct jmf_frame {
    float *xyz;          /**< 3 floats per particle */
    uint32_t *ids;       /**< particle ids when the file has them, else NULL */
    size_t count;
    size_t dropped;      /**< invalid particles skipped with drop_invalid */
    jmf_input_format format; /**< the format actually read */
    int compressed;      /**< 1 if the file was gzip-compressed */
    jmf_attribute *attributes; /**< read_options.attributes found, in file order */
    size_t attribute_count;
    char *array_names;   /**< with attributes asked for: every per-particle
                              array the file has, ", "-separated (for
                              messages); else NULL */
} jmf_frame;

/**
 * Reads the particles of one frame from path ("-": standard input, whose
 * format comes from its magic or opt->format). On failure returns non-zero,
 * leaves *out zeroed and writes a one-line message into err (if errlen > 0)
 * that names the file and the line (text) or byte offset (binary) and what
 * was expected, e.g. "a.csv:12: expected 3 numbers, found 2".
 */
jmf_status jmf_read_particles(const char *path, const jmf_read_options *opt,
                              jmf_frame *out, char *err, size_t errlen);

/** The name messages give standard input, path "-". */
#define JMF_STDIN_NAME "<stdin>"

/**
 * The first half of jmf_read_particles: the whole input at path (standard
 * input for "-"; a FIFO or device is read to its end) into a malloc'd
 * buffer *out of *out_size bytes, at most opt->max_bytes (or the built-in
 * cap) of them. For inputs that can be read only once (pipes), whose bytes
 * a caller keeps for later parses with jmf_read_particles_mem. Errors as
 * jmf_read_particles; *out is NULL then.
 */
jmf_status jmf_read_input(const char *path, const jmf_read_options *opt, void **out, size_t *out_size, char *err,
                          size_t errlen);

/** The name jmf_read_particles gives path in messages: JMF_STDIN_NAME for
 *  "-", else path. */
const char *jmf_input_name(const char *path);

/** Same, from memory (name is only used in messages and for the extension). */
jmf_status jmf_read_particles_mem(const void *data, size_t size, const char *name,
                                  const jmf_read_options *opt, jmf_frame *out,
                                  char *err, size_t errlen);

/** Frees the arrays of a frame and zeroes it. NULL is allowed. */
void jmf_frame_free(jmf_frame *frame);

/** "csv", "xyz", ... ; "auto" for JMF_IN_AUTO. */
const char *jmf_input_format_name(jmf_input_format f);
/** Parses a name as given to --input-format; returns -1 if unknown. */
int jmf_input_format_parse(const char *name);

#ifdef __cplusplus
}
#endif
#endif

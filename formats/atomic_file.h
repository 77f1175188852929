/* atomic_file.h - writes a file through a temporary beside it, renamed into place only when complete. */
#ifndef JETMESH_FORMATS_ATOMIC_FILE_H
#define JETMESH_FORMATS_ATOMIC_FILE_H

#include <stdio.h>
#include <stddef.h>
#include "reader.h" /* jmf_status */

#ifdef __cplusplus
extern "C" {
#endif

/** An output being written. The temporary is
 *  "DIR/.STEM.jetmesh-tmp-HOST-PID-RAND" (see jmf_atomic_temp_parse), STEM
 *  the output's name or, past JMF_TEMP_STEM_MAX bytes, a short form of it
 *  (jmf_atomic_temp_stem). */
typedef struct jmf_atomic_file {
    FILE *fp;          /**< write to this */
    char *final_path;
    char *temp_path;
    size_t bytes;      /**< bytes written, set by jmf_atomic_commit */
    int no_sync;       /**< 1: skip the fsync before the rename (set after
                            jmf_atomic_open; a killed process still never
                            leaves a partial file, a power loss might) */
    int finished;      /**< set by jmf_atomic_finish */
} jmf_atomic_file;

/** Creates the temporary for path (refuses a path that is a directory).
 *  Creating and registering it for jmf_atomic_shutdown() is one step; after
 *  a shutdown it fails ("stopping on a signal"). */
jmf_status jmf_atomic_open(jmf_atomic_file *af, const char *path, char *err, size_t errlen);

/** Flushes, fsyncs, closes and renames the temporary over the final path.
 *  The data reaches the disk before the rename, so even after a power loss
 *  the final path holds either the old file or the complete new one; the
 *  directory itself is not synced (the rename may be the part that is lost).
 *  On any failure (e.g. disk full) the temporary is removed and the final
 *  path is left as it was. */
jmf_status jmf_atomic_commit(jmf_atomic_file *af, char *err, size_t errlen);

/** The two halves of jmf_atomic_commit, for an output that is complete
 *  before it may appear (frames converted ahead of their turn): finish
 *  flushes the data to the kernel and sets bytes, keeping the file open
 *  and the temporary in place (still removed by jmf_atomic_remove_pending);
 *  publish fsyncs (unless no_sync), closes and renames it into place, so
 *  the wait for the disk can happen on another thread. After a finish,
 *  either publish or abort. On failure each removes the temporary and
 *  releases af. */
jmf_status jmf_atomic_finish(jmf_atomic_file *af, char *err, size_t errlen);
jmf_status jmf_atomic_publish(jmf_atomic_file *af, char *err, size_t errlen);

/** Publishes n finished files as one: all are synced and closed, then all
 *  are renamed in order under the lock that jmf_atomic_shutdown() takes,
 *  so a signal sees every rename of the group or none (a .gltf and its
 *  .bin). On failure, those not yet renamed are removed; all are released. */
jmf_status jmf_atomic_publish_all(jmf_atomic_file *afs, int n, char *err, size_t errlen);

/** Writes n bytes to the temporary. On a short write (disk full, file too
 *  large, I/O error) returns JMF_E_IO with one line naming the final path
 *  and the cause; the caller then calls jmf_atomic_abort(). */
jmf_status jmf_atomic_write(jmf_atomic_file *af, const void *data, size_t n,
                            char *err, size_t errlen);

/** Closes and removes the temporary; the final path is untouched. */
void jmf_atomic_abort(jmf_atomic_file *af);

/** The longest STEM of a temporary's name: with the rest (at most 98
 *  bytes) it stays within the 255 bytes file systems allow a name. */
#define JMF_TEMP_STEM_MAX 120

/** The STEM of the temporaries of an output named name (no directory):
 *  the name itself up to JMF_TEMP_STEM_MAX bytes, else its first 100 bytes
 *  (whole UTF-8 characters), '~' and 16 hex digits of a 64-bit hash of the
 *  whole name. out has room for JMF_TEMP_STEM_MAX + 1 bytes; returns the
 *  length. */
size_t jmf_atomic_temp_stem(const char *name, char *out);

/** A temporary's name, parsed. */
typedef struct jmf_temp_name {
    size_t name_len;  /**< STEM (or NAME) is the name_len bytes after the leading '.' */
    long pid;         /**< the process that wrote it */
    const char *host; /**< HOST, host_len bytes into the parsed name; NULL
                           for the form before 0.4, ".NAME.jetmesh-tmp-PID",
                           which carried no host */
    size_t host_len;
} jmf_temp_name;

/** 1 if name (a directory entry) is a temporary of this writer,
 *  ".STEM.jetmesh-tmp-HOST-PID-RAND" (or the older ".NAME.jetmesh-tmp-PID"),
 *  filling *out; 0 otherwise. */
int jmf_atomic_temp_parse(const char *name, jmf_temp_name *out);

/** This machine's name as it appears in temporaries' names. */
const char *jmf_atomic_host(void);

/** Stops all output for good: under the writer's lock, no temporary can be
 *  created or renamed into place after it, and every temporary still on
 *  disk is unlinked. For the thread that takes SIGINT/SIGTERM/... before
 *  the process dies (cli/signals.c); not async-signal-safe. */
void jmf_atomic_shutdown(void);

#ifdef __cplusplus
}
#endif
#endif

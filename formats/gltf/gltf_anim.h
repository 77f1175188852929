/* gltf_anim.h - writes a whole sequence into one animated glTF/GLB, frame by frame: one node per frame, shown at its time by a STEP scale animation. */
#ifndef JETMESH_FORMATS_GLTF_ANIM_H
#define JETMESH_FORMATS_GLTF_ANIM_H

#include <stddef.h>
#include "../writer.h"
#include "gltf_wrap.h"

#ifdef __cplusplus
extern "C" {
#endif

/*
 * The file: one scene whose nodes are the frames, in order, each with its
 * own mesh (Draco-compressed with draco); node k (0-based position in the
 * sequence) has a "scale" animation channel with STEP interpolation: scale 0
 * from t = 0, 1 at t = k / fps, 0 at t = (k + 1) / fps (at most 3 keys), so
 * exactly one frame shows at a time in any player (Blender's importer makes
 * one object per frame, each visible at its frame). asset.extras holds
 * {"jetmesh_sequence": {"fps": F, "frames": N, "frame_numbers": [...]}}.
 * Why scale keys: glTF animates no visibility but through KHR_node_visibility
 * (with KHR_animation_pointer), which Blender 3.4's importer ignores (every
 * frame would show at once); Cycles aborts on a 0<->1 scale inside its
 * shutter, so Blender streams the frames instead (jetmesh_blender.py reads
 * them from this file itself, by frame_numbers).
 *
 * Streaming: each frame's bytes go to a temporary beside the output as the
 * frame is added (a .gltf: its .bin itself; a .glb: the atomic writer's
 * temporary of NAME.glb.frames, never renamed into place), only the JSON (a few hundred
 * bytes per frame) stays in memory; the .glb is assembled from the
 * temporary at the end. Every file goes through the atomic writer.
 */

/** One frame's glTF primitive, built in memory ahead of its turn. */
typedef struct jmf_anim_piece jmf_anim_piece;

/** Builds a frame's piece from mesh, with opt's attributes, z_up and Draco
 *  settings (draco: compress). Thread-safe. A mesh without triangles gives
 *  an empty piece (a node without a mesh). */
jmf_status jmf_anim_piece_build(const jm_mesh *mesh, const jmf_write_options *opt, int draco, const char *name,
                                jmf_anim_piece **out, char *err, size_t errlen);
/** The bytes a piece holds. */
size_t jmf_anim_piece_bytes(const jmf_anim_piece *p);
void jmf_anim_piece_free(jmf_anim_piece *p);

typedef struct jmf_anim jmf_anim;

/* The largest file jmf_anim writes: 2 GiB. The Khronos glTF-Validator (and
 * other tools with 32-bit signed sizes) refuse larger files, and GLB's
 * 32-bit lengths end at 4 GiB; a longer run is one file per frame. */
#define JMF_ANIM_MAX_BYTES ((size_t)2 << 30)

/** The glTF builder's parameters jmf_write_mesh would use for mesh (writer.c). */
void jmf_write_gltf_params(const jmf_write_options *opt, const jm_mesh *mesh, int draco, const char *name,
                           jmf_gltf_params *p);

/** Starts the file path (.glb: binary; else .gltf with a .bin beside it)
 *  for frames shown fps per second. */
jmf_status jmf_anim_open(const char *path, int glb, const jmf_write_options *opt, double fps, jmf_anim **out,
                         char *err, size_t errlen);
/** Sets the largest file a may write, in bytes (0: JMF_ANIM_MAX_BYTES). For
 *  tests only (the CLI's JETMESH_TEST_ANIMATE_LIMIT): the refusal without
 *  writing 2 GiB. */
void jmf_anim_set_limit(jmf_anim *a, size_t bytes);
/** The size the file would have if finished now (its frames' bytes, the JSON
 *  as estimated, GLB's framing): what the limit is checked against. */
size_t jmf_anim_bytes(const jmf_anim *a);
/** Adds the next frame as node node_name with frame number number; piece
 *  NULL: a frame that failed (an empty node keeps the others' times). Takes
 *  the piece (freed here). JMF_E_LIMIT, adding nothing, when the file would
 *  pass the limit (the message says why and what to write instead). */
jmf_status jmf_anim_add(jmf_anim *a, const char *node_name, long number, jmf_anim_piece *piece, char *err,
                        size_t errlen);
/** Writes the JSON and assembles the file, staged (jmf_staged_publish
 *  renames it into place); frees a. out_bytes: the bytes of all files.
 *  JMF_E_LIMIT when the finished file would pass the limit. */
jmf_status jmf_anim_finish(jmf_anim *a, jmf_staged *out, size_t *out_bytes, char *err, size_t errlen);
/** Removes every temporary and frees a. NULL is allowed. */
void jmf_anim_abort(jmf_anim *a);

#ifdef __cplusplus
}
#endif
#endif

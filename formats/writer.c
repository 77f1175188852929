/* writer.c - jmf_write_mesh: picks the output format from the options or the file name and writes it atomically. */
#include "writer.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "atomic_file.h"
#include "draco_wrap.h"
#include "draco_bits.h"
#include "gltf/gltf_wrap.h"
#include "gltf/gltf_anim.h"
#include "write/write_formats.h"

static const char *const k_names[] = {"auto", "obj", "gltf", "glb", "drc", "ply", "vtk"};
#define N_FORMATS ((int)(sizeof k_names / sizeof k_names[0]))

const char *jmf_output_format_name(jmf_output_format f)
{
    return (int)f >= 0 && (int)f < N_FORMATS ? k_names[f] : "unknown";
}

int jmf_output_format_parse(const char *name)
{
    if (!name) return -1;
    for (int i = 0; i < N_FORMATS; i++)
        if (strcasecmp(name, k_names[i]) == 0) return i;
    return -1;
}

static int ends_with(const char *s, const char *suffix)
{
    size_t n = strlen(s), k = strlen(suffix);
    return n >= k && strcasecmp(s + n - k, suffix) == 0;
}

int jmf_output_format_for(const char *path, const jmf_write_options *opt, int *out_draco)
{
    int draco = opt ? opt->draco != 0 : 0;
    int f = -1;
    if (path && (ends_with(path, ".draco.glb") || ends_with(path, ".draco.gltf"))) draco = 1;
    if (opt && opt->format != JMF_OUT_AUTO) {
        f = (int)opt->format > 0 && (int)opt->format < N_FORMATS ? (int)opt->format : -1;
    } else if (path) {
        const char *dot = strrchr(path, '.');
        const char *slash = strrchr(path, '/');
        if (dot && (!slash || dot > slash)) {
            int g = jmf_output_format_parse(dot + 1);
            f = g > 0 ? g : -1;
        }
    }
    /* Only glTF and GLB have a Draco variant; a .drc is Draco by itself. */
    if (out_draco) *out_draco = (f == JMF_OUT_GLTF || f == JMF_OUT_GLB) ? draco : 0;
    return f;
}

static const char *default_generator(const jmf_write_options *opt)
{
    return opt && opt->generator ? opt->generator : "jetmesh " JM_VERSION_STRING;
}

/* Commits af, or with a stage, finishes it and hands it to the stage to be
 * published later; adds its bytes. */
static jmf_status commit_or_stage(jmf_atomic_file *af, jmf_staged *stage, size_t *bytes, char *err, size_t errlen)
{
    jmf_status st = stage ? jmf_atomic_finish(af, err, errlen) : jmf_atomic_commit(af, err, errlen);
    if (st) return st;
    *bytes += af->bytes;
    if (stage) stage->files[stage->count++] = *af;
    return JMF_OK;
}

/* Writes the whole of data to path, atomically. */
static jmf_status write_bytes(const char *path, const void *data, size_t n, int no_sync, size_t *bytes,
                              jmf_staged *stage, char *err, size_t errlen)
{
    jmf_atomic_file af;
    jmf_status st = jmf_atomic_open(&af, path, err, errlen);
    if (st) return st;
    af.no_sync = no_sync;
    st = jmf_atomic_write(&af, data, n, err, errlen);
    if (st) {
        jmf_atomic_abort(&af);
        return st;
    }
    return commit_or_stage(&af, stage, bytes, err, errlen);
}

typedef jmf_status (*c_writer)(jmf_atomic_file *, const jm_mesh *, const jmf_attribute *, size_t, const char *,
                                char *, size_t);

static jmf_status write_obj_na(jmf_atomic_file *af, const jm_mesh *mesh, const jmf_attribute *attrs, size_t nattrs,
                               const char *generator, char *err, size_t errlen)
{
    (void)attrs;
    (void)nattrs;
    return jmf_write_obj(af, mesh, generator, err, errlen);
}

static jmf_status write_c_format(const char *path, const jm_mesh *mesh, c_writer fn,
                                 const jmf_write_options *opt, size_t *bytes,
                                 jmf_staged *stage, char *err, size_t errlen)
{
    /* The text formats carry the generator on one header line: keep it to
     * one line of reasonable length. */
    char gen[200];
    snprintf(gen, sizeof gen, "%s", default_generator(opt));
    for (char *c = gen; *c; c++)
        if ((unsigned char)*c < 0x20) *c = ' ';
    jmf_atomic_file af;
    jmf_status st = jmf_atomic_open(&af, path, err, errlen);
    if (st) return st;
    af.no_sync = opt && opt->no_sync;
    st = fn(&af, mesh, opt ? opt->attributes : NULL, opt ? opt->attribute_count : 0, gen, err, errlen);
    if (st) {
        jmf_atomic_abort(&af);
        return st;
    }
    return commit_or_stage(&af, stage, bytes, err, errlen);
}

static jmf_draco_params draco_params(const jmf_write_options *opt, const jm_mesh *mesh)
{
    jmf_draco_params p;
    jmf_draco_params_default(&p);
    /* default: the fewest bits from 16 at which no sliver triangle collapses */
    if (mesh && mesh->triangle_count && !(opt && opt->draco_position_bits > 0))
        p.position_bits = jmf_draco_auto_position_bits(mesh, NULL);
    if (opt) {
        if (opt->draco_position_bits > 0) p.position_bits = opt->draco_position_bits;
        if (opt->draco_normal_bits > 0) p.normal_bits = opt->draco_normal_bits;
        if (opt->draco_uv_bits > 0) p.uv_bits = opt->draco_uv_bits;
        if (opt->draco_speed > 0) p.speed = opt->draco_speed;
    }
    return p;
}

void jmf_write_gltf_params(const jmf_write_options *opt, const jm_mesh *mesh, int draco, const char *name,
                           jmf_gltf_params *p)
{
    memset(p, 0, sizeof *p);
    p->container = JMF_GLTF_BINARY;
    p->generator = default_generator(opt);
    p->z_up = opt ? opt->z_up : 0;
    p->draco = draco;
    p->draco_params = draco_params(opt, draco ? mesh : NULL);
    p->name = name;
    p->attributes = opt ? opt->attributes : NULL;
    p->attribute_count = opt ? opt->attribute_count : 0;
}

static jmf_status write_drc(const char *path, const jm_mesh *mesh, const jmf_write_options *opt,
                            size_t *bytes, jmf_staged *stage, char *err, size_t errlen)
{
    jmf_draco_params p = draco_params(opt, mesh);
    jmf_draco_blob blob;
    jmf_status st = jmf_draco_encode_attributes(mesh, opt ? opt->attributes : NULL, opt ? opt->attribute_count : 0,
                                                &p, path, &blob, err, errlen);
    if (st) return st;
    st = write_bytes(path, blob.data, blob.size, opt && opt->no_sync, bytes, stage, err, errlen);
    jmf_draco_blob_free(&blob);
    return st;
}

/* "dir/x.gltf" -> "dir/x.bin"; any other name gets ".bin" appended. */
static char *bin_path_for(const char *path)
{
    size_t n = strlen(path);
    size_t stem = ends_with(path, ".gltf") ? n - 5 : n;
    char *b = malloc(stem + 5);
    if (!b) return NULL;
    memcpy(b, path, stem);
    memcpy(b + stem, ".bin", 5);
    return b;
}

/* the glTF buffer's pieces, in order */
static jmf_status write_pieces(jmf_atomic_file *af, const jmf_gltf_output *out, char *err, size_t errlen)
{
    jmf_status st = JMF_OK;
    for (size_t i = 0; i < out->bin_pieces && !st; i++)
        st = jmf_atomic_write(af, out->bin[i].data, out->bin[i].size, err, errlen);
    return st;
}

static jmf_status write_gltf(const char *path, const jm_mesh *mesh, int glb, int draco,
                             const jmf_write_options *opt, size_t *bytes,
                             jmf_staged *stage, char *err, size_t errlen)
{
    jmf_gltf_params p;
    memset(&p, 0, sizeof p);
    p.container = glb ? JMF_GLTF_BINARY : opt && opt->embed ? JMF_GLTF_EMBEDDED : JMF_GLTF_SEPARATE;
    p.generator = default_generator(opt);
    p.z_up = opt ? opt->z_up : 0;
    p.draco = draco;
    p.draco_params = draco_params(opt, draco ? mesh : NULL);
    p.name = path;
    p.attributes = opt ? opt->attributes : NULL;
    p.attribute_count = opt ? opt->attribute_count : 0;
    char *bin_path = NULL;
    if (p.container == JMF_GLTF_SEPARATE) {
        bin_path = bin_path_for(path);
        if (!bin_path) {
            snprintf(err, errlen, "%s: out of memory", path);
            return JMF_E_NOMEM;
        }
        const char *slash = strrchr(bin_path, '/');
        p.bin_uri = slash ? slash + 1 : bin_path;
    }
    jmf_gltf_output out;
    jmf_status st = jmf_gltf_build(mesh, &p, &out, err, errlen);
    if (st) {
        free(bin_path);
        return st;
    }
    if (p.container == JMF_GLTF_BINARY) {
        static const unsigned char zeros[4];
        jmf_atomic_file af;
        st = jmf_atomic_open(&af, path, err, errlen);
        if (!st) af.no_sync = opt && opt->no_sync;
        if (!st) st = jmf_atomic_write(&af, out.main, out.main_size, err, errlen);
        if (!st) st = write_pieces(&af, &out, err, errlen);
        if (!st) st = jmf_atomic_write(&af, zeros, out.bin_pad, err, errlen);
        if (!st) {
            st = commit_or_stage(&af, stage, bytes, err, errlen);
        } else if (af.fp) {
            jmf_atomic_abort(&af);
        }
    } else if (!bin_path || out.bin_size == 0) {
        st = write_bytes(path, out.main, out.main_size, opt && opt->no_sync, bytes, stage, err, errlen);
    } else {
        /* Both temporaries are complete before either is renamed; the .bin
         * goes first so that the .gltf never names a missing buffer. */
        jmf_atomic_file fb, fg;
        st = jmf_atomic_open(&fb, bin_path, err, errlen);
        if (!st) {
            st = jmf_atomic_open(&fg, path, err, errlen);
            if (st) jmf_atomic_abort(&fb);
        }
        if (!st) fb.no_sync = fg.no_sync = opt && opt->no_sync;
        if (!st) {
            st = write_pieces(&fb, &out, err, errlen);
            if (!st) st = jmf_atomic_write(&fg, out.main, out.main_size, err, errlen);
            if (!st) st = commit_or_stage(&fb, stage, bytes, err, errlen);
            else jmf_atomic_abort(&fb);
            if (!st) {
                st = commit_or_stage(&fg, stage, bytes, err, errlen);
            } else {
                jmf_atomic_abort(&fg);
            }
        }
    }
    jmf_gltf_output_free(&out);
    free(bin_path);
    return st;
}

int jmf_format_holds_attributes(int f, int draco)
{
    (void)draco; /* Draco carries them as GENERIC attributes, in .drc and in glTF */
    return f == JMF_OUT_PLY || f == JMF_OUT_VTK || f == JMF_OUT_GLTF || f == JMF_OUT_GLB || f == JMF_OUT_DRC;
}

jmf_status jmf_check_attributes(const char *path, int f, int draco, const jm_mesh *mesh,
                                const jmf_write_options *opt, char *err, size_t errlen)
{
    if (!jmf_format_holds_attributes(f, draco)) {
        snprintf(err, errlen, "%s: %s cannot hold per-vertex attributes such as '%s': write glTF/GLB (Draco or "
                 "not), .drc, PLY or VTK, or leave out --attributes", path,
                 jmf_output_format_name((jmf_output_format)f), opt->attributes[0].name);
        return JMF_E_UNSUPPORTED;
    }
    for (size_t a = 0; a < opt->attribute_count; a++) {
        const jmf_attribute *at = &opt->attributes[a];
        int ok = at->name && *at->name && at->components >= 1 && at->components <= 4 &&
                 (at->values || !mesh->vertex_count);
        for (const char *c = at->name; ok && *c; c++)
            ok = (*c >= 'a' && *c <= 'z') || (*c >= 'A' && *c <= 'Z') || (*c >= '0' && *c <= '9') || *c == '_';
        if (!ok) {
            snprintf(err, errlen, "%s: attribute %zu ('%s') needs a name of letters, digits and '_', 1 to 4 "
                     "components and values", path, a, at->name ? at->name : "");
            return JMF_E_FORMAT;
        }
    }
    return JMF_OK;
}

static jmf_status write_mesh(const char *path, const jm_mesh *mesh, const jmf_write_options *opt,
                             size_t *out_bytes, jmf_staged *stage, char *err, size_t errlen)
{
    size_t bytes = 0;
    if (out_bytes) *out_bytes = 0;
    if (err && errlen) err[0] = '\0';
    if (!path || !*path) {
        snprintf(err, errlen, "no output path");
        return JMF_E_IO;
    }
    struct stat sb;
    if (path[strlen(path) - 1] == '/' || (stat(path, &sb) == 0 && S_ISDIR(sb.st_mode))) {
        snprintf(err, errlen, "%s: is a directory", path);
        return JMF_E_IO;
    }
    if (!mesh || (mesh->vertex_count && !mesh->positions) ||
        (mesh->triangle_count && !mesh->indices)) {
        snprintf(err, errlen, "%s: no mesh data to write", path);
        return JMF_E_FORMAT;
    }
    for (size_t i = 0; i < 3 * mesh->triangle_count; i++)
        if (mesh->indices[i] >= mesh->vertex_count) {
            snprintf(err, errlen, "%s: triangle %zu uses vertex %u but the mesh has %zu",
                     path, i / 3, (unsigned)mesh->indices[i], mesh->vertex_count);
            return JMF_E_FORMAT;
        }
    int draco = 0;
    int f = jmf_output_format_for(path, opt, &draco);
    if (f < 0) {
        snprintf(err, errlen, "%s: unknown output format (use .obj, .gltf, .glb, .drc, "
                 ".ply or .vtk, or name the format)", path);
        return JMF_E_UNSUPPORTED;
    }
    if (opt && opt->draco && f != JMF_OUT_GLTF && f != JMF_OUT_GLB && f != JMF_OUT_DRC) {
        snprintf(err, errlen, "%s: Draco compression applies to glTF, GLB and .drc only, not %s",
                 path, jmf_output_format_name((jmf_output_format)f));
        return JMF_E_UNSUPPORTED;
    }
    if (opt && opt->attribute_count) {
        jmf_status as = jmf_check_attributes(path, f, draco, mesh, opt, err, errlen);
        if (as) return as;
    }
    jmf_status st;
    switch (f) {
    case JMF_OUT_OBJ: st = write_c_format(path, mesh, write_obj_na, opt, &bytes, stage, err, errlen); break;
    case JMF_OUT_PLY: st = write_c_format(path, mesh, jmf_write_ply_attrs, opt, &bytes, stage, err, errlen); break;
    case JMF_OUT_VTK: st = write_c_format(path, mesh, jmf_write_vtk_attrs, opt, &bytes, stage, err, errlen); break;
    case JMF_OUT_DRC: st = write_drc(path, mesh, opt, &bytes, stage, err, errlen); break;
    case JMF_OUT_GLTF: st = write_gltf(path, mesh, 0, draco, opt, &bytes, stage, err, errlen); break;
    default: st = write_gltf(path, mesh, 1, draco, opt, &bytes, stage, err, errlen); break;
    }
    if (!st && out_bytes) *out_bytes = bytes;
    return st;
}

jmf_status jmf_write_mesh(const char *path, const jm_mesh *mesh, const jmf_write_options *opt, size_t *out_bytes,
                          char *err, size_t errlen)
{
    /* staged, then published as one: a .gltf and its .bin appear together */
    jmf_staged s;
    jmf_status st = jmf_write_mesh_staged(path, mesh, opt, out_bytes, &s, err, errlen);
    return st ? st : jmf_staged_publish(&s, err, errlen);
}

jmf_status jmf_write_mesh_staged(const char *path, const jm_mesh *mesh, const jmf_write_options *opt,
                                 size_t *out_bytes, jmf_staged *out_staged, char *err, size_t errlen)
{
    if (!out_staged) return write_mesh(path, mesh, opt, out_bytes, NULL, err, errlen);
    memset(out_staged, 0, sizeof *out_staged);
    jmf_status st = write_mesh(path, mesh, opt, out_bytes, out_staged, err, errlen);
    if (st) jmf_staged_abort(out_staged);
    return st;
}

jmf_status jmf_staged_publish(jmf_staged *s, char *err, size_t errlen)
{
    jmf_status st = s->count ? jmf_atomic_publish_all(s->files, s->count, err, errlen) : JMF_OK;
    s->count = 0;
    return st;
}

void jmf_staged_abort(jmf_staged *s)
{
    if (!s) return;
    for (int i = 0; i < s->count; i++) jmf_atomic_abort(&s->files[i]);
    s->count = 0;
}

/* convert.c - `jetmesh convert`: plans outputs, then reads, meshes and writes each frame with one context. */
#include "convert.h"

#include <errno.h>
#include <unistd.h>
#include <fcntl.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <strings.h>
#include <sys/stat.h>

#include "../formats/gltf/gltf_anim.h"
#include "../formats/reader.h"
#include "../formats/writer.h"
#include "../lib/jetmesh.h"
#include "domain_advice.h"
#include "farm.h"
#include "inputs.h"
#include "names.h"
#include "options.h"
#include "param_errors.h"
#include "select_options.h"
#include "platform.h"
#include "progress.h"
#include "pvd.h"
#include "sequence.h"
#include "shard.h"
#include "signals.h"
#include "stale.h"
#include "stats/stats.h"
#include "stdout_check.h"
#include "vertex_attrs.h"

/* One frame to convert. */
typedef struct job {
    const seq_frame *in;
    char *out;
} job;

/* What converting one frame gave, kept until its turn to be reported. */
typedef struct outcome {
    stats_record rec;  /* no input/output strings; error owned here */
    jm_stats st;       /* for --verbose */
    jmf_staged staged; /* the finished output, not yet renamed into place */
    int status;        /* exit status of a failure */
    int retry;         /* refused over its share of --max-memory: redo alone */
    int done;          /* converted (by a worker, ahead of its turn) */
    jmf_anim_piece *piece; /* --animate: the frame's glTF piece, for its turn */
} outcome;

typedef struct run {
    convert_options *o;
    seq_list frames;
    job *jobs;
    size_t njobs;
    jm_context *ctx;   /* one frame at a time: all threads, all the memory */
    jm_context **wctx; /* several at once: one per worker */
    int nwctx;
    jmf_read_options wread; /* the workers' share of --max-memory */
    outcome *oc;
    stats_log log;
    progress bar;
    size_t failed;
    int worst; /* exit status so far */
    float neighbours;   /* jm_choose_field's measure on choice_frame; < 0: none */
    long choice_frame;
    size_t empty; /* frames with particles that gave no triangle */
    size_t no_particles; /* frames with none */
    size_t planned; /* frames of the whole run, all shards together */
    inputs in;          /* each frame's reads (a pipe read once) */
    jmf_anim *anim;     /* --animate: the one file being written */
    int anim_failed;    /* a frame could not be added to it */
    int anim_full;      /* it would pass its size limit: the run stops */
    int anim_warned;    /* the warning that it is heading past the limit is out */
    size_t anim_limit;  /* its limit: JMF_ANIM_MAX_BYTES, or JETMESH_TEST_ANIMATE_LIMIT */
} run;

static int is_gltf_family(int f)
{
    return f == JMF_OUT_GLTF || f == JMF_OUT_GLB;
}

/* --animate: one plain -o file for the whole run. */
static int animate_plan(run *r, seq_kind k)
{
    convert_options *o = r->o;
    size_t len = strlen(o->output);
    if (k != SEQ_PLAIN)
        return options_usage_error("convert", "--animate writes every frame into one file: give -o NAME.glb or "
                                   "NAME.gltf without a frame placeholder, not '%s'", o->output);
    if (platform_is_dir(o->output) || (len > 0 && o->output[len - 1] == '/'))
        return options_usage_error("convert", "--animate writes one file: %s is a directory", o->output);
    if (o->resume)
        return options_usage_error("convert", "--animate and --resume do not go together: the one file is "
                                   "written whole or not at all");
    return EXIT_ALL_OK;
}

/* --animate: the one output (every frame names it) is no input, and not
 * the statistics or the chart either. */
static int animate_check_output(run *r)
{
    const char *out = r->o->output;
    const char *extra[2] = {r->o->stats_path, r->o->stats_svg};
    struct stat so, si;
    for (int k = 0; k < 2; k++)
        if (extra[k] && strcmp(extra[k], out) == 0)
            return options_usage_error("convert", "--animate and %s would both write %s",
                                       k ? "--stats-svg" : "--stats", out);
    if (stat(out, &so) != 0)
        return EXIT_ALL_OK;
    for (size_t j = 0; j < r->njobs; j++)
        if (stat(r->jobs[j].in->path, &si) == 0 && si.st_dev == so.st_dev && si.st_ino == so.st_ino)
            return options_usage_error("convert", "refusing to overwrite the input file %s (with %s)",
                                       r->jobs[j].in->path, out);
    return EXIT_ALL_OK;
}

/* Decides every frame's output path and the output format. */
static int plan_outputs(run *r)
{
    convert_options *o = r->o;
    size_t n = r->frames.count;
    r->jobs = calloc(n, sizeof *r->jobs);
    if (!r->jobs) {
        fprintf(stderr, "jetmesh convert: out of memory\n");
        return EXIT_RESOURCE;
    }
    r->njobs = n;
    seq_kind k = seq_kind_of(o->output);
    if (k == SEQ_INVALID)
        return options_usage_error("convert", "'%s' has more than one frame placeholder ({} or %%d)", o->output);
    size_t len = strlen(o->output);
    int as_dir = 0;
    if (o->animate) {
        int rc = animate_plan(r, k);
        if (rc != EXIT_ALL_OK)
            return rc;
        k = SEQ_PLAIN; /* every frame names the one file */
    } else if (k == SEQ_PLAIN) {
        as_dir = platform_is_dir(o->output) || (len > 0 && o->output[len - 1] == '/');
        if (!as_dir && n > 1) {
            struct stat st;
            if (stat(o->output, &st) == 0)
                return options_usage_error("convert",
                                           "%s exists and is not a directory: with several "
                                           "frames, OUTPUT is a directory or a template with {}",
                                           o->output);
            jmf_write_options autodetect;
            memset(&autodetect, 0, sizeof autodetect);
            int d = 0;
            if (jmf_output_format_for(o->output, &autodetect, &d) >= 0)
                return options_usage_error("convert",
                                           "%zu frames cannot all be written to the one file %s: "
                                           "give a directory or a template with {}",
                                           n, o->output);
            as_dir = 1;
        }
    }
    if (as_dir && !o->format_given)
        o->write.format = JMF_OUT_GLB; /* documented default for a directory */
    const char *ext = jmf_output_format_name(o->write.format);
    for (size_t i = 0; i < n; i++) {
        const seq_frame *f = &r->frames.items[i];
        char *out;
        if (k != SEQ_PLAIN)
            out = seq_substitute(o->output, f->index, f->digits);
        else if (as_dir)
            out = seq_in_directory(o->output, f->path, ext);
        else
            out = strdup(o->output);
        if (!out) {
            fprintf(stderr, "jetmesh convert: out of memory\n");
            return EXIT_RESOURCE;
        }
        r->jobs[i].in = f;
        r->jobs[i].out = out;
    }
    /* the format, from --format or the (first) output's extension */
    int draco = 0;
    int fmt = jmf_output_format_for(r->jobs[0].out, &o->write, &draco);
    if (fmt < 0)
        return options_usage_error("convert",
                                   "cannot tell the output format of '%s': use --format "
                                   "obj|gltf|glb|drc|ply|vtk",
                                   r->jobs[0].out);
    for (size_t i = 1; i < n; i++) {
        int d2 = 0;
        if (jmf_output_format_for(r->jobs[i].out, &o->write, &d2) != fmt)
            return options_usage_error("convert", "'%s' and '%s' name different output formats",
                                       r->jobs[0].out, r->jobs[i].out);
    }
    o->write.format = (jmf_output_format)fmt;
    if (draco)
        o->write.draco = 1;
    if (o->write.draco && !is_gltf_family(fmt))
        return options_usage_error("convert",
                                   "--draco applies to glTF/GLB output, not %s (.drc is Draco already)",
                                   jmf_output_format_name((jmf_output_format)fmt));
    if (o->write.embed && fmt != JMF_OUT_GLTF)
        return options_usage_error("convert", "--embed applies to .gltf output, not %s",
                                   jmf_output_format_name((jmf_output_format)fmt));
    if (o->attributes && !jmf_format_holds_attributes(fmt, o->write.draco))
        return options_usage_error("convert",
                                   "%s cannot hold per-vertex attributes (--attributes): write glTF/GLB "
                                   "(Draco or not), .drc, PLY or VTK",
                                   jmf_output_format_name((jmf_output_format)fmt));
    if (o->animate && !is_gltf_family(fmt))
        return options_usage_error("convert", "--animate writes one glTF: give -o NAME.glb or NAME.gltf, not %s",
                                   jmf_output_format_name((jmf_output_format)fmt));
    if (o->animate && o->write.embed)
        return options_usage_error("convert", "--animate writes a .glb or a .gltf with a .bin; not with --embed");
    return EXIT_ALL_OK;
}

/* --shard: keeps this process's share of the planned frames (outputs and
 * their collisions were decided over all of them, as a single run does, so
 * every shard names the same files). */
static void take_shard(run *r)
{
    size_t k = 0;
    r->planned = r->njobs;
    for (size_t i = 0; i < r->njobs; i++) {
        if (shard_owns(&r->o->shard, i))
            r->jobs[k++] = r->jobs[i];
        else
            free(r->jobs[i].out);
    }
    r->njobs = k;
    if (!r->o->quiet && r->o->shard.count > 0) {
        long i = r->o->shard.index, n = r->o->shard.count;
        printf("shard %ld/%ld: %zu of the %zu frames (positions %ld, %ld, %ld... from 0)\n", i, n, k,
               r->planned, i, i + n, i + 2 * n);
        stdout_check();
    }
}

/* path with its directory resolved (symbolic links, "..", "./"), so that
 * two spellings of one file compare equal; a copy of path when the
 * directory does not exist yet. NULL when out of memory. */
static char *canonical(const char *path)
{
    const char *slash = strrchr(path, '/');
    char *dir = slash ? strndup(path, (size_t)(slash - path) + (slash == path)) : strdup(".");
    if (!dir)
        return NULL;
    char *real = realpath(dir, NULL);
    free(dir);
    if (!real)
        return strdup(path);
    const char *base = slash ? slash + 1 : path;
    size_t n = strlen(real) + strlen(base) + 2;
    char *c = malloc(n);
    if (c)
        snprintf(c, n, "%s/%s", strcmp(real, "/") == 0 ? "" : real, base);
    free(real);
    return c;
}

typedef struct out_name {
    char *canon;
    const char *given; /* for messages */
    const char *what;  /* "frame 12", "--stats", ... */
} out_name;

static int cmp_out_name(const void *a, const void *b)
{
    return strcmp(((const out_name *)a)->canon, ((const out_name *)b)->canon);
}

/* Refuses two outputs of the run that are one file (two frames, a mesh and
 * the statistics or the chart, a .gltf's .bin and another output), and any
 * output that is an input. */
static int check_outputs(run *r)
{
    size_t n = r->njobs, m = 0;
    out_name *names = calloc(2 * n + 2, sizeof *names);
    char (*what)[48] = calloc(2 * n + 2, sizeof *what);
    char **bins = calloc(n + 1, sizeof *bins);
    int rc = EXIT_ALL_OK;
    if (!names || !what || !bins)
        goto nomem;
    for (size_t i = 0; i < n; i++) {
        const char *out = r->jobs[i].out;
        snprintf(what[m], sizeof what[m], "the output of frame %ld", r->jobs[i].in->index);
        names[m] = (out_name){canonical(out), out, what[m]};
        if (!names[m++].canon)
            goto nomem;
        size_t len = strlen(out);
        if (r->o->write.format == JMF_OUT_GLTF && !r->o->write.embed && len > 5 &&
            strcmp(out + len - 5, ".gltf") == 0) {
            bins[i] = malloc(len);
            if (!bins[i])
                goto nomem;
            memcpy(bins[i], out, len - 5);
            memcpy(bins[i] + len - 5, ".bin", 5);
            snprintf(what[m], sizeof what[m], "the .bin of frame %ld", r->jobs[i].in->index);
            names[m] = (out_name){canonical(bins[i]), bins[i], what[m]};
            if (!names[m++].canon)
                goto nomem;
        }
    }
    const char *extra[2] = {r->o->stats_path, r->o->stats_svg};
    const char *extra_what[2] = {"--stats", "--stats-svg"};
    for (int k = 0; k < 2; k++)
        if (extra[k]) {
            names[m] = (out_name){canonical(extra[k]), extra[k], extra_what[k]};
            if (!names[m++].canon)
                goto nomem;
        }
    qsort(names, m, sizeof *names, cmp_out_name);
    for (size_t i = 1; i < m && rc == EXIT_ALL_OK; i++)
        if (strcmp(names[i - 1].canon, names[i].canon) == 0) {
            if (strncmp(names[i - 1].what, "the output of frame", 19) == 0 &&
                strncmp(names[i].what, "the output of frame", 19) == 0)
                rc = options_usage_error("convert", "two frames would write %s: use a template with {} in -o",
                                         names[i].given);
            else
                rc = options_usage_error("convert", "%s and %s would both write %s: give them different names",
                                         names[i - 1].what, names[i].what, names[i].given);
        }
    if (rc != EXIT_ALL_OK)
        goto out;

    /* no output is an input (the same file, however it is spelled) */
    struct stat *ins = malloc((n ? n : 1) * sizeof *ins);
    char *have = calloc(n ? n : 1, 1);
    if (!ins || !have) {
        free(ins);
        free(have);
        goto nomem;
    }
    for (size_t i = 0; i < n; i++)
        have[i] = stat(r->jobs[i].in->path, &ins[i]) == 0;
    for (size_t i = 0; i < m && rc == EXIT_ALL_OK; i++) {
        struct stat st;
        if (stat(names[i].given, &st) != 0)
            continue;
        for (size_t j = 0; j < n; j++) {
            if (have[j] && ins[j].st_dev == st.st_dev && ins[j].st_ino == st.st_ino) {
                rc = options_usage_error("convert", "refusing to overwrite the input file %s (with %s)",
                                         r->jobs[j].in->path, names[i].given);
                break;
            }
        }
    }
    free(ins);
    free(have);
    goto out;
nomem:
    fprintf(stderr, "jetmesh convert: out of memory\n");
    rc = EXIT_RESOURCE;
out:
    for (size_t i = 0; names && i < m; i++)
        free(names[i].canon);
    for (size_t i = 0; bins && i < n; i++)
        free(bins[i]);
    free(names);
    free(what);
    free(bins);
    return rc;
}

/* Before any frame is meshed: every directory the run writes into can be
 * made and written (a file is created there and removed), so a run into a
 * read-only place fails at once instead of meshing every frame and
 * throwing each away. */
static int check_writable(run *r)
{
    const char *last = NULL;
    size_t lastlen = 0;
    /* a file name the file system cannot hold fails before any work */
    for (size_t i = 0; i < r->njobs + 2; i++) {
        const char *out = i < r->njobs ? r->jobs[i].out : (i == r->njobs ? r->o->stats_path : r->o->stats_svg);
        const char *slash = out ? strrchr(out, '/') : NULL;
        if (!out || strlen(slash ? slash + 1 : out) <= 255)
            continue;
        char *dir = slash ? strndup(out, (size_t)(slash - out) + (slash == out)) : strdup(".");
        long most = dir ? pathconf(dir, _PC_NAME_MAX) : -1;
        free(dir);
        if (most <= 0)
            most = 255;
        if (strlen(slash ? slash + 1 : out) > (size_t)most)
            return options_usage_error("convert", "the file name of %s is %zu bytes, over the %ld its file "
                                       "system accepts", out, strlen(slash ? slash + 1 : out), most);
    }
    for (size_t i = 0; i < r->njobs + 2; i++) {
        const char *out = i < r->njobs ? r->jobs[i].out : (i == r->njobs ? r->o->stats_path : r->o->stats_svg);
        if (!out)
            continue;
        const char *slash = strrchr(out, '/');
        size_t dl = slash ? (size_t)(slash - out) : 0;
        if (last && dl == lastlen && strncmp(out, last, dl) == 0)
            continue; /* the same directory as the previous output */
        last = out;
        lastlen = dl;
        struct stat st;
        if (stat(out, &st) == 0 && !S_ISREG(st.st_mode))
            continue; /* a device or FIFO is written in place */
        if (platform_make_dirs(out, 1) != 0) {
            fprintf(stderr, "jetmesh convert: cannot create the directory of %s: %s\n", out, strerror(errno));
            return EXIT_SOME_FAILED;
        }
        char probe[4200];
        snprintf(probe, sizeof probe, "%.*s%s.jetmesh-probe-%ld", (int)dl, out, dl ? "/" : "", (long)getpid());
        int fd = open(probe, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0600);
        if (fd < 0 && errno != EEXIST) {
            fprintf(stderr, "jetmesh convert: cannot write in the directory of %s: %s\n", out, strerror(errno));
            return EXIT_SOME_FAILED;
        }
        if (fd >= 0) {
            close(fd);
            unlink(probe);
        }
    }
    return EXIT_ALL_OK;
}

/* Writes s for a one-line report: control characters (a newline in a file
 * name) as C escapes, so that every report stays one line per frame. */
static void print_path(FILE *f, const char *s)
{
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p == '\n')
            fputs("\\n", f);
        else if (*p == '\t')
            fputs("\\t", f);
        else if (*p == '\r')
            fputs("\\r", f);
        else if (*p < 0x20 || *p == 0x7f)
            fprintf(f, "\\x%02x", *p);
        else if (*p == '\\')
            fputs("\\\\", f);
        else
            fputc(*p, f);
    }
}

static const char *uv_name(jm_uv_mode m)
{
    switch (m) {
    case JM_UV_PLANAR: return "planar";
    case JM_UV_SPHERICAL: return "spherical";
    case JM_UV_NONE: return "none";
    default: return "box";
    }
}

static int frame_jobs(const run *r);
static int total_threads(const run *r);

/* "auto" or "given", and the field/method names, for the reports */
static const char *choice_name(const run *r)
{
    return r->o->field_auto ? "auto" : "given";
}

/* --field auto (the default): the field and method of the whole run, from
 * the first frame of the sequence that reads (the same for every shard of
 * a run and for a resumed run); the method only where --method was not
 * given. With --field metasphere given on what looks like bulk fluid, a
 * warning with the alternative, once. */
static void choose_field(run *r)
{
    convert_options *o = r->o;
    r->neighbours = -1.0f;
    if (!o->field_auto && o->params.field == JM_FIELD_SPH)
        return;
    for (size_t i = 0; i < r->frames.count && i < 8; i++) {
        const seq_frame *f = &r->frames.items[i];
        jmf_frame fr;
        char err[1024];
        memset(&fr, 0, sizeof fr);
        double t0 = platform_now_ms();
        if (inputs_read(&r->in, i, &o->read, &fr, err, sizeof err, NULL) != JMF_OK)
            continue; /* its own failure is reported in its turn */
        double ms = platform_now_ms() - t0;
        jm_particles in = {fr.xyz, fr.count, 0, NULL};
        jm_field fd;
        jm_method m;
        float nb;
        jm_status s = jm_choose_field(&o->params, &in, &fd, &m, &nb);
        /* the frame's conversion takes these particles instead of reading
         * them again, unless --attributes all changes what it reads */
        if (!o->attributes || strcasecmp(o->attributes, "all") != 0)
            inputs_hold(&r->in, i, &o->read, &fr, ms);
        jmf_frame_free(&fr);
        if (s != JM_OK)
            continue;
        r->neighbours = nb;
        r->choice_frame = f->index;
        if (o->field_auto) {
            o->params.field = fd;
            if (o->params.method == JM_METHOD_DEFAULT)
                o->params.method = m;
        } else if (fd == JM_FIELD_SPH && !o->quiet) {
            fprintf(stderr,
                    "jetmesh convert: warning: %s looks like bulk fluid (%.1f neighbours within the "
                    "link distance): the metasphere leaves cavities between particles that do not "
                    "touch; --field sph --method mc (or no --field) gives one liquid surface\n",
                    f->path, (double)nb);
            fflush(stderr);
        }
        return;
    }
    if (o->field_auto) /* no frame reads: they fail in their turn anyway */
        o->params.field = JM_FIELD_METASPHERE;
}

static void print_params(const run *r)
{
    jm_params p;
    char mem[32];
    jm_context_get_params(r->ctx, &p);
    printf("jetmesh %s: %zu frames; radius %g, cube size %g r, field %s, method %s (%s", jm_version(),
           r->njobs, (double)p.radius, (double)p.cube_size, cli_field_name(p.field),
           cli_method_name(p.method), choice_name(r));
    if (r->neighbours >= 0)
        printf(": %.2f neighbours in frame %ld", (double)r->neighbours, r->choice_frame);
    printf("), threshold %g, ", (double)p.threshold);
    if (p.field == JM_FIELD_SPH)
        printf("smoothing length %g r, ", (double)p.smoothing_length);
    if (p.anisotropic)
        printf("anisotropic kernels (radius %g r), ", (double)p.aniso_radius);
    if (p.field != JM_FIELD_SPH)
        printf("link distance %g r, ", (double)p.link_distance);
    if (r->o->params.threads > JM_MAX_THREADS)
        printf("threads %d (-j %d capped at %d), ", total_threads(r), r->o->params.threads, JM_MAX_THREADS);
    else
        printf("threads %d, ", total_threads(r));
    printf("frames at once %d, uv %s, normals %s, max memory %s; output %s%s\n", frame_jobs(r), uv_name(p.uv_mode), p.no_normals ? "no" : "yes",
           p.max_bytes ? platform_format_bytes(p.max_bytes, mem, sizeof mem) : "no limit",
           jmf_output_format_name(r->o->write.format), r->o->write.draco ? " with Draco" : "");
    stdout_check();
}

static int read_status(jmf_status s)
{
    return s == JMF_E_NOMEM || s == JMF_E_LIMIT ? EXIT_RESOURCE : EXIT_SOME_FAILED;
}

/* Marks an outcome failed with msg and the exit status it implies. */
static void outcome_fail(outcome *oc, const char *msg, int status)
{
    stats_fail(&oc->rec, msg);
    oc->status = status;
}

/* The message (into msg) and exit status of a frame the library refused
 * with ms; outside: its coordinates are beyond the lattice's reach. */
static int mesh_failure(const convert_options *o, const char *path, const jm_particles *parts, jm_status ms,
                        size_t est, int outside, char *msg, size_t len)
{
    if (outside) {
        /* no memory changes that: a frame this tool cannot mesh as it is (issue 30) */
        domain_advice(msg, len, path, &o->params, parts);
        return EXIT_SOME_FAILED;
    }
    if (ms == JM_E_TOO_LARGE) {
        /* names --cube-size when the machine itself could not hold it */
        param_errors_too_large(msg, len, path, &o->params, parts, est, o->max_memory);
        return EXIT_RESOURCE;
    }
    if (ms == JM_E_TOO_DENSE) {
        snprintf(msg, len,
                 "%s: %zu particles packed far closer than their radius %g: many duplicated "
                 "particles, or -r far too large for their spacing (the neighbour search is "
                 "bounded; see jetmesh(1), LIMITS)",
                 path, parts->count, (double)o->params.radius);
        return EXIT_SOME_FAILED;
    }
    if (ms == JM_E_NUMERIC_DOMAIN) {
        param_errors_domain(msg, len, path, &o->params, parts);
        return EXIT_SOME_FAILED;
    }
    if (ms == JM_E_INVALID_PARTICLE) {
        snprintf(msg, len, "%s: %s (--drop-invalid skips such particles)", path, jm_status_message(ms));
        return EXIT_SOME_FAILED;
    }
    snprintf(msg, len, "%s: %s", path, jm_status_message(ms));
    return ms == JM_E_INVALID_ARGUMENT ? EXIT_SOME_FAILED : EXIT_RESOURCE;
}

/* Reads, meshes and writes one frame with ctx, staging the output (its
 * temporaries complete, not yet renamed). Prints nothing: the outcome is
 * reported in frame order by report(). shared: ctx has only a share of
 * --max-memory, so a refusal over that share asks for a retry alone. */
static void convert_frame(const convert_options *o, inputs *in, jm_context *ctx, const jmf_read_options *read,
                          int shared, const job *jb, outcome *oc)
{
    const seq_frame *f = jb->in;
    const size_t fi = (size_t)(f - in->frames->items);
    char err[1024], msg[1400], b1[32];
    memset(oc, 0, sizeof *oc);
    oc->rec.index = f->index;
    if (o->resume && platform_is_file(jb->out)) {
        oc->rec.status = STATS_SKIPPED;
        return;
    }
    stats_record *rec = &oc->rec;
    double t0 = platform_now_ms();
    jmf_frame fr;
    memset(&fr, 0, sizeof fr);
    double held_ms = 0; /* a frame read by the field choice: that read's time */
    jmf_status rs = inputs_read(in, fi, read, &fr, err, sizeof err, &held_ms);
    double t1 = platform_now_ms();
    t0 -= held_ms;
    rec->ms_read = t1 - t0;
    if (rs != JMF_OK) {
        if (rs == JMF_E_LIMIT && shared) {
            oc->retry = 1;
            return;
        }
        if (rs == JMF_E_LIMIT && o->max_memory)
            snprintf(msg, sizeof msg, "%s (over --max-memory %s: raise --max-memory)", err,
                     platform_format_bytes(o->max_memory, b1, sizeof b1));
        else if (rs == JMF_E_UNSUPPORTED && read->format == JMF_IN_AUTO && strcmp(f->path, "-") == 0)
            snprintf(msg, sizeof msg, "%s (standard input has no name to tell its format by: give "
                     "--input-format)", err);
        else
            snprintf(msg, sizeof msg, "%s", err);
        rec->ms_total = rec->ms_read;
        rec->peak_rss_bytes = platform_peak_rss();
        outcome_fail(oc, msg, read_status(rs));
        return;
    }
    rec->particles = fr.count;
    rec->dropped = fr.dropped;
    jm_particles parts = {fr.xyz, fr.count, 0, fr.ids};
    jm_mesh mesh;
    jm_stats *st = &oc->st;
    memset(&mesh, 0, sizeof mesh);
    jm_status ms = jm_mesh_particles(ctx, &parts, &mesh, st);
    double t2 = platform_now_ms();
    if (ms != JM_OK) {
        /* the library's own estimate, the one it refused on */
        size_t est = st->estimated_bytes;
        if (ms == JM_E_TOO_LARGE && !est) jm_estimate_bytes(ctx, &parts, &est);
        int outside = ms == JM_E_TOO_LARGE && domain_outside(&o->params, &parts);
        if (shared && !outside && (ms == JM_E_TOO_LARGE || ms == JM_E_OUT_OF_MEMORY)) {
            jmf_frame_free(&fr);
            oc->retry = 1;
            return;
        }
        int status = mesh_failure(o, f->path, &parts, ms, est, outside, msg, sizeof msg);
        jmf_frame_free(&fr);
        rec->ms_field = st->ms_prepare + st->ms_field;
        rec->ms_total = t2 - t0;
        rec->peak_rss_bytes = platform_peak_rss();
        rec->lib_peak_bytes = st->peak_bytes;
        outcome_fail(oc, msg, status);
        return;
    }
    jmf_write_options wopt = o->write;
    jmf_attribute *va = NULL;
    size_t nva = 0;
    if (fr.attribute_count) {
        jm_status as = vattrs_make(ctx, &fr, &mesh, &va, &nva);
        if (as != JM_OK) {
            snprintf(msg, sizeof msg, "%s: interpolating its attributes: %s", f->path, jm_status_message(as));
            jmf_frame_free(&fr);
            rec->ms_total = platform_now_ms() - t0;
            outcome_fail(oc, msg, as == JM_E_OUT_OF_MEMORY ? EXIT_RESOURCE : EXIT_SOME_FAILED);
            return;
        }
        wopt.attributes = va;
        wopt.attribute_count = nva;
    }
    jmf_frame_free(&fr); /* the library keeps no pointer to the particles */
    rec->vertices = mesh.vertex_count;
    rec->triangles = mesh.triangle_count;
    double t3 = platform_now_ms();
    /* the stages add up to the total: the library's call (t1 to t2) by its
     * own stages, what they leave (its bookkeeping, the call itself) with
     * extract; the interpolated --attributes and freeing the frame (t2 to
     * t3) with attributes */
    const double lib = st->ms_prepare + st->ms_field + st->ms_extract + st->ms_attributes + st->ms_post;
    rec->ms_field = st->ms_prepare + st->ms_field;
    rec->ms_extract = st->ms_extract + ((t2 - t1) - lib);
    rec->ms_attributes = st->ms_attributes + (t3 - t2);
    rec->ms_post = st->ms_post;
    rec->lib_peak_bytes = st->peak_bytes;

    size_t bytes = 0;
    jmf_status ws;
    if (platform_make_dirs(jb->out, 1) != 0) {
        snprintf(err, sizeof err, "%s: cannot create its directory: %s", jb->out, strerror(errno));
        ws = JMF_E_IO;
    } else if (o->animate) {
        char name[64];
        snprintf(name, sizeof name, "%s frame %ld", jb->out, f->index);
        ws = jmf_anim_piece_build(&mesh, &wopt, o->write.draco, name, &oc->piece, err, sizeof err);
        bytes = jmf_anim_piece_bytes(oc->piece);
    } else {
        ws = jmf_write_mesh_staged(jb->out, &mesh, &wopt, &bytes, &oc->staged, err, sizeof err);
    }
    vattrs_free(va, nva);
    double t4 = platform_now_ms();
    rec->ms_write = t4 - t3;
    rec->ms_total = t4 - t0;
    rec->peak_rss_bytes = platform_peak_rss();
    if (ws != JMF_OK) {
        outcome_fail(oc, err, ws == JMF_E_NOMEM ? EXIT_RESOURCE : EXIT_SOME_FAILED);
        return;
    }
    rec->bytes = bytes;
}

/* --animate: once, when the frames so far, at their mean size, would take
 * the whole run past the file's limit, a warning (the run goes on: frames
 * may shrink; it stops when the file really would pass the limit). */
static void animation_forecast(run *r, const job *jb)
{
    size_t done = (size_t)(jb - r->jobs) + 1;
    if (r->anim_warned || done < 4 || done >= r->njobs)
        return;
    double bytes = (double)jmf_anim_bytes(r->anim);
    if (bytes / (double)done * (double)r->njobs <= (double)r->anim_limit)
        return;
    r->anim_warned = 1;
    progress_clear(&r->bar);
    char b1[32], b2[32];
    fprintf(stderr,
            "jetmesh: warning: %zu frames made %s of %s; at that rate its %zu frames would pass the %s an "
            "animated file may hold, and the run will stop there: one file per frame (-o 'DIR/frame_{}.glb') "
            "has no such limit\n",
            done, platform_format_bytes((size_t)bytes, b1, sizeof b1), r->o->output, r->njobs,
            platform_format_bytes(r->anim_limit, b2, sizeof b2));
    fflush(stderr);
}

/* Takes a frame's outcome in its turn: publishes its output (renamed into
 * place), logs it and prints its line. 0 when it went well (or was
 * skipped). */
static int report(run *r, const job *jb, outcome *oc)
{
    convert_options *o = r->o;
    char err[1024], b1[32], b2[32];
    stats_record *rec = stats_add(&r->log, jb->in->index, jb->in->path, jb->out);
    if (!rec) {
        fprintf(stderr, "jetmesh: out of memory\n");
        jmf_staged_abort(&oc->staged);
        free(oc->rec.error);
        oc->rec.error = NULL;
        r->worst = EXIT_RESOURCE;
        r->failed++;
        return -1;
    }
    if (r->anim) {
        /* --animate: the frame joins the one file (a failed one as an empty node) */
        char name[64];
        snprintf(name, sizeof name, "frame_%04ld", jb->in->index);
        double t0 = platform_now_ms();
        jmf_anim_piece *pc = oc->rec.status == STATS_OK ? oc->piece : NULL;
        if (pc == NULL)
            jmf_anim_piece_free(oc->piece);
        oc->piece = NULL;
        jmf_status as = jmf_anim_add(r->anim, name, jb->in->index, pc, err, sizeof err);
        if (as == JMF_E_LIMIT) {
            /* the file cannot hold the run: every frame after this one is wasted work */
            outcome_fail(oc, err, EXIT_RESOURCE);
            r->anim_failed = r->anim_full = 1;
        } else if (as != JMF_OK) {
            if (oc->rec.status == STATS_OK)
                outcome_fail(oc, err, EXIT_SOME_FAILED);
            r->anim_failed = 1;
        } else {
            animation_forecast(r, jb);
        }
        const double dt = platform_now_ms() - t0;
        oc->rec.ms_write += dt;
        oc->rec.ms_total += dt;
    } else if (oc->rec.status == STATS_OK) {
        /* the flush to disk and the rename: part of the frame's write time */
        double t0 = platform_now_ms();
        if (jmf_staged_publish(&oc->staged, err, sizeof err) != JMF_OK)
            outcome_fail(oc, err, EXIT_SOME_FAILED);
        double dt = platform_now_ms() - t0;
        oc->rec.ms_write += dt;
        oc->rec.ms_total += dt;
    }
    char *in = rec->input, *out = rec->output;
    *rec = oc->rec; /* the error string moves into the log */
    rec->input = in;
    rec->output = out;
    oc->rec.error = NULL;
    if (rec->status == STATS_SKIPPED) {
        if (!o->quiet) {
            progress_clear(&r->bar);
            printf("frame %ld ", rec->index);
            print_path(stdout, rec->input);
            printf(": skipped, ");
            print_path(stdout, rec->output);
            printf(" exists (--resume)\n");
            stdout_check();
        }
        return 0;
    }
    if (rec->status == STATS_FAILED) {
        progress_clear(&r->bar);
        fprintf(stderr, "jetmesh: frame %ld: %s\n", rec->index, rec->error);
        fflush(stderr);
        r->failed++;
        if (oc->status > r->worst)
            r->worst = oc->status;
        return -1;
    }
    if (rec->particles > 0 && rec->triangles == 0 && !select_any(&o->params) && r->empty++ == 0)
        param_errors_warn_empty(rec->index, rec->input, rec->particles, &o->params);
    if (rec->particles == 0 && r->no_particles++ == 0)
        param_errors_warn_no_particles(rec->index, rec->input, rec->dropped);
    if (!o->quiet) {
        const jm_stats *st = &oc->st;
        progress_clear(&r->bar);
        printf("frame %ld ", rec->index);
        print_path(stdout, rec->input);
        printf(": %zu particles", rec->particles);
        if (rec->dropped)
            printf(" (%zu dropped)", rec->dropped);
        if (st->particles != rec->particles) /* the selection's (select_options.h) */
            printf(" (%zu meshed)", st->particles);
        printf(", %zu vertices, %zu triangles, %.2f ms -> ", rec->vertices, rec->triangles, rec->ms_total);
        print_path(stdout, rec->output);
        putchar('\n');
        if (o->verbose)
            printf("  read %.2f ms, field %.2f ms, extract %.2f ms, attributes %.2f ms, post %.2f ms, write %.2f ms; "
                   "%zu isolated, %zu blocks, %zu cells, %zu cavities removed, %d threads, library peak %s, "
                   "process peak %s, %zu bytes written\n",
                   rec->ms_read, rec->ms_field, rec->ms_extract, rec->ms_attributes, rec->ms_post, rec->ms_write,
                   st->isolated, st->blocks, st->cells, st->cavities_removed, st->threads,
                   platform_format_bytes(st->peak_bytes, b1, sizeof b1),
                   platform_format_bytes(rec->peak_rss_bytes, b2, sizeof b2), rec->bytes);
        if (o->verbose && st->ms_post > 0.0)
            printf("  post-processing (smoothing, simplification) %.2f ms\n", st->ms_post);
        stdout_check();
    }
    return 0;
}

/* Drops an outcome that will not be reported (after a stop): its staged
 * output is removed, so the disk holds what a one-at-a-time run leaves. */
static void discard(outcome *oc)
{
    jmf_anim_piece_free(oc->piece);
    oc->piece = NULL;
    jmf_staged_abort(&oc->staged);
    free(oc->rec.error);
    oc->rec.error = NULL;
}

/* The threads of the run, all frames at once together: -j (at most
 * JM_MAX_THREADS, what one context starts) or the cores. */
static int total_threads(const run *r)
{
    int t = r->o->params.threads ? r->o->params.threads : platform_cores();
    return t > JM_MAX_THREADS ? JM_MAX_THREADS : t;
}

/* The frames at once: --frame-jobs, or as many as threads (at most
 * CONVERT_MAX_FRAME_JOBS), never more than frames. */
static int frame_jobs(const run *r)
{
    int w = r->o->frame_jobs ? r->o->frame_jobs : total_threads(r);
    if (w > CONVERT_MAX_FRAME_JOBS)
        w = CONVERT_MAX_FRAME_JOBS;
    if ((size_t)w > r->njobs)
        w = (int)r->njobs;
    return w < 1 ? 1 : w;
}

static int farm_job(void *user, int w, size_t i)
{
    run *r = user;
    convert_frame(r->o, &r->in, r->wctx[w], &r->wread, 1, &r->jobs[i], &r->oc[i]);
    r->oc[i].done = 1;
    return r->oc[i].retry; /* a frame over its share stops the farm: done alone later */
}

/* Creates the per-worker contexts of W frames at once: each gets an equal
 * share of the threads and of --max-memory. 0 if any cannot be made. */
static int make_workers(run *r, int W)
{
    int threads = total_threads(r);
    jm_params p = r->o->params;
    p.threads = threads / W > 0 ? threads / W : 1;
    /* a share of 0 would read as "no limit": at least one byte */
    size_t share = r->o->max_memory / (size_t)W;
    if (r->o->max_memory && share == 0)
        share = 1;
    if (r->o->max_memory)
        p.max_bytes = share;
    r->wread = r->o->read;
    if (r->o->max_memory)
        r->wread.max_bytes = share;
    r->wctx = calloc((size_t)W, sizeof *r->wctx);
    if (!r->wctx)
        return 0;
    r->nwctx = W;
    for (int w = 0; w < W; w++)
        if (jm_context_create(&p, &r->wctx[w]) != JM_OK)
            return 0;
    return 1;
}

static void free_workers(run *r)
{
    for (int w = 0; w < r->nwctx; w++)
        jm_context_free(r->wctx[w]);
    free(r->wctx);
    r->wctx = NULL;
    r->nwctx = 0;
}

/* The main context with every thread of the run, for frames converted one
 * at a time. While frames are converted at once it has one thread, so the
 * run never holds more threads than -j (plus this one). 0 on failure. */
static int full_context(run *r)
{
    jm_params p;
    jm_context_get_params(r->ctx, &p);
    if (p.threads == total_threads(r))
        return 1;
    p = r->o->params;
    p.threads = total_threads(r);
    return jm_context_set_params(r->ctx, &p) == JM_OK;
}

/* Converts every frame: W at once on worker threads while the results are
 * taken in frame order; from a frame over its share of --max-memory (or
 * when no worker can start) on, one at a time with all threads. Without
 * --keep-going it stops at the first failure, and outputs of later frames
 * made ahead are removed: the result is the same as one at a time. */
static void convert_all(run *r)
{
    size_t n = r->njobs, i = 0;
    int W = frame_jobs(r), stopped = 0;
    farm *fm = NULL;
    if (n == 0) /* a shard with no frame */
        return;
    r->oc = calloc(n, sizeof *r->oc);
    if (!r->oc) {
        fprintf(stderr, "jetmesh: out of memory\n");
        r->worst = EXIT_RESOURCE;
        return;
    }
    if (W > 1 && make_workers(r, W))
        /* up to window + 1 frames past the last one reported, each holding
         * its staged output (memory and open files) until its turn */
        fm = farm_start(n, W, 2 * W < 31 ? 2 * (size_t)W : 31, farm_job, r);
    for (; i < n && !stopped; i++) {
        outcome *oc = &r->oc[i];
        if (fm && (!farm_wait(fm, i) || oc->retry)) {
            /* this frame and the rest one at a time: any outcomes beyond it
             * are complete once the farm has stopped, or never begun; the
             * workers' contexts (their threads and scratch) go first, so
             * that the frame alone has all the threads and all the memory */
            farm_stop(fm);
            fm = NULL;
            free_workers(r);
        }
        if ((!oc->done || oc->retry) && !full_context(r)) {
            outcome_fail(oc, "out of memory for the meshing context", EXIT_RESOURCE);
            oc->done = 1;
            oc->retry = 0;
        }
        if (!oc->done || oc->retry)
            convert_frame(r->o, &r->in, r->ctx, &r->o->read, 0, &r->jobs[i], oc);
        int ok = report(r, &r->jobs[i], oc) == 0;
        inputs_release(&r->in, (size_t)(r->jobs[i].in - r->frames.items));
        if (fm)
            farm_taken(fm, i);
        progress_update(&r->bar, i + 1);
        if (!ok && (!r->o->keep_going || r->anim_full))
            stopped = 1;
    }
    farm_stop(fm);
    for (; i < n; i++)
        discard(&r->oc[i]);
}

static void write_reports(run *r, double wall_ms)
{
    stats_summary sum;
    char err[1024];
    stats_summarize(&r->log, wall_ms, &sum);
    jm_params p;
    jm_context_get_params(r->ctx, &p);
    sum.field = cli_field_name(p.field);
    sum.method = cli_method_name(p.method);
    sum.field_choice = choice_name(r);
    sum.neighbours = r->neighbours;
    if (r->o->stats_path)
        platform_make_dirs(r->o->stats_path, 1); /* a failure shows when writing */
    if (r->o->stats_svg)
        platform_make_dirs(r->o->stats_svg, 1);
    if (r->o->stats_path && stats_write(r->o->stats_path, &r->log, &sum, err, sizeof err) != 0) {
        fprintf(stderr, "jetmesh: cannot write the statistics: %s\n", err);
        if (r->worst < EXIT_SOME_FAILED)
            r->worst = EXIT_SOME_FAILED;
    }
    if (r->o->stats_svg && stats_write_svg(r->o->stats_svg, &r->log, &sum, err, sizeof err) != 0) {
        fprintf(stderr, "jetmesh: cannot write the chart: %s\n", err);
        if (r->worst < EXIT_SOME_FAILED)
            r->worst = EXIT_SOME_FAILED;
    }
    if (!r->o->quiet) {
        printf("converted %zu of %zu frames (%zu failed, %zu skipped) in %.2f s, %.1f frames/s; "
               "field %s, method %s (%s)\n",
               sum.ok, r->njobs, sum.failed, sum.skipped, sum.wall_seconds, sum.frames_per_second,
               sum.field, sum.method, sum.field_choice);
        stdout_check();
    }
}

static void list_failures(const run *r)
{
    if (r->empty > 1)
        fprintf(stderr, "jetmesh: warning: %zu frames with particles gave empty meshes (see the first above)\n",
                r->empty);
    if (r->no_particles > 1)
        fprintf(stderr, "jetmesh: warning: %zu frames had no particles (see the first above)\n", r->no_particles);
    if (r->failed == 0)
        return;
    if (r->anim_full) {
        fprintf(stderr, "jetmesh: stopped: %s cannot hold the whole run; %zu frames not converted\n", r->o->output,
                r->njobs - r->log.count);
    } else if (!r->o->keep_going) {
        if (r->log.count < r->njobs)
            fprintf(stderr,
                    "jetmesh: stopped at the first failure; %zu frames not converted "
                    "(--keep-going converts the others)\n",
                    r->njobs - r->log.count);
        return;
    }
    fprintf(stderr, "jetmesh: %zu of %zu frames failed:\n", r->failed, r->njobs);
    for (size_t i = 0; i < r->log.count; i++) {
        const stats_record *rec = &r->log.items[i];
        if (rec->status == STATS_FAILED)
            fprintf(stderr, "  frame %ld: %s\n", rec->index, rec->error ? rec->error : "failed");
    }
}

/* --animate: the one file, once every frame is in (none after a stop). */
static void finish_animation(run *r)
{
    char err[1024];
    jmf_staged st;
    size_t bytes = 0;
    jmf_anim *a = r->anim;
    r->anim = NULL;
    if (r->log.count < r->njobs || r->anim_failed || r->failed == r->njobs) {
        jmf_anim_abort(a);
        fprintf(stderr, "jetmesh: %s not written: %s\n", r->o->output,
                r->anim_full ? "it would pass the size limit" : r->failed == r->njobs ? "no frame converted"
                                                                           : "not every frame went in");
        if (r->worst < EXIT_SOME_FAILED)
            r->worst = EXIT_SOME_FAILED;
        return;
    }
    if (jmf_anim_finish(a, &st, &bytes, err, sizeof err) != JMF_OK ||
        jmf_staged_publish(&st, err, sizeof err) != JMF_OK) {
        fprintf(stderr, "jetmesh: %s\n", err);
        if (r->worst < EXIT_SOME_FAILED)
            r->worst = EXIT_SOME_FAILED;
        return;
    }
    if (!r->o->quiet) {
        printf("animated %zu frames at %g fps -> %s (%zu bytes)\n", r->njobs, r->o->fps, r->o->output, bytes);
        stdout_check();
    }
}

/* --pvd, a VTK or PLY sequence: the .pvd collection beside it for ParaView. */
static void write_pvd(run *r)
{
    const convert_options *o = r->o;
    int f = o->write.format;
    if (!o->pvd || r->njobs < 2 || (f != JMF_OUT_VTK && f != JMF_OUT_PLY))
        return;
    char **files = malloc(r->log.count * sizeof *files);
    double *times = malloc(r->log.count * sizeof *times);
    char *path = pvd_path_for(o->output);
    char err[1024];
    size_t n = 0;
    const double dt = o->time_step > 0 ? o->time_step : 1.0 / o->fps;
    for (size_t i = 0; files && times && i < r->log.count; i++) {
        const stats_record *rec = &r->log.items[i];
        if (rec->status == STATS_FAILED)
            continue;
        files[n] = rec->output;
        times[n++] = (double)rec->index * dt;
    }
    if (!files || !times || !path)
        fprintf(stderr, "jetmesh: out of memory for the .pvd\n");
    else if (n && pvd_write(path, files, times, n, o->write.no_sync, err, sizeof err) != 0) {
        fprintf(stderr, "jetmesh: cannot write the ParaView collection: %s\n", err);
        if (r->worst < EXIT_SOME_FAILED)
            r->worst = EXIT_SOME_FAILED;
    }
    else if (n && !o->quiet)
        printf("ParaView collection (%zu frames, %g s apart per frame number) -> %s\n", n, dt, path);
    free(files);
    free(times);
    free(path);
}

static void run_free(run *r)
{
    for (size_t i = 0; i < r->njobs; i++)
        free(r->jobs[i].out);
    free(r->jobs);
    inputs_free(&r->in);
    seq_list_free(&r->frames);
    stats_free(&r->log);
    jm_context_free(r->ctx);
    free_workers(r);
    free(r->oc);
    jmf_anim_abort(r->anim);
    free(r->o->attributes_all);
}

int cmd_convert(int argc, char **argv)
{
    convert_options o;
    int rc = options_parse_convert(argc, argv, &o);
    if (rc == OPTIONS_DONE)
        return EXIT_ALL_OK;
    if (rc != OPTIONS_RUN)
        return EXIT_USAGE;
    signals_install_cleanup(); /* first: before any thread starts (signals.c) */
    if (o.threshold_given && o.params.threshold == 0.0f && o.params.field == JM_FIELD_SPH)
        fprintf(stderr, "jetmesh convert: warning: --threshold 0 means the default of the field "
                        "(0.6 for sph)\n");

    run r;
    memset(&r, 0, sizeof r);
    r.o = &o;
    double start = platform_now_ms();
    char err[1024];
    if (seq_expand(o.inputs, o.ninputs, &o.frames, &r.frames, err, sizeof err) != 0) {
        rc = options_usage_error("convert", "%s", err);
        goto done;
    }
    if (r.frames.count == 0) {
        rc = options_usage_error("convert", "--frames selects none of the input frames");
        goto done;
    }
    if (r.frames.count > SEQ_MAX_FRAMES) {
        rc = options_usage_error("convert",
                                 "the inputs name %zu frames, more than the %d one run plans: split them "
                                 "over several runs (--frames) or shards (--shard)",
                                 r.frames.count, SEQ_MAX_FRAMES);
        goto done;
    }
    if (inputs_init(&r.in, &r.frames, o.max_memory) != 0) {
        fprintf(stderr, "jetmesh convert: out of memory\n");
        rc = EXIT_RESOURCE;
        goto done;
    }
    if ((rc = plan_outputs(&r)) != EXIT_ALL_OK ||
        (rc = o.animate ? animate_check_output(&r) : check_outputs(&r)) != EXIT_ALL_OK)
        goto done;
    choose_field(&r);
    if ((rc = vattrs_resolve_all(o.attributes, &o.read, &r.in, &o.attributes_all)) != EXIT_ALL_OK)
        goto done;
    if (o.attributes_all)
        o.read.attributes = o.attributes_all;
    take_shard(&r);
    if ((rc = check_writable(&r)) != EXIT_ALL_OK)
        goto done;

    /* one thread while frames are converted at once: full_context() gives
     * it the rest when it has to convert alone */
    jm_params mp = o.params;
    mp.threads = frame_jobs(&r) > 1 ? 1 : total_threads(&r);
    jm_status cs = jm_context_create(&mp, &r.ctx);
    if (cs != JM_OK) {
        if (cs == JM_E_INVALID_ARGUMENT) {
            if (param_errors_describe(&o.params, err, sizeof err) == 0)
                snprintf(err, sizeof err, "invalid meshing parameters: %s", jm_status_message(cs));
            rc = options_usage_error("convert", "%s", err);
        } else {
            fprintf(stderr, "jetmesh convert: cannot create the meshing context: %s\n",
                    jm_status_message(cs));
            rc = EXIT_RESOURCE;
        }
        goto done;
    }
    if (o.verbose)
        print_params(&r);
    {
        /* what a killed run left beside these outputs */
        char **outs = malloc((r.njobs + 1) * sizeof *outs);
        char *frames = NULL; /* --animate: the .glb's temporary of its frames */
        size_t gone = 0, nouts = r.njobs;
        for (size_t i = 0; outs && i < r.njobs; i++)
            outs[i] = r.jobs[i].out;
        if (outs && o.animate && (frames = malloc(strlen(o.output) + 8)) != NULL) {
            sprintf(frames, "%s.frames", o.output);
            outs[nouts++] = frames;
        }
        if (outs)
            gone = stale_remove(outs, nouts);
        free(outs);
        free(frames);
        if (gone && !o.quiet)
            printf("removed %zu temporar%s left by an interrupted run\n", gone, gone == 1 ? "y" : "ies");
    }
    if (o.animate) {
        int glb = o.write.format == JMF_OUT_GLB;
        if (platform_make_dirs(o.output, 1) != 0 ||
            jmf_anim_open(o.output, glb, &o.write, o.fps, &r.anim, err, sizeof err) != JMF_OK) {
            if (!r.anim && platform_make_dirs(o.output, 1) != 0)
                snprintf(err, sizeof err, "%s: cannot create its directory: %s", o.output, strerror(errno));
            fprintf(stderr, "jetmesh convert: %s\n", err);
            rc = EXIT_SOME_FAILED;
            goto done;
        }
        /* tests only: a lower limit, so the refusal is tested without writing 2 GiB */
        const char *lim = getenv("JETMESH_TEST_ANIMATE_LIMIT");
        r.anim_limit = lim && *lim ? (size_t)strtoull(lim, NULL, 10) : 0;
        jmf_anim_set_limit(r.anim, r.anim_limit);
        if (!r.anim_limit)
            r.anim_limit = JMF_ANIM_MAX_BYTES;
    }
    progress_init(&r.bar, r.njobs, !o.quiet);
    convert_all(&r);
    progress_finish(&r.bar);
    if (o.animate)
        finish_animation(&r);
    else
        write_pvd(&r);
    list_failures(&r);
    write_reports(&r, platform_now_ms() - start);
    rc = r.worst ? r.worst : (r.failed ? EXIT_SOME_FAILED : EXIT_ALL_OK);
done:
    run_free(&r);
    return rc;
}

/* bench_run.c - runs one `jetmesh bench` case: loads its input, meshes it repeatedly on one context, records per-stage samples. */
#include "bench_run.h"
#include "bench_flicker.h"

#include <dirent.h>
#include <stdarg.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <unistd.h>
#ifdef __GLIBC__
#include <malloc.h>
#endif

#include "../../formats/writer.h"
#include "bench_options.h"
#include "../select_options.h"
#include "../param_errors.h"
#include "../platform.h"
#include "../scenes.h"

void bench_load_input(const bench_opts *o, bench_input *in)
{
    scene_points pts = {0};
    int r = 0;
    in->loaded = -1;
    switch (in->kind) {
    case IN_JET: r = scene_jet(in->frame, o->radius, &pts); break;
    case IN_BLOCK: r = scene_block(in->n, o->radius, o->seed, &pts); break;
    case IN_SPRAY: r = scene_spray(in->n, o->radius, o->seed, &pts); break;
    case IN_FILE: {
        jmf_frame fr;
        char err[256];
        jmf_status s = jmf_read_particles(in->path, &o->read, &fr, err, sizeof err);
        if (s != JMF_OK) {
            snprintf(in->err, sizeof in->err, "%s", err);
            return;
        }
        in->xyz = fr.xyz;
        in->ids = fr.ids;
        in->count = fr.count;
        in->loaded = 1;
        return;
    }
    }
    if (r != 0) {
        snprintf(in->err, sizeof in->err, "out of memory generating the scene");
        return;
    }
    in->xyz = pts.xyz;
    in->count = pts.count;
    in->loaded = 1;
}

void bench_free_input(bench_input *in)
{
    free(in->xyz);
    free(in->ids);
    in->xyz = NULL;
    in->ids = NULL;
}

/* Makes the process's peak RSS start from now (Linux >= 4.0); 1 if it did. */
static int reset_peak_rss(void)
{
#ifdef __GLIBC__
    malloc_trim(0);
#endif
    FILE *f = fopen("/proc/self/clear_refs", "w");
    if (!f)
        return 0;
    int ok = fputs("5", f) >= 0;
    if (fclose(f) != 0)
        ok = 0;
    return ok;
}

/* Removes every file in dir (the written mesh and a .gltf's .bin). */
void bench_empty_dir(const char *dir)
{
    DIR *d = opendir(dir);
    if (!d)
        return;
    struct dirent *e;
    char path[4096];
    while ((e = readdir(d))) {
        if (strcmp(e->d_name, ".") == 0 || strcmp(e->d_name, "..") == 0)
            continue;
        snprintf(path, sizeof path, "%s/%s", dir, e->d_name);
        unlink(path);
    }
    closedir(d);
}

void bench_progress(const bench_opts *o, const char *fmt, ...)
{
    static int shown = 0;
    if (o->quiet || !isatty(2))
        return;
    if (!fmt) {
        if (shown)
            fputs("\r\033[K", stderr);
        shown = 0;
        return;
    }
    va_list ap;
    va_start(ap, fmt);
    fputs("\r\033[K", stderr);
    vfprintf(stderr, fmt, ap);
    va_end(ap);
    fflush(stderr);
    shown = 1;
}

void bench_run_case(const bench_opts *o, const bench_input *in, bench_case *c, const char *wdir)
{
    bench_samples s[ST_COUNT];
    memset(s, 0, sizeof s);
    jm_context *ctx = NULL;
    c->ran = 1;
    c->ok = 0;
    c->has_write = o->write_format >= 0;

    jm_params p = o->params;
    p.radius = (float)o->radius;
    p.cube_size = (float)c->cube;
    p.field = c->field == BENCH_FIELD_SPH_ANISO ? JM_FIELD_SPH : c->field;
    p.anisotropic = c->field == BENCH_FIELD_SPH_ANISO;
    p.method = c->method;
    p.threads = c->threads;
    p.no_templates = !c->templates;

    if (in->loaded != 1) {
        snprintf(c->err, sizeof c->err, "%s", in->err);
        return;
    }
    c->rss_reset = reset_peak_rss();
    jm_status js = jm_context_create(&p, &ctx);
    if (js != JM_OK) {
        if (js != JM_E_INVALID_ARGUMENT || param_errors_describe(&p, c->err, sizeof c->err) == 0)
            snprintf(c->err, sizeof c->err, "jm_context_create: %s", jm_status_message(js));
        return;
    }
    jm_context_get_params(ctx, &c->params);

    jm_particles parts = {in->xyz, in->count, 0, in->ids};
    jmf_write_options wo;
    memset(&wo, 0, sizeof wo);
    wo.format = o->write_format >= 0 ? (jmf_output_format)o->write_format : JMF_OUT_AUTO;
    wo.draco = o->write_draco;
    char wpath[4200];
    snprintf(wpath, sizeof wpath, "%s/mesh.%s", wdir ? wdir : ".", o->write_ext);

    double start = platform_now_ms();
    long total_runs = 0;
    for (;;) {
        int timed = total_runs >= o->warmup;
        if (timed) {
            double elapsed = platform_now_ms() - start;
            if ((long)c->reps >= o->repeat && elapsed >= o->min_time * 1e3)
                break;
            if ((long)c->reps >= o->max_repeat)
                break;
        }
        jm_mesh mesh;
        jm_stats st;
        double t0 = platform_now_ms();
        js = jm_mesh_particles(ctx, &parts, &mesh, &st);
        double t1 = platform_now_ms();
        if (js != JM_OK) {
            snprintf(c->err, sizeof c->err, "jm_mesh_particles: %s", jm_status_message(js));
            goto out;
        }
        double tw = 0;
        if (c->has_write) {
            char err[300];
            size_t bytes = 0;
            double w0 = platform_now_ms();
            jmf_status ws = jmf_write_mesh(wpath, &mesh, &wo, &bytes, err, sizeof err);
            tw = platform_now_ms() - w0;
            bench_empty_dir(wdir);
            if (ws != JMF_OK) {
                snprintf(c->err, sizeof c->err, "write: %s", err);
                goto out;
            }
            c->write_bytes = bytes;
        }
        if (st.peak_bytes > c->lib_peak)
            c->lib_peak = st.peak_bytes;
        total_runs++;
        if (!timed) {
            start = platform_now_ms(); /* the floor counts timed runs only */
            continue;
        }
        c->last = st;
        if (bench_samples_push(&s[ST_TOTAL], st.ms_total) ||
            bench_samples_push(&s[ST_PREPARE], st.ms_prepare) ||
            bench_samples_push(&s[ST_FIELD], st.ms_field) ||
            bench_samples_push(&s[ST_EXTRACT], st.ms_extract) ||
            bench_samples_push(&s[ST_ATTR], st.ms_attributes) ||
            bench_samples_push(&s[ST_WALL], t1 - t0) || bench_samples_push(&s[ST_POST], st.ms_post) ||
            (c->has_write && bench_samples_push(&s[ST_WRITE], tw))) {
            snprintf(c->err, sizeof c->err, "out of memory recording samples");
            goto out;
        }
        c->reps++;
        if (c->reps == 1 || c->reps % 64 == 0)
            bench_progress(o, "bench: %s %s %s c%.3g %dT%s: run %zu", in->name,
                           cli_field_name(c->field), cli_method_name(c->method), c->cube,
                           c->threads, c->templates ? "" : " no-templates", c->reps);
    }
    for (int k = 0; k < ST_COUNT; k++)
        bench_summarize(&s[k], &c->st[k]);
    c->rss_peak = platform_peak_rss();
    if (o->flicker > 0 && bench_flicker(o, in, ctx, c) != 0)
        goto out;
    c->ok = 1;
out:
    bench_progress(o, NULL);
    jm_context_free(ctx);
    for (int k = 0; k < ST_COUNT; k++)
        free(s[k].v);
}

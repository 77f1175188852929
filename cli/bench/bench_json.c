/* bench_json.c - writes the results of `jetmesh bench` as one JSON document: machine, settings, every case with its stage summaries. */
#include "bench_report.h"

#include <math.h>

#include "bench_options.h"

static const char *const stage_key[ST_COUNT] = {"total", "prepare",  "field", "extract",
                                                "attributes", "wall", "write", "post"};

static void json_str(FILE *f, const char *s)
{
    fputc('"', f);
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        if (*p == '"' || *p == '\\')
            fprintf(f, "\\%c", *p);
        else if (*p == '\n')
            fputs("\\n", f);
        else if (*p == '\t')
            fputs("\\t", f);
        else if (*p < 0x20)
            fprintf(f, "\\u%04x", *p);
        else
            fputc(*p, f);
    }
    fputc('"', f);
}

static void json_num(FILE *f, double v)
{
    if (isfinite(v))
        fprintf(f, "%.9g", v);
    else
        fputs("null", f);
}

static void json_opt(FILE *f, double v) /* 0 = not applicable */
{
    if (v > 0)
        json_num(f, v);
    else
        fputs("null", f);
}

static void json_summary(FILE *f, const bench_summary *s)
{
    fputs("{\"median\": ", f);
    json_num(f, s->median);
    fputs(", \"min\": ", f);
    json_num(f, s->min);
    fputs(", \"p10\": ", f);
    json_num(f, s->p10);
    fputs(", \"q1\": ", f);
    json_num(f, s->q1);
    fputs(", \"q3\": ", f);
    json_num(f, s->q3);
    fputs(", \"p90\": ", f);
    json_num(f, s->p90);
    fputs(", \"max\": ", f);
    json_num(f, s->max);
    fputs(", \"mean\": ", f);
    json_num(f, s->mean);
    fputs("}", f);
}

static void json_case(FILE *f, const bench_opts *o, const bench_input *in, const bench_case *c)
{
    const char *kind = in->kind == IN_JET ? "jet" : in->kind == IN_BLOCK ? "block"
                                                   : in->kind == IN_SPRAY ? "spray" : "file";
    fputs("    {\"name\": ", f);
    json_str(f, in->name);
    fprintf(f, ", \"kind\": \"%s\"", kind);
    if (in->kind == IN_FILE) {
        fputs(", \"path\": ", f);
        json_str(f, in->path);
    } else if (in->kind == IN_JET)
        fprintf(f, ", \"frame\": %d", in->frame);
    else
        fprintf(f, ", \"n\": %zu, \"seed\": %llu", in->n, (unsigned long long)o->seed);
    fprintf(f, ",\n     \"field\": \"%s\", \"method\": \"%s\", \"radius\": ", cli_field_name(c->field),
            cli_method_name(c->method));
    json_num(f, o->radius);
    fputs(", \"cube_size\": ", f);
    json_num(f, c->cube);
    const jm_params *p = &c->params;
    if (c->ran && p->radius > 0) {
        fputs(", \"threshold\": ", f);
        json_num(f, p->threshold);
        fputs(", \"smoothing_length\": ", f);
        json_num(f, p->smoothing_length);
        fputs(", \"link_distance\": ", f);
        json_num(f, p->link_distance);
    }
    fprintf(f, ", \"threads\": %d, \"templates\": %s,\n", c->threads, c->templates ? "true" : "false");
    fprintf(f, "     \"status\": \"%s\", \"error\": ", c->ok ? "ok" : "failed");
    if (c->ok)
        fputs("null", f);
    else
        json_str(f, c->err);
    if (!c->ok) {
        fputs("}", f);
        return;
    }
    const jm_stats *st = &c->last;
    double sec = c->st[ST_TOTAL].median / 1e3;
    fprintf(f, ", \"repetitions\": %zu, \"warmup\": %ld, \"threads_used\": %d,\n", c->reps, o->warmup,
            st->threads);
    fprintf(f, "     \"particles\": %zu, \"isolated\": %zu, \"blocks\": %zu, \"cells\": %zu, "
               "\"vertices\": %zu, \"triangles\": %zu,\n",
            st->particles, st->isolated, st->blocks, st->cells, st->vertices, st->triangles);
    fputs("     \"particles_per_s\": ", f);
    json_num(f, sec > 0 ? (double)st->particles / sec : NAN);
    fputs(", \"triangles_per_s\": ", f);
    json_num(f, sec > 0 ? (double)st->triangles / sec : NAN);
    fprintf(f, ",\n     \"estimated_bytes\": %zu, \"lib_peak_bytes\": %zu, \"peak_rss_bytes\": %zu, "
               "\"peak_rss_reset\": %s,\n",
            st->estimated_bytes, c->lib_peak, c->rss_peak, c->rss_reset ? "true" : "false");
    fputs("     \"ms\": {\n", f);
    for (int k = 0; k < ST_COUNT; k++) {
        fprintf(f, "       \"%s\": ", stage_key[k]);
        if (k == ST_WRITE && !c->has_write)
            fputs("null", f);
        else
            json_summary(f, &c->st[k]);
        fputs(k + 1 < ST_COUNT ? ",\n" : "\n", f);
    }
    fputs("     },\n     \"write\": ", f);
    if (c->has_write) {
        fputs("{\"format\": ", f);
        json_str(f, o->write_ext);
        fprintf(f, ", \"bytes\": %zu, \"fraction_of_total\": ", c->write_bytes);
        double w = c->st[ST_WRITE].median, t = c->st[ST_TOTAL].median;
        json_num(f, w + t > 0 ? w / (w + t) : NAN);
        fputs("}", f);
    } else
        fputs("null", f);
    fputs(",\n     \"speedup_vs_1_thread\": ", f);
    json_opt(f, c->speedup_threads);
    fputs(", \"template_speedup\": ", f);
    json_opt(f, c->speedup_templates);
    fputs(",\n     \"flicker\": ", f);
    if (c->flicker_frames)
        fprintf(f, "{\"frames\": %d, \"p99_r\": %.6g, \"max_r\": %.6g}", c->flicker_frames, c->flicker_p99,
                c->flicker_max);
    else
        fputs("null", f);
    fputs("}", f);
}

void bench_json_doc(FILE *f, const bench_opts *o, const bench_machine *m, const bench_case *cases,
                    size_t ncases, int failed)
{
    fputs("{\n", f);
    fprintf(f, "  \"jetmesh_version\": \"%s\",\n", jm_version());
    fputs("  \"date\": ", f);
    json_str(f, m->date);
    fputs(",\n  \"machine\": {\"cpu_model\": ", f);
    json_str(f, m->cpu);
    fputs(", \"cpu_detail\": ", f);
    json_str(f, m->detail);
    fprintf(f, ", \"cores\": %d, \"memory_bytes\": %zu, \"os\": ", m->cores, m->memory);
    json_str(f, m->os);
    fputs("},\n  \"settings\": {\"min_time_s\": ", f);
    json_num(f, o->min_time);
    fprintf(f, ", \"repeat\": %ld, \"max_repeat\": %ld, \"warmup\": %ld, \"write\": ", o->repeat,
            o->max_repeat, o->warmup);
    if (o->write_format >= 0)
        json_str(f, o->write_ext);
    else
        fputs("null", f);
    fputs(", \"radius\": ", f);
    json_num(f, o->radius);
    fputs("},\n", f);
    fprintf(f, "  \"failed\": %d,\n  \"cases\": [\n", failed);
    for (size_t i = 0; i < ncases; i++) {
        json_case(f, o, &o->inputs[cases[i].input], &cases[i]);
        fputs(i + 1 < ncases ? ",\n" : "\n", f);
    }
    fputs("  ]\n}\n", f);
}

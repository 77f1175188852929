/* stats_svg.c - draws the per-frame stage times of a conversion as a standalone stacked-bar SVG chart. */
#include "stats.h"

#include <math.h>
#include <stdio.h>
#include <string.h>

#include "../../formats/atomic_file.h"
#include "../../lib/jetmesh.h"

#define STAGES 6

static const char *stage_name[STAGES] = {"read", "field", "extract", "attributes", "post", "write"};
static const char *stage_color[STAGES] = {"#4e79a7", "#f28e2b", "#e15759", "#76b7b2", "#b07aa1", "#59a14f"};

static void stage_times(const stats_record *r, double t[STAGES])
{
    t[0] = r->ms_read;
    t[1] = r->ms_field;
    t[2] = r->ms_extract;
    t[3] = r->ms_attributes;
    t[4] = r->ms_post;
    t[5] = r->ms_write;
    for (int i = 0; i < STAGES; i++)
        if (!(t[i] > 0))
            t[i] = 0;
}

static void xml_text(FILE *f, const char *s)
{
    for (const unsigned char *p = (const unsigned char *)s; *p; p++) {
        switch (*p) {
        case '&': fputs("&amp;", f); break;
        case '<': fputs("&lt;", f); break;
        case '>': fputs("&gt;", f); break;
        case '"': fputs("&quot;", f); break;
        case '\'': fputs("&apos;", f); break;
        default:
            if (*p < 0x20 && *p != '\t' && *p != '\n')
                fputc('?', f); /* not allowed in XML 1.0 */
            else if (*p >= 0x80)
                fputc('?', f); /* keep the file ASCII whatever the names hold */
            else
                fputc(*p, f);
        }
    }
}

/* A round step (1, 2 or 5 times a power of ten) giving about `ticks` ticks to top. */
static double nice_step(double top, int ticks)
{
    double raw = top / ticks;
    double p = pow(10.0, floor(log10(raw)));
    double m = raw / p;
    double s = m <= 1 ? 1 : m <= 2 ? 2 : m <= 5 ? 5 : 10;
    return s * p;
}

static void write_chart(FILE *f, const stats_log *log, const stats_summary *sum)
{
    const double W = 960, H = 480, left = 80, right = 170, top = 50, bottom = 60;
    const double pw = W - left - right, ph = H - top - bottom;
    size_t n = log->count;
    double ymax = 0;
    for (size_t i = 0; i < n; i++) {
        double t[STAGES], total = 0;
        stage_times(&log->items[i], t);
        for (int s = 0; s < STAGES; s++)
            total += t[s];
        if (total > ymax)
            ymax = total;
    }
    if (!(ymax > 0))
        ymax = 1;
    double step = nice_step(ymax, 5);
    double ytop = ceil(ymax / step - 1e-9) * step;
    if (ytop <= 0)
        ytop = step;

    fprintf(f,
            "<?xml version=\"1.0\" encoding=\"UTF-8\"?>\n"
            "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"%.0f\" height=\"%.0f\" "
            "viewBox=\"0 0 %.0f %.0f\" font-family=\"sans-serif\" font-size=\"12\">\n",
            W, H, W, H);
    fprintf(f, "<title>jetmesh %s: time per frame by stage</title>\n", JM_VERSION_STRING);
    fprintf(f, "<rect x=\"0\" y=\"0\" width=\"%.0f\" height=\"%.0f\" fill=\"#ffffff\"/>\n", W, H);
    fprintf(f,
            "<text x=\"%.1f\" y=\"24\" text-anchor=\"middle\" font-size=\"16\">Time per frame by "
            "stage: %zu frames, median %.2f ms, %.2f frames/s</text>\n",
            left + pw / 2, n, sum->ms_median, sum->frames_per_second);

    /* grid, y ticks and labels */
    fputs("<g stroke=\"#dddddd\" stroke-width=\"1\">\n", f);
    for (double v = step; v <= ytop + step * 1e-6; v += step) {
        double y = top + ph - v / ytop * ph;
        fprintf(f, "<line x1=\"%.1f\" y1=\"%.2f\" x2=\"%.1f\" y2=\"%.2f\"/>\n", left, y, left + pw, y);
    }
    fputs("</g>\n<g text-anchor=\"end\">\n", f);
    for (double v = 0; v <= ytop + step * 1e-6; v += step) {
        double y = top + ph - v / ytop * ph;
        fprintf(f, "<text x=\"%.1f\" y=\"%.2f\">%g</text>\n", left - 6, y + 4, v);
    }
    fputs("</g>\n", f);

    /* bars */
    double bw = n ? pw / (double)n : pw;
    double gap = bw > 4 ? bw * 0.15 : 0;
    for (size_t i = 0; i < n; i++) {
        const stats_record *r = &log->items[i];
        double t[STAGES], acc = 0;
        stage_times(r, t);
        double x = left + bw * (double)i + gap / 2;
        fputs("<g>", f);
        fprintf(f, "<title>frame %ld (", r->index);
        xml_text(f, r->input);
        fprintf(f, "): %s, read %.2f, field %.2f, extract %.2f, attributes %.2f, write %.2f ms</title>",
                stats_status_name(r->status), t[0], t[1], t[2], t[3], t[4]);
        for (int s = 0; s < STAGES; s++) {
            if (t[s] <= 0)
                continue;
            double y0 = top + ph - (acc + t[s]) / ytop * ph;
            double h = t[s] / ytop * ph;
            fprintf(f, "<rect x=\"%.2f\" y=\"%.2f\" width=\"%.2f\" height=\"%.2f\" fill=\"%s\"/>", x,
                    y0, bw - gap, h, stage_color[s]);
            acc += t[s];
        }
        if (r->status == STATS_FAILED)
            fprintf(f, "<text x=\"%.2f\" y=\"%.2f\" text-anchor=\"middle\" fill=\"#d62728\">x</text>",
                    x + (bw - gap) / 2, top + ph - acc / ytop * ph - 3);
        fputs("</g>\n", f);
    }

    /* axes, x labels */
    fprintf(f,
            "<g stroke=\"#000000\" stroke-width=\"1\"><line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" "
            "y2=\"%.1f\"/><line x1=\"%.1f\" y1=\"%.1f\" x2=\"%.1f\" y2=\"%.1f\"/></g>\n",
            left, top, left, top + ph, left, top + ph, left + pw, top + ph);
    size_t every = n > 20 ? (n + 19) / 20 : 1;
    fputs("<g text-anchor=\"middle\">\n", f);
    for (size_t i = 0; i < n; i += every) {
        double x = left + bw * ((double)i + 0.5);
        fprintf(f, "<line x1=\"%.2f\" y1=\"%.1f\" x2=\"%.2f\" y2=\"%.1f\" stroke=\"#000000\"/>", x,
                top + ph, x, top + ph + 4);
        fprintf(f, "<text x=\"%.2f\" y=\"%.1f\">%ld</text>\n", x, top + ph + 18,
                log->items[i].index);
    }
    fputs("</g>\n", f);
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" text-anchor=\"middle\">frame</text>\n", left + pw / 2,
            H - 14);
    fprintf(f,
            "<text x=\"20\" y=\"%.1f\" text-anchor=\"middle\" transform=\"rotate(-90 20 %.1f)\">"
            "time (ms)</text>\n",
            top + ph / 2, top + ph / 2);

    /* legend, top stage first like the stack */
    double lx = left + pw + 20, ly = top + 10;
    fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" font-weight=\"bold\">stage</text>\n", lx, ly);
    for (int s = STAGES - 1, row = 0; s >= 0; s--, row++) {
        double y = ly + 14 + row * 20;
        fprintf(f,
                "<rect x=\"%.1f\" y=\"%.1f\" width=\"12\" height=\"12\" fill=\"%s\"/>"
                "<text x=\"%.1f\" y=\"%.1f\">%s</text>\n",
                lx, y, stage_color[s], lx + 18, y + 10, stage_name[s]);
    }
    if (sum->failed)
        fprintf(f, "<text x=\"%.1f\" y=\"%.1f\" fill=\"#d62728\">x failed (%zu)</text>\n", lx,
                ly + 14 + STAGES * 20 + 10, sum->failed);
    fputs("</svg>\n", f);
}

int stats_write_svg(const char *path, const stats_log *log, const stats_summary *sum,
                    char *err, size_t errlen)
{
    jmf_atomic_file af;
    if (jmf_atomic_open(&af, path, err, errlen) != JMF_OK)
        return -1;
    write_chart(af.fp, log, sum);
    return jmf_atomic_commit(&af, err, errlen) == JMF_OK ? 0 : -1;
}

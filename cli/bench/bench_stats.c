/* bench_stats.c - collects timing samples and summarises them: median, min, max, mean, nearest-rank p10/q1/q3/p90. */
#include "bench_stats.h"

#include <math.h>
#include <stdlib.h>
#include <string.h>

int bench_samples_push(bench_samples *s, double x)
{
    if (s->n == s->cap) {
        size_t cap = s->cap ? s->cap * 2 : 64;
        double *v = realloc(s->v, cap * sizeof *v);
        if (!v)
            return -1;
        s->v = v;
        s->cap = cap;
    }
    s->v[s->n++] = x;
    return 0;
}

static int cmp_double(const void *a, const void *b)
{
    double x = *(const double *)a, y = *(const double *)b;
    return (x > y) - (x < y);
}

/* Nearest rank: the ceil(q n)-th smallest (1-based), at least the first. */
static double rank(const double *sorted, size_t n, double q)
{
    size_t k = (size_t)ceil(q * (double)n);
    if (k < 1)
        k = 1;
    if (k > n)
        k = n;
    return sorted[k - 1];
}

void bench_summarize(bench_samples *s, bench_summary *out)
{
    memset(out, 0, sizeof *out);
    if (s->n == 0)
        return;
    qsort(s->v, s->n, sizeof *s->v, cmp_double);
    size_t n = s->n;
    double sum = 0;
    for (size_t i = 0; i < n; i++)
        sum += s->v[i];
    out->mean = sum / (double)n;
    out->min = s->v[0];
    out->max = s->v[n - 1];
    out->median = n % 2 ? s->v[n / 2] : 0.5 * (s->v[n / 2 - 1] + s->v[n / 2]);
    out->p10 = rank(s->v, n, 0.10);
    out->p90 = rank(s->v, n, 0.90);
    out->q1 = rank(s->v, n, 0.25);
    out->q3 = rank(s->v, n, 0.75);
}

/* shard.c - --shard I/N: which of a run's frames this process converts when N processes share them. */
#include "shard.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "numbers.h"

#define SHARD_MAX 1000000L

static int from_slurm(shard_spec *out, char *err, size_t errlen)
{
    const char *id = getenv("SLURM_ARRAY_TASK_ID"), *count = getenv("SLURM_ARRAY_TASK_COUNT");
    const char *min = getenv("SLURM_ARRAY_TASK_MIN"), *step = getenv("SLURM_ARRAY_TASK_STEP");
    long i, n, lo = 0, st = 1;
    if (!id || !count) {
        snprintf(err, errlen,
                 "--shard slurm: SLURM_ARRAY_TASK_ID or SLURM_ARRAY_TASK_COUNT is not set (not a task "
                 "of a Slurm job array: submit with sbatch --array=0-N-1, or give --shard I/N)");
        return -1;
    }
    if (cli_parse_long(id, 0, 1L << 30, &i) != 0 || cli_parse_long(count, 1, SHARD_MAX, &n) != 0 ||
        (min && cli_parse_long(min, 0, 1L << 30, &lo) != 0) ||
        (step && cli_parse_long(step, 1, 1L << 30, &st) != 0)) {
        snprintf(err, errlen, "--shard slurm: unreadable SLURM_ARRAY_TASK_* variables (ID '%s', COUNT '%s')",
                 id, count);
        return -1;
    }
    if (st != 1 || i - lo < 0 || i - lo >= n) {
        snprintf(err, errlen,
                 "--shard slurm: the job array must be contiguous (task %ld, min %ld, count %ld, step %ld): "
                 "use --array=0-%ld, or give --shard I/N",
                 i, lo, n, st, n - 1);
        return -1;
    }
    out->index = i - lo;
    out->count = n;
    return 0;
}

int shard_parse(const char *text, shard_spec *out, char *err, size_t errlen)
{
    if (strcmp(text, "slurm") == 0)
        return from_slurm(out, err, errlen);
    const char *slash = strchr(text, '/');
    char idx[32];
    long i, n;
    size_t len = slash ? (size_t)(slash - text) : 0;
    if (!slash || len == 0 || len >= sizeof idx) {
        snprintf(err, errlen, "--shard is I/N (this process's share I of N, from 0) or slurm, not '%s'", text);
        return -1;
    }
    memcpy(idx, text, len);
    idx[len] = '\0';
    if (cli_parse_long(slash + 1, 1, SHARD_MAX, &n) != 0 || cli_parse_long(idx, 0, SHARD_MAX, &i) != 0 ||
        idx[0] == '+' || slash[1] == '+') {
        snprintf(err, errlen, "--shard is I/N with whole numbers 0 <= I < N <= %ld, not '%s'", SHARD_MAX, text);
        return -1;
    }
    if (i >= n) {
        snprintf(err, errlen, "--shard %s: I counts from 0, so it must be below N (0 to %ld)", text, n - 1);
        return -1;
    }
    out->index = i;
    out->count = n;
    return 0;
}

int shard_owns(const shard_spec *s, size_t pos)
{
    return s->count <= 1 || (long)(pos % (size_t)s->count) == s->index;
}

/* bench_machine.c - describes the machine a benchmark ran on: CPU model and vector extensions, cores, memory, OS and the UTC date. */
#include "bench_machine.h"

#include <stdio.h>
#include <stdlib.h>
#include <string.h>
#include <sys/utsname.h>
#include <time.h>

#include "../platform.h"
#include "../../lib/jetmesh_testing.h"

void bench_machine_info(bench_machine *m)
{
    memset(m, 0, sizeof *m);
    snprintf(m->cpu, sizeof m->cpu, "unknown");
    FILE *f = fopen("/proc/cpuinfo", "r");
    int family = -1, model = -1;
    if (f) {
        char line[512];
        while (fgets(line, sizeof line, f)) {
            if (family < 0 && strncmp(line, "cpu family", 10) == 0 && strchr(line, ':'))
                family = atoi(strchr(line, ':') + 1);
            if (model < 0 && strncmp(line, "model\t", 6) == 0 && strchr(line, ':'))
                model = atoi(strchr(line, ':') + 1);
            if (strncmp(line, "model name", 10) == 0 || strncmp(line, "Model", 5) == 0) {
                if (strcmp(m->cpu, "unknown") != 0)
                    continue; /* the first processor's */
                char *colon = strchr(line, ':');
                if (!colon)
                    continue;
                colon++;
                while (*colon == ' ' || *colon == '\t')
                    colon++;
                size_t n = strcspn(colon, "\r\n");
                while (n > 0 && colon[n - 1] == ' ')
                    n--;
                if (n > 0)
                    snprintf(m->cpu, sizeof m->cpu, "%.*s", (int)n, colon);
            }
        }
        fclose(f);
    }
    /* the vector level the library's kernels run (its one CPU probe) */
    const char *isa = jm_testing_cpu_name();
    if (family >= 0 && model >= 0)
        snprintf(m->detail, sizeof m->detail, "%s%sfamily %d model %d", isa, *isa ? ", " : "", family, model);
    else
        snprintf(m->detail, sizeof m->detail, "%s", isa);
    m->cores = platform_cores();
    m->memory = platform_physical_memory();
    struct utsname u;
    if (uname(&u) == 0)
        snprintf(m->os, sizeof m->os, "%.40s %.64s %.32s", u.sysname, u.release, u.machine);
    time_t now = time(NULL);
    struct tm tm;
    if (gmtime_r(&now, &tm))
        strftime(m->date, sizeof m->date, "%Y-%m-%dT%H:%M:%SZ", &tm);
}

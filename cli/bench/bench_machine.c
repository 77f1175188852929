/* bench_machine.c - describes the machine a benchmark ran on: CPU model, cores, memory, OS and the UTC date. */
#include "bench_machine.h"

#include <stdio.h>
#include <string.h>
#include <sys/utsname.h>
#include <time.h>

#include "../platform.h"

void bench_machine_info(bench_machine *m)
{
    memset(m, 0, sizeof *m);
    snprintf(m->cpu, sizeof m->cpu, "unknown");
    FILE *f = fopen("/proc/cpuinfo", "r");
    if (f) {
        char line[512];
        while (fgets(line, sizeof line, f)) {
            if (strncmp(line, "model name", 10) == 0 || strncmp(line, "Model", 5) == 0) {
                char *colon = strchr(line, ':');
                if (!colon)
                    continue;
                colon++;
                while (*colon == ' ' || *colon == '\t')
                    colon++;
                size_t n = strcspn(colon, "\r\n");
                while (n > 0 && colon[n - 1] == ' ')
                    n--;
                if (n > 0) {
                    snprintf(m->cpu, sizeof m->cpu, "%.*s", (int)n, colon);
                    break;
                }
            }
        }
        fclose(f);
    }
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

/* bench_machine.h - what `jetmesh bench` reports of the machine it ran on: CPU model and vector extensions, cores, memory, OS, date. */
#ifndef JETMESH_CLI_BENCH_MACHINE_H
#define JETMESH_CLI_BENCH_MACHINE_H

#include <stddef.h>

typedef struct bench_machine {
    char cpu[160];  /* "unknown" where /proc/cpuinfo does not say */
    char detail[64];  /* the widest vector paths the library picks here: "AVX-512", "AVX2 and FMA, no AVX-512",
                     * "SSE2", or "" off x86-64; and the CPU family and model where /proc/cpuinfo gives them
                     * (the hypervisor's model name often does not tell a Zen 2 from a Zen 5) */
    int cores;
    size_t memory;  /* physical, bytes */
    char os[160];   /* "sysname release machine"; "" where uname fails */
    char date[40];  /* now, UTC: 2026-01-31T12:00:00Z */
} bench_machine;

/** Fills m from /proc/cpuinfo, the platform, uname and the clock. */
void bench_machine_info(bench_machine *m);

#endif

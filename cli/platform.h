/* platform.h - what the CLI asks of the system: a monotonic clock, physical memory, peak RSS, core count. */
#ifndef JETMESH_CLI_PLATFORM_H
#define JETMESH_CLI_PLATFORM_H

#include <stddef.h>

/** Milliseconds on a monotonic clock (arbitrary origin). */
double platform_now_ms(void);

/** Physical memory in bytes (sysconf), or 0 if unknown. */
size_t platform_physical_memory(void);

/** Peak resident set size of this process in bytes (VmHWM from
 *  /proc/self/status, else getrusage ru_maxrss * 1024), or 0. */
size_t platform_peak_rss(void);

/** Online processors (at least 1). */
int platform_cores(void);

/** Creates the directories of path that do not exist (mkdir -p, mode 0777
 *  less umask); with parent_only, only those of its parent. 0, or -1 with errno. */
int platform_make_dirs(const char *path, int parent_only);

/** 1 if path exists (stat succeeds) and is a directory. */
int platform_is_dir(const char *path);

/** 1 if path exists and is a regular file. */
int platform_is_file(const char *path);

/** Formats bytes as "512 B", "12.3 MiB", "2.0 GiB" into buf. */
const char *platform_format_bytes(size_t bytes, char *buf, size_t len);

#endif

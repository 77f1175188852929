/* stale.c - removes the hidden temporaries that killed runs left beside this run's outputs. */
#include "stale.h"

#include "../formats/atomic_file.h"

#include <dirent.h>
#include <errno.h>
#include <signal.h>
#include <stdlib.h>
#include <string.h>
#include <sys/types.h>
#include <unistd.h>

static int cmp_str(const void *a, const void *b)
{
    return strcmp(*(char *const *)a, *(char *const *)b);
}

/* length of the directory part of path, with its '/' (0: none) */
static size_t dir_len(const char *path)
{
    const char *s = strrchr(path, '/');
    return s ? (size_t)(s - path) + 1 : 0;
}

static char *join(const char *dir, size_t dlen, const char *name, size_t nlen)
{
    char *p = malloc(dlen + nlen + 1);
    if (!p) return NULL;
    memcpy(p, dir, dlen);
    memcpy(p + dlen, name, nlen);
    p[dlen + nlen] = '\0';
    return p;
}

/* 1 if pid names no process here (a live one, ours or another user's, keeps its files) */
static int dead(long pid)
{
    if (pid <= 0 || pid == (long)getpid()) return 0;
    return kill((pid_t)pid, 0) != 0 && errno == ESRCH;
}

/* 1 if the temporary was written on this machine, where its pid means
 * something (the older form without a host was always local); another
 * host's, on a shared file system, is left to that host */
static int this_host(const jmf_temp_name *t)
{
    const char *h = jmf_atomic_host();
    return !t->host || (t->host_len == strlen(h) && memcmp(t->host, h, t->host_len) == 0);
}

/* scans directory dirpath (its first dlen bytes, "" for the current one)
 * for temporaries of the sorted names */
static size_t scan(char *const *names, size_t count, const char *dirpath, size_t dlen)
{
    char *dir = dlen ? join(dirpath, dlen, "", 0) : strdup(".");
    DIR *d = dir ? opendir(dir) : NULL;
    size_t removed = 0;
    if (!d) {
        free(dir);
        return 0;
    }
    struct dirent *e;
    while ((e = readdir(d)) != NULL) {
        const char *nm = e->d_name;
        jmf_temp_name t;
        if (!jmf_atomic_temp_parse(nm, &t) || !this_host(&t) || !dead(t.pid)) continue;
        char *final = join(dirpath, dlen, nm + 1, t.name_len);
        if (!final) break;
        if (bsearch(&final, names, count, sizeof *names, cmp_str)) {
            char *tmp = join(dirpath, dlen, nm, strlen(nm));
            if (tmp && unlink(tmp) == 0) removed++;
            free(tmp);
        }
        free(final);
    }
    closedir(d);
    free(dir);
    return removed;
}

/* path's directory and the STEM its temporaries carry
 * (jmf_atomic_temp_stem) when that is not its name; NULL when it is, or
 * out of memory (*nomem) */
static char *stem_path(const char *path, int *nomem)
{
    size_t dl = dir_len(path);
    char stem[JMF_TEMP_STEM_MAX + 1];
    size_t sl = jmf_atomic_temp_stem(path + dl, stem);
    if (strcmp(stem, path + dl) == 0) return NULL;
    char *p = join(path, dl, stem, sl);
    if (!p) *nomem = 1;
    return p;
}

size_t stale_remove(char *const *outputs, size_t n)
{
    /* names: the outputs and the .bin beside each .gltf, and the short
     * STEM paths of long names, whose temporaries carry those (made: those
     * allocated here), sorted; dirs: their distinct directories */
    char **names = malloc(4 * n * sizeof *names), **made = malloc(3 * n * sizeof *made);
    char **dirs = malloc(4 * n * sizeof *dirs);
    size_t m = 0, nmade = 0, ndirs = 0, removed = 0;
    int nomem = 0;
    if (!names || !made || !dirs) goto out;
    for (size_t i = 0; i < n; i++) {
        names[m++] = outputs[i];
        size_t len = strlen(outputs[i]);
        if (len > 5 && strcmp(outputs[i] + len - 5, ".gltf") == 0) {
            char *bin = join(outputs[i], len - 5, ".bin", 4);
            if (!bin) goto out;
            names[m++] = made[nmade++] = bin;
        }
    }
    for (size_t i = 0, full = m; i < full; i++) {
        char *sp = stem_path(names[i], &nomem);
        if (nomem) goto out;
        if (sp) names[m++] = made[nmade++] = sp;
    }
    qsort(names, m, sizeof *names, cmp_str);
    for (size_t i = 0; i < m; i++) {
        char *d = join(names[i], dir_len(names[i]), "", 0);
        if (!d) goto out;
        dirs[ndirs++] = d;
    }
    qsort(dirs, ndirs, sizeof *dirs, cmp_str);
    for (size_t i = 0; i < ndirs; i++)
        if (i == 0 || strcmp(dirs[i], dirs[i - 1]) != 0) removed += scan(names, m, dirs[i], strlen(dirs[i]));
out:
    for (size_t i = 0; i < ndirs; i++) free(dirs[i]);
    for (size_t i = 0; i < nmade; i++) free(made[i]);
    free(dirs);
    free(made);
    free(names);
    return removed;
}

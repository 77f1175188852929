/* atomic_file.c - writes an output through "DIR/.NAME.jetmesh-tmp-PID", fsyncs and renames it into place. */
#include "atomic_file.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stdlib.h>
#include <string.h>
#include <sys/stat.h>
#include <unistd.h>

/*
 * Temporaries still open are kept in a fixed table so that a signal handler
 * can unlink them with nothing but atomic loads and unlink(2). A slot is
 * FREE, FILLING (its path being copied in) or ARMED. A path too long for a
 * slot, or a 65th simultaneous output, is simply not registered: the write
 * still works, only the cleanup on a signal cannot see it.
 *
 * A target that exists and is neither a regular file nor a directory (a
 * FIFO, /dev/stdout, /dev/null, /dev/full) is written directly: renaming a
 * temporary over a device node would replace the device, which is never
 * what the user meant. Such a write is not atomic, but errors are still
 * reported. A symbolic link is followed: the file it points to is replaced
 * and the link kept.
 */
enum { SLOT_FREE = 0, SLOT_FILLING = 1, SLOT_ARMED = 2 };
#define PENDING_SLOTS 64
#define PENDING_PATH 4096

static struct pending_slot {
    atomic_int state;
    char path[PENDING_PATH];
} g_pending[PENDING_SLOTS];

static void pending_add(const char *path)
{
    size_t n = strlen(path);
    if (n >= PENDING_PATH) return;
    for (int i = 0; i < PENDING_SLOTS; i++) {
        int expect = SLOT_FREE;
        if (atomic_compare_exchange_strong(&g_pending[i].state, &expect, SLOT_FILLING)) {
            memcpy(g_pending[i].path, path, n + 1);
            atomic_store(&g_pending[i].state, SLOT_ARMED);
            return;
        }
    }
}

static int pending_find(const char *path)
{
    for (int i = 0; i < PENDING_SLOTS; i++)
        if (atomic_load(&g_pending[i].state) == SLOT_ARMED &&
            strcmp(g_pending[i].path, path) == 0)
            return i;
    return -1;
}

static void pending_remove(const char *path)
{
    int i = pending_find(path);
    if (i >= 0) atomic_store(&g_pending[i].state, SLOT_FREE);
}

void jmf_atomic_remove_pending(void)
{
    for (int i = 0; i < PENDING_SLOTS; i++)
        if (atomic_load(&g_pending[i].state) == SLOT_ARMED)
            unlink(g_pending[i].path);
}

static void set_err(char *err, size_t errlen, const char *fmt, ...)
{
    if (!err || errlen == 0) return;
    va_list ap;
    va_start(ap, fmt);
    vsnprintf(err, errlen, fmt, ap);
    va_end(ap);
}

static char *dup_str(const char *s)
{
    size_t n = strlen(s) + 1;
    char *d = malloc(n);
    if (d) memcpy(d, s, n);
    return d;
}

#define TEMP_TAG ".jetmesh-tmp-"

int jmf_atomic_temp_parse(const char *name, size_t *out_len, long *out_pid)
{
    const char *tag = name && name[0] == '.' ? strstr(name + 1, TEMP_TAG) : NULL;
    if (!tag || tag == name + 1) return 0;
    const char *d = tag + strlen(TEMP_TAG);
    size_t nd = strlen(d);
    if (nd == 0 || nd > 9 || strspn(d, "0123456789") != nd) return 0;
    *out_len = (size_t)(tag - name - 1);
    *out_pid = strtol(d, NULL, 10);
    return 1;
}

/* "DIR/NAME" -> "DIR/.NAME.jetmesh-tmp-PID"; NULL on allocation failure. */
static char *temp_name_for(const char *path)
{
    const char *slash = strrchr(path, '/');
    size_t dirlen = slash ? (size_t)(slash - path) + 1 : 0;
    const char *name = path + dirlen;
    char pid[32];
    int pn = snprintf(pid, sizeof pid, "%ld", (long)getpid());
    size_t len = dirlen + 1 + strlen(name) + strlen(TEMP_TAG) + (size_t)pn + 1;
    char *t = malloc(len);
    if (!t) return NULL;
    memcpy(t, path, dirlen);
    snprintf(t + dirlen, len - dirlen, ".%s" TEMP_TAG "%s", name, pid);
    return t;
}

static void release(jmf_atomic_file *af)
{
    free(af->final_path);
    free(af->temp_path);
    af->final_path = NULL;
    af->temp_path = NULL;
    af->fp = NULL;
    af->finished = 0;
}

jmf_status jmf_atomic_open(jmf_atomic_file *af, const char *path, char *err, size_t errlen)
{
    if (!af) return JMF_E_IO;
    memset(af, 0, sizeof *af);
    if (!path || !*path) {
        set_err(err, errlen, "empty output path");
        return JMF_E_IO;
    }
    size_t plen = strlen(path);
    if (path[plen - 1] == '/') {
        set_err(err, errlen, "%s: is a directory", path);
        return JMF_E_IO;
    }

    char *target = NULL;
    struct stat st;
    int exists = 0;
    mode_t keep_mode = 0;
    if (lstat(path, &st) == 0) {
        if (S_ISLNK(st.st_mode)) {
            char *real = realpath(path, NULL); /* NULL for a dangling link */
            if (real) target = real;
        }
        if (stat(target ? target : path, &st) == 0) {
            exists = 1;
            if (S_ISDIR(st.st_mode)) {
                set_err(err, errlen, "%s: is a directory", path);
                free(target);
                return JMF_E_IO;
            }
            keep_mode = st.st_mode & 07777;
        }
    } else if (errno != ENOENT) {
        set_err(err, errlen, "%s: %s", path, strerror(errno));
        return JMF_E_IO;
    }
    if (!target) target = dup_str(path);
    if (!target) {
        set_err(err, errlen, "%s: out of memory", path);
        return JMF_E_NOMEM;
    }
    af->final_path = target;

    if (exists && !S_ISREG(st.st_mode)) { /* device or FIFO: write in place */
        af->fp = fopen(target, "wb");
        if (!af->fp) {
            set_err(err, errlen, "%s: cannot open for writing: %s", path, strerror(errno));
            release(af);
            return JMF_E_IO;
        }
        return JMF_OK;
    }

    af->temp_path = temp_name_for(target);
    if (!af->temp_path) {
        set_err(err, errlen, "%s: out of memory", path);
        release(af);
        return JMF_E_NOMEM;
    }
    int fd = -1;
    for (int attempt = 0; attempt < 2 && fd < 0; attempt++) {
        fd = open(af->temp_path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
        if (fd >= 0 || errno != EEXIST) break;
        if (pending_find(af->temp_path) >= 0) {
            set_err(err, errlen, "%s: already being written by this process", path);
            release(af);
            return JMF_E_IO;
        }
        unlink(af->temp_path); /* left behind by a dead process with our pid */
    }
    if (fd < 0) {
        set_err(err, errlen, "%s: cannot create temporary file %s: %s", path,
                af->temp_path, strerror(errno));
        release(af);
        return JMF_E_IO;
    }
    pending_add(af->temp_path);
    if (exists) (void)fchmod(fd, keep_mode);
    af->fp = fdopen(fd, "wb");
    if (!af->fp) {
        int e = errno;
        close(fd);
        unlink(af->temp_path);
        pending_remove(af->temp_path);
        set_err(err, errlen, "%s: %s", path, strerror(e));
        release(af);
        return JMF_E_IO;
    }
    setvbuf(af->fp, NULL, _IOFBF, (size_t)1 << 20);
    return JMF_OK;
}

jmf_status jmf_atomic_write(jmf_atomic_file *af, const void *data, size_t n,
                            char *err, size_t errlen)
{
    if (n == 0) return JMF_OK;
    if (!af || !af->fp) {
        set_err(err, errlen, "write to a file that is not open");
        return JMF_E_IO;
    }
    errno = 0;
    if (fwrite(data, 1, n, af->fp) != n) {
        int e = errno;
        set_err(err, errlen, "%s: write failed: %s", af->final_path,
                e ? strerror(e) : "I/O error");
        return JMF_E_IO;
    }
    return JMF_OK;
}

/* fails af: message, temporary removed, af released */
static jmf_status fail_file(jmf_atomic_file *af, const char *what, int e, char *err, size_t errlen)
{
    set_err(err, errlen, "%s: %s: %s", af->final_path, what, strerror(e ? e : EIO));
    jmf_atomic_abort(af);
    return JMF_E_IO;
}

jmf_status jmf_atomic_finish(jmf_atomic_file *af, char *err, size_t errlen)
{
    if (!af || !af->fp) {
        set_err(err, errlen, "commit of a file that is not open");
        return JMF_E_IO;
    }
    errno = 0;
    if (fflush(af->fp) != 0) return fail_file(af, "write failed", errno, err, errlen);
    if (ferror(af->fp)) return fail_file(af, "write failed", EIO, err, errlen);
    off_t pos = ftello(af->fp);
    af->bytes = pos > 0 ? (size_t)pos : 0;
    af->finished = 1;
    return JMF_OK;
}

jmf_status jmf_atomic_publish(jmf_atomic_file *af, char *err, size_t errlen)
{
    if (!af || !af->finished || !af->fp) {
        set_err(err, errlen, "publish of a file that is not finished");
        return JMF_E_IO;
    }
    const char *what = NULL;
    int e = 0;
    errno = 0;
    if (!af->no_sync && af->temp_path && fsync(fileno(af->fp)) != 0) {
        what = "fsync failed";
        e = errno;
    }
    errno = 0;
    if (fclose(af->fp) != 0 && !what) {
        what = "close failed";
        e = errno ? errno : EIO;
    }
    af->fp = NULL;
    if (!what && af->temp_path && rename(af->temp_path, af->final_path) != 0) {
        what = "rename failed";
        e = errno;
    }
    if (what) return fail_file(af, what, e, err, errlen);
    if (af->temp_path) pending_remove(af->temp_path);
    release(af);
    return JMF_OK;
}

jmf_status jmf_atomic_commit(jmf_atomic_file *af, char *err, size_t errlen)
{
    jmf_status st = jmf_atomic_finish(af, err, errlen);
    return st ? st : jmf_atomic_publish(af, err, errlen);
}

void jmf_atomic_abort(jmf_atomic_file *af)
{
    if (!af) return;
    if (af->fp) fclose(af->fp);
    af->fp = NULL;
    if (af->temp_path) {
        unlink(af->temp_path);
        pending_remove(af->temp_path);
    }
    release(af);
}

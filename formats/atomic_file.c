/* atomic_file.c - writes an output through a hidden temporary beside it, fsyncs and renames it into place. */
#include "atomic_file.h"

#include <errno.h>
#include <fcntl.h>
#include <limits.h>
#include <stdarg.h>
#include <pthread.h>
#include <stdint.h>
#include <stdlib.h>
#include <string.h>
#include <sys/random.h>
#include <sys/stat.h>
#include <time.h>
#include <unistd.h>

/*
 * Temporaries and signals. Every temporary this process has on disk is in
 * one registry, guarded by one mutex. Creating a temporary (open with
 * O_EXCL) and registering it is a single step under that mutex, and so are
 * renaming one into place and removing one: nothing can create, rename or
 * unlink a temporary between the moment the registry is closed and the
 * process's death. jmf_atomic_shutdown() (called by the CLI's signal
 * thread, cli/signals.c) takes the mutex, marks the registry closed and
 * unlinks every registered temporary; from then on opens and renames fail
 * ("stopping"). So whatever the threads are doing when a signal arrives,
 * no temporary outlives the process and every output is either the old
 * file or the complete new one. The registry grows as needed: a
 * temporary that cannot be registered is not created.
 *
 * A target that exists and is neither a regular file nor a directory (a
 * FIFO, /dev/stdout, /dev/null, /dev/full) is written directly: renaming a
 * temporary over a device node would replace the device, which is never
 * what the user meant. Such a write is not atomic, but errors are still
 * reported. A symbolic link is followed: the file it points to is replaced
 * and the link kept; a dangling one alike, its target created (as a
 * shell's redirection does; issue 30: it was replaced by a file while a
 * live one was written through); a loop of links is an error.
 *
 * Names: "DIR/.NAME.jetmesh-tmp-HOST-PID-RAND", HOST this machine's name
 * (letters, digits, '.', '_' and '-' kept, others as '_', at most 64),
 * RAND 8 hex digits drawn once per process: shards on different hosts
 * sharing a network file system never collide, and a later run on the same
 * host can tell a dead process's leftovers (cli/stale.c). NAME is the
 * output's name up to JMF_TEMP_STEM_MAX bytes; a longer one is cut to its
 * first bytes and "~" and a hash of the whole (jmf_atomic_temp_stem), so
 * the temporary's name stays within the 255 bytes file systems allow
 * whatever the output's (issue 30: a 225-byte output name failed).
 */
static pthread_mutex_t g_lock = PTHREAD_MUTEX_INITIALIZER;
static char **g_pending;    /* temporaries on disk, registered */
static size_t g_npending, g_cappending;
static int g_closed;        /* jmf_atomic_shutdown ran */

/* under g_lock */
static int pending_find(const char *path)
{
    for (size_t i = 0; i < g_npending; i++)
        if (strcmp(g_pending[i], path) == 0) return (int)i;
    return -1;
}

/* under g_lock; 0 on allocation failure */
static int pending_add(const char *path)
{
    if (g_npending == g_cappending) {
        size_t nc = g_cappending ? 2 * g_cappending : 16;
        char **p = realloc(g_pending, nc * sizeof *p);
        if (!p) return 0;
        g_pending = p;
        g_cappending = nc;
    }
    size_t n = strlen(path) + 1;
    char *d = malloc(n);
    if (!d) return 0;
    memcpy(d, path, n);
    g_pending[g_npending++] = d;
    return 1;
}

/* under g_lock */
static void pending_remove(const char *path)
{
    int i = pending_find(path);
    if (i < 0) return;
    free(g_pending[i]);
    g_pending[i] = g_pending[--g_npending];
}

void jmf_atomic_shutdown(void)
{
    pthread_mutex_lock(&g_lock);
    g_closed = 1;
    for (size_t i = 0; i < g_npending; i++) {
        unlink(g_pending[i]);
        free(g_pending[i]);
    }
    g_npending = 0;
    pthread_mutex_unlock(&g_lock);
}

/* ---- names */
static pthread_once_t g_name_once = PTHREAD_ONCE_INIT;
static char g_host[65];
static char g_rand[9];

static void make_name_parts(void)
{
    char h[256] = "";
    if (gethostname(h, sizeof h - 1) != 0) h[0] = '\0';
    h[sizeof h - 1] = '\0';
    size_t k = 0;
    for (size_t i = 0; h[i] && k < sizeof g_host - 1; i++) {
        char c = h[i];
        int ok = (c >= 'a' && c <= 'z') || (c >= 'A' && c <= 'Z') || (c >= '0' && c <= '9') ||
                 c == '.' || c == '_' || c == '-';
        g_host[k++] = ok ? c : '_';
    }
    if (k == 0) memcpy(g_host, "localhost", (k = 9));
    g_host[k] = '\0';
    uint32_t r = 0;
    if (getrandom(&r, sizeof r, GRND_NONBLOCK) != (ssize_t)sizeof r) {
        struct timespec ts;
        clock_gettime(CLOCK_REALTIME, &ts);
        r = (uint32_t)ts.tv_nsec * 2654435761u ^ (uint32_t)ts.tv_sec ^ (uint32_t)getpid() * 40503u;
    }
    snprintf(g_rand, sizeof g_rand, "%08x", (unsigned)r);
}

const char *jmf_atomic_host(void)
{
    pthread_once(&g_name_once, make_name_parts);
    return g_host;
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

static int all_of(const char *s, size_t n, const char *set)
{
    for (size_t i = 0; i < n; i++)
        if (!strchr(set, s[i])) return 0;
    return 1;
}

int jmf_atomic_temp_parse(const char *name, jmf_temp_name *out)
{
    const char *tag = name && name[0] == '.' ? strstr(name + 1, TEMP_TAG) : NULL;
    if (!tag || tag == name + 1) return 0;
    const char *d = tag + strlen(TEMP_TAG);
    size_t nd = strlen(d);
    static const char digits[] = "0123456789";
    jmf_temp_name t;
    memset(&t, 0, sizeof t);
    t.name_len = (size_t)(tag - name - 1);
    if (nd >= 1 && nd <= 9 && all_of(d, nd, digits)) { /* before 0.4: ".NAME.jetmesh-tmp-PID" */
        t.pid = strtol(d, NULL, 10);
    } else {
        /* HOST-PID-RAND, parsed from the right: HOST may hold '-' */
        if (nd < 12 || d[nd - 9] != '-' || !all_of(d + nd - 8, 8, "0123456789abcdef")) return 0;
        size_t end = nd - 9, p = end;
        while (p > 0 && strchr(digits, d[p - 1])) p--;
        if (p == end || end - p > 9 || p < 2 || d[p - 1] != '-') return 0;
        t.pid = strtol(d + p, NULL, 10);
        t.host = d;
        t.host_len = p - 1;
    }
    *out = t;
    return 1;
}

/* the bytes of a long name kept before its hash */
#define TEMP_STEM_KEEP 100

size_t jmf_atomic_temp_stem(const char *name, char *out)
{
    size_t n = strlen(name);
    if (n <= JMF_TEMP_STEM_MAX) {
        memcpy(out, name, n + 1);
        return n;
    }
    /* FNV-1a, 64 bits, of the whole name */
    uint64_t h = 14695981039346656037ull;
    for (size_t i = 0; i < n; i++) h = (h ^ (unsigned char)name[i]) * 1099511628211ull;
    size_t keep = TEMP_STEM_KEEP;
    while (keep > 0 && ((unsigned char)name[keep] & 0xc0) == 0x80) keep--; /* not inside a UTF-8 character */
    memcpy(out, name, keep);
    return keep + (size_t)snprintf(out + keep, JMF_TEMP_STEM_MAX + 1 - keep, "~%016llx", (unsigned long long)h);
}

/* "DIR/NAME" -> "DIR/.STEM.jetmesh-tmp-HOST-PID-RAND"; NULL on allocation failure. */
static char *temp_name_for(const char *path)
{
    jmf_atomic_host();
    const char *slash = strrchr(path, '/');
    size_t dirlen = slash ? (size_t)(slash - path) + 1 : 0;
    char stem[JMF_TEMP_STEM_MAX + 1];
    jmf_atomic_temp_stem(path + dirlen, stem);
    char suffix[128];
    int sn = snprintf(suffix, sizeof suffix, "%s-%ld-%s", g_host, (long)getpid(), g_rand);
    size_t len = dirlen + 1 + strlen(stem) + strlen(TEMP_TAG) + (size_t)sn + 1;
    char *t = malloc(len);
    if (!t) return NULL;
    memcpy(t, path, dirlen);
    snprintf(t + dirlen, len - dirlen, ".%s" TEMP_TAG "%s", stem, suffix);
    return t;
}

/* The missing file at the end of a chain of symbolic links from path (a
 * dangling link's target; a relative link is relative to its directory);
 * NULL when the chain loops, ends in an existing file, or cannot be read
 * (errno says why: ELOOP for a loop). */
static char *dangling_target(const char *path)
{
    char *cur = dup_str(path);
    for (int hops = 0; cur && hops < 40; hops++) {
        struct stat st;
        if (lstat(cur, &st) != 0) {
            if (errno == ENOENT) return cur;
            break;
        }
        if (!S_ISLNK(st.st_mode)) {
            errno = EEXIST;
            break;
        }
        char to[4096];
        ssize_t n = readlink(cur, to, sizeof to - 1);
        if (n < 0) break;
        to[n] = '\0';
        const char *slash = strrchr(cur, '/');
        size_t dl = to[0] == '/' || !slash ? 0 : (size_t)(slash - cur) + 1;
        char *next = malloc(dl + (size_t)n + 1);
        if (next) {
            memcpy(next, cur, dl);
            memcpy(next + dl, to, (size_t)n + 1);
        }
        free(cur);
        cur = next;
        errno = ELOOP;
    }
    free(cur);
    return NULL;
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

/* unlinks and unregisters a temporary, in one step */
static void remove_temp(const char *temp)
{
    pthread_mutex_lock(&g_lock);
    if (pending_find(temp) >= 0) {
        unlink(temp);
        pending_remove(temp);
    }
    pthread_mutex_unlock(&g_lock);
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
            target = real ? real : dangling_target(path);
            if (!target) {
                set_err(err, errlen, "%s: a symbolic link that cannot be followed: %s", path, strerror(errno));
                return JMF_E_IO;
            }
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
    } else if (errno != ENOENT && errno != ENAMETOOLONG) {
        /* a name too long for the file system cannot exist: its temporary's
         * is short, and a rename into place says so (a scratch file that is
         * never renamed, "NAME.glb.frames", works) */
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
    /* create and register in one step (see the top of the file) */
    int fd = -1, e = 0;
    const char *why = NULL;
    pthread_mutex_lock(&g_lock);
    if (g_closed) {
        why = "stopping on a signal";
    } else if (pending_find(af->temp_path) >= 0) {
        why = "already being written by this process";
    } else {
        for (int attempt = 0; attempt < 2 && fd < 0; attempt++) {
            fd = open(af->temp_path, O_WRONLY | O_CREAT | O_EXCL | O_CLOEXEC, 0666);
            if (fd >= 0 || errno != EEXIST) break;
            unlink(af->temp_path); /* a dead process's, with our host, pid and draw */
        }
        e = errno;
        if (fd >= 0 && !pending_add(af->temp_path)) {
            close(fd);
            unlink(af->temp_path);
            fd = -1;
            e = ENOMEM;
        }
    }
    pthread_mutex_unlock(&g_lock);
    if (why) {
        set_err(err, errlen, "%s: %s", path, why);
        release(af);
        return JMF_E_IO;
    }
    if (fd < 0) {
        set_err(err, errlen, "%s: cannot create temporary file %s: %s", path,
                af->temp_path, strerror(e));
        release(af);
        return e == ENOMEM ? JMF_E_NOMEM : JMF_E_IO;
    }
    if (exists) (void)fchmod(fd, keep_mode);
    af->fp = fdopen(fd, "wb");
    if (!af->fp) {
        e = errno;
        close(fd);
        remove_temp(af->temp_path);
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

/* fsync (unless no_sync) and close: the first half of a publish */
static jmf_status sync_close(jmf_atomic_file *af, char *err, size_t errlen)
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
    return what ? fail_file(af, what, e, err, errlen) : JMF_OK;
}

jmf_status jmf_atomic_publish_all(jmf_atomic_file *afs, int n, char *err, size_t errlen)
{
    jmf_status st = JMF_OK;
    for (int i = 0; i < n; i++) {
        if (!st) st = sync_close(&afs[i], err, errlen);
        else jmf_atomic_abort(&afs[i]);
    }
    if (st) {
        for (int i = 0; i < n; i++) jmf_atomic_abort(&afs[i]);
        return st;
    }
    /* every rename of the group under the lock: a signal sees all or none */
    const char *what = NULL;
    int e = 0, bad = -1;
    pthread_mutex_lock(&g_lock);
    if (g_closed) {
        what = "stopping on a signal";
        bad = 0;
    }
    for (int i = 0; i < n && !what; i++) {
        jmf_atomic_file *af = &afs[i];
        if (!af->temp_path) continue; /* written in place */
        if (rename(af->temp_path, af->final_path) != 0) {
            what = "rename failed";
            e = errno;
            bad = i;
            break;
        }
        pending_remove(af->temp_path);
    }
    pthread_mutex_unlock(&g_lock);
    if (what) {
        set_err(err, errlen, "%s: %s%s%s", afs[bad].final_path, what, e ? ": " : "", e ? strerror(e) : "");
        for (int i = bad; i < n; i++) jmf_atomic_abort(&afs[i]);
        for (int i = 0; i < bad; i++) release(&afs[i]);
        return JMF_E_IO;
    }
    for (int i = 0; i < n; i++) release(&afs[i]);
    return JMF_OK;
}

jmf_status jmf_atomic_publish(jmf_atomic_file *af, char *err, size_t errlen)
{
    if (!af) {
        set_err(err, errlen, "publish of a file that is not finished");
        return JMF_E_IO;
    }
    return jmf_atomic_publish_all(af, 1, err, errlen);
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
    if (af->temp_path) remove_temp(af->temp_path);
    release(af);
}

/* test_realtime.c - a reused context meshes the next frame without any heap allocation (the paper's real-time embedding), whatever its thread count. */
#include <setjmp.h>
#include <stdarg.h>
#include <stdatomic.h>
#include <stddef.h>
#include <stdint.h>
#include <cmocka.h>
#include <stdio.h>
#include <stdlib.h>
#include <string.h>

#include "../lib/jetmesh.h"
#include "../lib/core/internal.h" /* white-box: jm_heap_calls, the library's own count */

/* Every call to the C library's allocator and to the kernel's mappings in
 * this process is counted while `counting` is set: the library's own
 * (jm_heap_calls) and any the C library makes for it (qsort allocates
 * above 1 KiB). The sanitizers bring their own allocator: there only the
 * library's count is checked. */
static atomic_int counting;
static atomic_size_t calls; /* atomic: the workers allocate at once during the first frames */
#if !defined(__SANITIZE_ADDRESS__) && !defined(__SANITIZE_THREAD__)
#include <sys/mman.h>
#define INTERPOSED 1
extern void *__libc_malloc(size_t);
extern void *__libc_calloc(size_t, size_t);
extern void *__libc_realloc(void *, size_t);
extern void *__libc_memalign(size_t, size_t);
extern void __libc_free(void *);
extern void *__mmap(void *, size_t, int, int, int, off_t);
extern int __munmap(void *, size_t);
static void note(void)
{
    if (atomic_load_explicit(&counting, memory_order_relaxed))
        atomic_fetch_add_explicit(&calls, 1, memory_order_relaxed);
}
void *malloc(size_t n)
{
    note();
    return __libc_malloc(n);
}
void *calloc(size_t a, size_t b)
{
    note();
    return __libc_calloc(a, b);
}
void *realloc(void *p, size_t n)
{
    note();
    return __libc_realloc(p, n);
}
void free(void *p)
{
    if (p) note();
    __libc_free(p);
}
int posix_memalign(void **p, size_t align, size_t n)
{
    note();
    *p = __libc_memalign(align, n);
    return *p ? 0 : 12;
}
void *aligned_alloc(size_t align, size_t n)
{
    note();
    return __libc_memalign(align, n);
}
void *mmap(void *a, size_t n, int prot, int flags, int fd, off_t off)
{
    note();
    return __mmap(a, n, prot, flags, fd, off);
}
int munmap(void *a, size_t n)
{
    note();
    return __munmap(a, n);
}
#endif

static float *read_jet(int frame, size_t *n)
{
    const char *root = getenv("JETMESH_ROOT");
    char path[1024], line[256];
    snprintf(path, sizeof path, "%s/samples/jet/jet_%03d.csv", root ? root : ".", frame);
    FILE *f = fopen(path, "r");
    if (!f) fail_msg("cannot read %s", path);
    float *p = malloc(3 * 4096 * sizeof *p);
    *n = 0;
    while (fgets(line, sizeof line, f) && *n < 4096)
        if (sscanf(line, "%f,%f,%f", &p[3 * *n], &p[3 * *n + 1], &p[3 * *n + 2]) == 3) (*n)++;
    fclose(f);
    assert_true(*n > 100);
    return p;
}

/* heap calls (the C library's where counted, else the library's own)
 * while meshing one frame */
static size_t frame_calls(jm_context *ctx, const float *xyz, size_t n, size_t *nv)
{
    jm_particles in = {xyz, n, 0, NULL};
    jm_mesh m;
    const size_t own = jm_heap_calls();
    calls = 0;
    counting = 1;
    const jm_status s = jm_mesh_particles(ctx, &in, &m, NULL);
    counting = 0;
    assert_int_equal(s, JM_OK);
    *nv = m.vertex_count;
    const size_t mine = jm_heap_calls() - own;
#ifdef INTERPOSED
    if (mine > calls) fail_msg("the library counted %zu heap calls, the C library %zu", mine, calls);
    return calls;
#else
    return mine;
#endif
}

/* The paper's jet (frames 99 and 98), both fields, cube r/2 and r, one
 * thread and two: after a context has meshed a frame once, meshing it again
 * allocates nothing; after both frames once, either again allocates
 * nothing. */
static void test_next_frame_allocates_nothing(void **state)
{
    (void)state;
    size_t n99, n98, nv;
    float *a = read_jet(99, &n99), *b = read_jet(98, &n98);
    for (int field = JM_FIELD_METASPHERE; field <= JM_FIELD_SPH; field++)
        for (int threads = 1; threads <= 2; threads++)
            for (int k = 0; k < 2; k++) {
                jm_params p = {0};
                p.radius = 0.025f;
                p.cube_size = k ? 1.0f : 0.5f;
                p.field = (jm_field)field;
                p.threads = threads;
                jm_context *ctx = NULL;
                assert_int_equal(jm_context_create(&p, &ctx), JM_OK);
                const size_t first = frame_calls(ctx, a, n99, &nv);
                assert_true(first > 0); /* the counting counts */
                size_t again = frame_calls(ctx, a, n99, &nv);
                if (again)
                    fail_msg("field %d, cube %g, %d threads: the same frame again made %zu heap calls (%zu vertices)",
                             field, (double)p.cube_size, threads, again, nv);
                (void)frame_calls(ctx, b, n98, &nv);
                for (int r = 0; r < 2; r++) {
                    again = frame_calls(ctx, a, n99, &nv) + frame_calls(ctx, b, n98, &nv);
                    if (again)
                        fail_msg("field %d, cube %g, %d threads: frames 99 and 98 again made %zu heap calls", field,
                                 (double)p.cube_size, threads, again);
                }
                jm_context_free(ctx);
            }
    free(a);
    free(b);
}

int main(void)
{
    const struct CMUnitTest tests[] = {
        cmocka_unit_test(test_next_frame_allocates_nothing),
    };
    return cmocka_run_group_tests(tests, NULL, NULL);
}

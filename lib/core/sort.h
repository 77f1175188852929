/* sort.h - an in-place sort that allocates nothing (glibc's qsort mallocs above 1 KiB), for the frame's keys. */
#ifndef JETMESH_SORT_H
#define JETMESH_SORT_H
#include <stddef.h>

/* JM_SORT_DEFINE(name, T, less) defines static void name(T *a, size_t n):
 * a sorted in place by less(const T *x, const T *y) (a strict order);
 * introsort: quicksort on the median of three, heapsort past 2 log2 n
 * levels, insertion sort below 16. Not stable: for distinct keys (every
 * use here) the order is the only one. */
#define JM_SORT_DEFINE(name, T, less)                                                                      \
    static void name##_sift(T *a, size_t i, size_t n)                                                    \
    {                                                                                                    \
        for (;;) {                                                                                       \
            size_t c = 2 * i + 1;                                                                        \
            if (c >= n) return;                                                                          \
            if (c + 1 < n && less(&a[c], &a[c + 1])) c++;                                                \
            if (!less(&a[i], &a[c])) return;                                                             \
            T t_ = a[i];                                                                                 \
            a[i] = a[c];                                                                                 \
            a[c] = t_;                                                                                   \
            i = c;                                                                                       \
        }                                                                                                \
    }                                                                                                    \
    static void name##_rec(T *a, size_t n, int depth)                                                    \
    {                                                                                                    \
        while (n > 16) {                                                                                 \
            if (depth-- == 0) {                                                                          \
                for (size_t i = n / 2; i-- > 0;) name##_sift(a, i, n);                                   \
                for (size_t e = n; e-- > 1;) {                                                           \
                    T t_ = a[0];                                                                         \
                    a[0] = a[e];                                                                         \
                    a[e] = t_;                                                                           \
                    name##_sift(a, 0, e);                                                                \
                }                                                                                        \
                return;                                                                                  \
            }                                                                                            \
            /* median of first, middle, last into a[0] */                                               \
            size_t m = n / 2;                                                                            \
            T t_;                                                                                        \
            if (less(&a[m], &a[0])) { t_ = a[m]; a[m] = a[0]; a[0] = t_; }                               \
            if (less(&a[n - 1], &a[m])) { t_ = a[m]; a[m] = a[n - 1]; a[n - 1] = t_; }                   \
            if (less(&a[m], &a[0])) { t_ = a[m]; a[m] = a[0]; a[0] = t_; }                               \
            t_ = a[0]; a[0] = a[m]; a[m] = t_;                                                           \
            size_t i = 0, j = n;                                                                         \
            for (;;) {                                                                                   \
                do i++; while (i < n && less(&a[i], &a[0]));                                             \
                do j--; while (less(&a[0], &a[j]));                                                      \
                if (i >= j) break;                                                                       \
                t_ = a[i]; a[i] = a[j]; a[j] = t_;                                                       \
            }                                                                                            \
            t_ = a[0]; a[0] = a[j]; a[j] = t_;                                                           \
            /* the smaller side by recursion, the larger by the loop */                                 \
            if (j < n - j - 1) {                                                                         \
                name##_rec(a, j, depth);                                                                 \
                a += j + 1;                                                                              \
                n -= j + 1;                                                                              \
            } else {                                                                                     \
                name##_rec(a + j + 1, n - j - 1, depth);                                                 \
                n = j;                                                                                   \
            }                                                                                            \
        }                                                                                                \
        for (size_t i = 1; i < n; i++)                                                                   \
            for (size_t k = i; k > 0 && less(&a[k], &a[k - 1]); k--) {                                   \
                T t_ = a[k];                                                                             \
                a[k] = a[k - 1];                                                                         \
                a[k - 1] = t_;                                                                           \
            }                                                                                            \
    }                                                                                                    \
    static void name(T *a, size_t n)                                                                     \
    {                                                                                                    \
        int depth = 0;                                                                                   \
        for (size_t k = n; k > 1; k >>= 1) depth += 2;                                                   \
        name##_rec(a, n, depth);                                                                         \
    }
#endif

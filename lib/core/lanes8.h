/* lanes8.h - 8 float lanes as GCC vectors, each lane the scalar code's IEEE operations in its order: the same bits wherever the build and the CPU lower them (AVX2, SSE2, plain C). */
#ifndef JETMESH_LANES8_H
#define JETMESH_LANES8_H
#include <math.h>
#include <stdint.h>
#include <string.h>

/* Only for static functions inlined into one caller (cloned per CPU with
 * JM_KERNEL_*): a vector never crosses a function's boundary, so the
 * note GCC gives about their ABI without AVX is moot (the Makefile passes
 * -Wno-psabi to the files that include this). No contraction into fused
 * multiply-adds: ISO C mode. */
typedef float v8f __attribute__((vector_size(32)));
typedef int32_t v8i __attribute__((vector_size(32)));
#define JM_LANES 8
#define JM_L8 static inline __attribute__((always_inline))

JM_L8 v8f bc(float x) { return (v8f){x, x, x, x, x, x, x, x}; }
/* m ? a : b, lane by lane (m: 0 or -1) */
JM_L8 v8f sel(v8i m, v8f a, v8f b) { return (v8f)((m & (v8i)a) | (~m & (v8i)b)); }
JM_L8 v8f vabs(v8f x) { return (v8f)((v8i)x & 0x7fffffff); }
JM_L8 v8f vsqrt(v8f x)
{
    v8f r;
    for (int l = 0; l < JM_LANES; l++) r[l] = sqrtf(x[l]);
    return r;
}
JM_L8 int any(v8i m)
{
    uint64_t x[4];
    memcpy(x, &m, sizeof x);
    return (x[0] | x[1] | x[2] | x[3]) != 0;
}
/* jm_cos_quarter and jm_sin_quarter (field.h), term by term */
JM_L8 v8f vcos(v8f t)
{
    const v8f t2 = t * t;
    return 1.0f + t2 * (-0.5f + t2 * (1.0f / 24 + t2 * (-1.0f / 720 + t2 * (1.0f / 40320 - t2 * (1.0f / 3628800)))));
}
JM_L8 v8f vsin(v8f t)
{
    const v8f t2 = t * t;
    return t * (1.0f + t2 * (-1.0f / 6 + t2 * (1.0f / 120 + t2 * (-1.0f / 5040 + t2 * (1.0f / 362880)))));
}
#endif

/* metanormal_simd.h - the metasphere normal kernels in one vector width (W 8: AVX2, W 16: AVX-512), included once per width by metanormal.c. */
/* The width's dialect (metanormal.c defines them): VT##W the vector and MT##W
 * the mask types, TGT##W the target, B##W(x) a broadcast, LANES##W(k, s, e)
 * the mask of lanes k + i in [s, e), CMP##W, AND##W, ANY##W (a lane set),
 * SEL##W(m, a, b) (m ? b : a), KEEPMAX##W(old, m, v) (m ? max(v, old) :
 * old) and ADDM##W(old, m, x) (m ? old + x : old); arithmetic through the
 * width's intrinsic prefix PFX##W. Every lane does the operations of the
 * plain C ball_c and link_c in the same order: the same bits at any width. */
#define MN_CAT_(a, b) a##b
#define MN_CAT(a, b) MN_CAT_(a, b)
#define MN_V MN_CAT(VT, W)
#define MN_M MN_CAT(MT, W)
#define MN_B(x) MN_CAT(B, W)(x)
#define MN_OP(op) MN_CAT(MN_CAT(PFX, W), op)
#define MN_CMP MN_CAT(CMP, W)
#define MN_AND MN_CAT(AND, W)
#define MN_ANY MN_CAT(ANY, W)

/* runs of W sorted points from each row's start (the last shifted back to
 * end at the array's end); lanes outside [s, e) are masked off, so each
 * vertex gets each piece once */
#define MN_FOR_RUNS(P, lo, hi, k, lanes, ...)                                                              \
    FOR_PART_VERTICES(P, lo, hi, s_, e_, {                                                               \
        for (size_t r_ = s_; r_ < e_; r_ += W) {                                                         \
            const size_t k = r_ + W <= (P)->n ? r_ : (P)->n - W;                                         \
            const MN_M lanes = MN_CAT(LANES, W)(k, r_, e_);                                              \
            __VA_ARGS__                                                                                  \
        }                                                                                                \
    })

__attribute__((target(MN_CAT(TGT, W)))) static inline MN_V MN_CAT(weight, W)(const pass *P, MN_V v, MN_M *ok)
{
    MN_V g = MN_OP(_max_ps)(MN_OP(_sub_ps)(MN_B(P->thr), v), MN_OP(_setzero_ps)());
    MN_V x = MN_OP(_sub_ps)(MN_B(1.0f), MN_OP(_mul_ps)(g, MN_B(P->inv_tau)));
    *ok = MN_CMP(x, MN_OP(_setzero_ps)(), _CMP_GT_OQ);
    return MN_OP(_mul_ps)(MN_OP(_mul_ps)(x, x), MN_OP(_sub_ps)(MN_B(3.0f), MN_OP(_mul_ps)(MN_B(2.0f), x)));
}

/* acc[k..k+W) += w n where m */
__attribute__((target(MN_CAT(TGT, W)))) static inline void MN_CAT(add, W)(float *a, size_t k, MN_M m, MN_V w, MN_V n)
{
    MN_V old = MN_OP(_loadu_ps)(a + k);
    MN_OP(_storeu_ps)(a + k, MN_CAT(ADDM, W)(old, m, MN_OP(_mul_ps)(w, n)));
}
/* the three sums += w (nx, ny, nz) where m */
__attribute__((target(MN_CAT(TGT, W)))) static inline void MN_CAT(add3, W)(const pass *P, size_t k, MN_M m, MN_V w,
                                                                         MN_V nx, MN_V ny, MN_V nz)
{
    MN_CAT(add, W)(P->ax, k, m, w, nx);
    MN_CAT(add, W)(P->ay, k, m, w, ny);
    MN_CAT(add, W)(P->az, k, m, w, nz);
}

/* probe: the fused pass (P->vm kept too); a constant where inlined */
__attribute__((target(MN_CAT(TGT, W)), always_inline)) static inline void MN_CAT(ball_w, W)(const pass *P,
                                                                                          const int lo[3],
                                                                                          const int hi[3],
                                                                                          const float *q,
                                                                                          const int probe)
{
    const MN_V qx = MN_B(q[0]), qy = MN_B(q[1]), qz = MN_B(q[2]), zero = MN_OP(_setzero_ps)();
    MN_FOR_RUNS(P, lo, hi, k, lanes, {
        MN_V dx = MN_OP(_sub_ps)(MN_OP(_loadu_ps)(P->x + k), qx), dy = MN_OP(_sub_ps)(MN_OP(_loadu_ps)(P->y + k), qy);
        MN_V dz = MN_OP(_sub_ps)(MN_OP(_loadu_ps)(P->z + k), qz);
        MN_V d2 = MN_OP(_add_ps)(MN_OP(_add_ps)(MN_OP(_mul_ps)(dx, dx), MN_OP(_mul_ps)(dy, dy)), MN_OP(_mul_ps)(dz, dz));
        MN_M near = MN_AND(lanes, MN_CMP(d2, MN_B(P->rb2), _CMP_LT_OQ));
        if (!MN_ANY(near)) continue;
        MN_V d = MN_OP(_sqrt_ps)(d2);
        MN_V v = MN_OP(_sub_ps)(MN_B(1.0f), MN_OP(_mul_ps)(d, MN_B(P->inv_r)));
        if (probe) {
            MN_V old = MN_OP(_loadu_ps)(P->vm + k);
            MN_OP(_storeu_ps)(P->vm + k, MN_CAT(KEEPMAX, W)(old, lanes, v));
        }
        MN_M ok;
        MN_V w = MN_CAT(weight, W)(P, v, &ok);
        MN_M m = MN_AND(MN_AND(ok, near), MN_CMP(d, zero, _CMP_GT_OQ));
        if (!MN_ANY(m)) continue;
        MN_V id = MN_OP(_div_ps)(MN_B(1.0f), d);
        MN_CAT(add3, W)(P, k, m, w, MN_OP(_mul_ps)(dx, id), MN_OP(_mul_ps)(dy, id), MN_OP(_mul_ps)(dz, id));
    })
}

__attribute__((target(MN_CAT(TGT, W)), always_inline)) static inline void MN_CAT(link_w, W)(
    const pass *P, const int lo[3], const int hi[3], const float *q, const float *u, float D, float rr2, float rrp2,
    const int probe)
{
    const MN_V qx = MN_B(q[0]), qy = MN_B(q[1]), qz = MN_B(q[2]), ux = MN_B(u[0]), uy = MN_B(u[1]), uz = MN_B(u[2]);
    const MN_V dd = MN_B(D), r2 = MN_B(rr2), zero = MN_OP(_setzero_ps)(), ir = MN_B(P->inv_r);
    MN_FOR_RUNS(P, lo, hi, k, lanes, {
        MN_V wx = MN_OP(_sub_ps)(MN_OP(_loadu_ps)(P->x + k), qx), wy = MN_OP(_sub_ps)(MN_OP(_loadu_ps)(P->y + k), qy);
        MN_V wz = MN_OP(_sub_ps)(MN_OP(_loadu_ps)(P->z + k), qz);
        MN_V s = MN_OP(_add_ps)(MN_OP(_add_ps)(MN_OP(_mul_ps)(wx, ux), MN_OP(_mul_ps)(wy, uy)), MN_OP(_mul_ps)(wz, uz));
        MN_V q2 = MN_OP(_sub_ps)(
            MN_OP(_add_ps)(MN_OP(_add_ps)(MN_OP(_mul_ps)(wx, wx), MN_OP(_mul_ps)(wy, wy)), MN_OP(_mul_ps)(wz, wz)),
            MN_OP(_mul_ps)(s, s));
        MN_M in = MN_AND(MN_AND(MN_CMP(s, zero, _CMP_GE_OQ), MN_CMP(s, dd, _CMP_LE_OQ)), MN_CMP(q2, r2, _CMP_LT_OQ));
        in = MN_AND(in, lanes);
        if (!MN_ANY(in)) continue;
        MN_V sm = MN_OP(_sub_ps)(dd, s);
        MN_V near = MN_CAT(SEL, W)(MN_CMP(s, sm, _CMP_LT_OQ), sm, s);
        MN_V sg = MN_CAT(SEL, W)(MN_CMP(s, sm, _CMP_LE_OQ), MN_B(-1.0f), MN_B(1.0f));
        MN_V t = MN_OP(_mul_ps)(near, ir), t2 = MN_OP(_mul_ps)(t, t);
        MN_V qq = MN_OP(_sqrt_ps)(MN_OP(_max_ps)(q2, zero));
        /* jm_cos_quarter and jm_sin_quarter, term by term */
        MN_V cs = MN_OP(_sub_ps)(MN_B(1.0f / 40320), MN_OP(_mul_ps)(t2, MN_B(1.0f / 3628800)));
        cs = MN_OP(_add_ps)(MN_B(-1.0f / 720), MN_OP(_mul_ps)(t2, cs));
        cs = MN_OP(_add_ps)(MN_B(1.0f / 24), MN_OP(_mul_ps)(t2, cs));
        cs = MN_OP(_add_ps)(MN_B(-0.5f), MN_OP(_mul_ps)(t2, cs));
        cs = MN_OP(_add_ps)(MN_B(1.0f), MN_OP(_mul_ps)(t2, cs));
        MN_V v = MN_OP(_sub_ps)(cs, MN_OP(_mul_ps)(qq, ir));
        if (probe) {
            MN_M keep = MN_AND(in, MN_CMP(q2, MN_B(rrp2), _CMP_LT_OQ));
            MN_V old = MN_OP(_loadu_ps)(P->vm + k);
            MN_OP(_storeu_ps)(P->vm + k, MN_CAT(KEEPMAX, W)(old, keep, v));
        }
        MN_M ok;
        MN_V w = MN_CAT(weight, W)(P, v, &ok);
        MN_M m = MN_AND(MN_AND(in, ok), MN_CMP(qq, zero, _CMP_GT_OQ));
        if (!MN_ANY(m)) continue;
        MN_V sn = MN_OP(_add_ps)(MN_B(-1.0f / 5040), MN_OP(_mul_ps)(t2, MN_B(1.0f / 362880)));
        sn = MN_OP(_add_ps)(MN_B(1.0f / 120), MN_OP(_mul_ps)(t2, sn));
        sn = MN_OP(_add_ps)(MN_B(-1.0f / 6), MN_OP(_mul_ps)(t2, sn));
        sn = MN_OP(_add_ps)(MN_B(1.0f), MN_OP(_mul_ps)(t2, sn));
        sn = MN_OP(_mul_ps)(sg, MN_OP(_mul_ps)(t, sn));
        MN_V iq = MN_OP(_div_ps)(MN_B(1.0f), qq);
        MN_V ox = MN_OP(_add_ps)(MN_OP(_mul_ps)(sn, ux), MN_OP(_mul_ps)(MN_OP(_sub_ps)(wx, MN_OP(_mul_ps)(s, ux)), iq));
        MN_V oy = MN_OP(_add_ps)(MN_OP(_mul_ps)(sn, uy), MN_OP(_mul_ps)(MN_OP(_sub_ps)(wy, MN_OP(_mul_ps)(s, uy)), iq));
        MN_V oz = MN_OP(_add_ps)(MN_OP(_mul_ps)(sn, uz), MN_OP(_mul_ps)(MN_OP(_sub_ps)(wz, MN_OP(_mul_ps)(s, uz)), iq));
        MN_CAT(add3, W)(P, k, m, w, ox, oy, oz);
    })
}

/* the four entry points: ball##W, ball##W##p (probe), link##W, link##W##p */
__attribute__((target(MN_CAT(TGT, W)))) static void MN_CAT(ball, W)(const pass *P, const int lo[3], const int hi[3],
                                                                   const float *q)
{
    MN_CAT(ball_w, W)(P, lo, hi, q, 0);
}
__attribute__((target(MN_CAT(TGT, W)))) static void MN_CAT(MN_CAT(ball, W), p)(const pass *P, const int lo[3],
                                                                              const int hi[3], const float *q)
{
    MN_CAT(ball_w, W)(P, lo, hi, q, 1);
}
__attribute__((target(MN_CAT(TGT, W)))) static void MN_CAT(link, W)(const pass *P, const int lo[3], const int hi[3],
                                                                   const float *q, const float *u, float D, float rr2)
{
    MN_CAT(link_w, W)(P, lo, hi, q, u, D, rr2, 0.0f, 0);
}
__attribute__((target(MN_CAT(TGT, W)))) static void MN_CAT(MN_CAT(link, W), p)(const pass *P, const int lo[3],
                                                                              const int hi[3], const float *q,
                                                                              const float *u, float D, float rr2,
                                                                              float rrp2)
{
    MN_CAT(link_w, W)(P, lo, hi, q, u, D, rr2, rrp2, 1);
}

#undef MN_FOR_RUNS
#undef MN_ANY
#undef MN_AND
#undef MN_CMP
#undef MN_OP
#undef MN_B
#undef MN_M
#undef MN_V
#undef MN_CAT
#undef MN_CAT_

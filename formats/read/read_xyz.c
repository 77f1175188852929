/* read_xyz.c - reads raw little-endian float32 x,y,z triples (no header; N = size / 12). */
#include "readbuf.h"

#include <math.h>
#include <string.h>

jmf_status jmr_read_xyz(const uint8_t *data, size_t size, const jmr_ctx *ctx, jmr_points *pts)
{
    size_t n = size / 12, i;
    jmf_status st;
    if (size % 12 != 0)
        return jmr_fail(ctx, JMF_E_FORMAT, jmr_byte(n * 12),
                        "truncated particle: file size %zu is not a multiple of 12 bytes "
                        "(3 little-endian float32 per particle); %zu stray bytes",
                        size, size % 12);
    st = jmr_points_reserve(pts, ctx, n);
    if (st) return st;
#if defined(__BYTE_ORDER__) && __BYTE_ORDER__ == __ORDER_LITTLE_ENDIAN__
    /* the file's bytes are the float array: copied whole, then checked; a
     * non-finite coordinate goes through the per-point path below (its
     * message, drop_invalid) */
    if (pts->count == 0 && !pts->ids) {
        int finite = 1;
        if (n) memcpy(pts->xyz, data, 12 * n);
        for (i = 0; i < 3 * n; i++) finite &= isfinite(pts->xyz[i]) != 0;
        if (finite) {
            pts->count = n;
            return JMF_OK;
        }
    }
#endif
    for (i = 0; i < n; i++) {
        const uint8_t *p = data + 12 * i;
        st = jmr_points_add(pts, ctx, jmr_f32_bits(jmr_le32(p)), jmr_f32_bits(jmr_le32(p + 4)),
                            jmr_f32_bits(jmr_le32(p + 8)), 0, jmr_byte(12 * i));
        if (st) return st;
    }
    return JMF_OK;
}

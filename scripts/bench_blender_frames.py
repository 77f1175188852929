#!/usr/bin/env python3
# bench_blender_frames.py - makes N moving particle frames (CSV with velocities) from one real BGEO frame, for the Blender streaming bench.
# Usage: bench_blender_frames.py FRAME.bgeo OUT_DIR [N]   (writes OUT_DIR/p_1.csv ... p_N.csv)
# The frame (e.g. SPlisHSPlasH's 6,859-particle dam break) sloshes along x,
# x + 0.2 sin(2 pi k / 100) at 25 frames a second, its velocity the file's plus
# that motion's: every frame a different mesh of the same size.
import gzip
import math
import os
import struct
import sys


def read_bgeo(path):
    """[(x, y, z, vx, vy, vz)] of a BgeoV 5 file (see formats/read/read_bgeo.c for the layout)."""
    with open(path, "rb") as f:
        d = f.read()
    if d[:2] == b"\x1f\x8b":
        d = gzip.decompress(d)
    if d[:5] != b"BgeoV":
        sys.exit("%s: not a BgeoV file" % path)
    counts = struct.unpack_from(">9i", d, 5)  # version, points, prims, groups x2, point/vertex/prim/detail attribs
    npts, nattr = counts[1], counts[5]
    pos, attrs, word = 41, {}, 4  # x y z w first
    for _ in range(nattr):
        n = struct.unpack_from(">H", d, pos)[0]
        name = d[pos + 2:pos + 2 + n].decode()
        size, typ = struct.unpack_from(">Hi", d, pos + 2 + n)
        pos += 2 + n + 6
        if typ == 4:  # indexed string: count, strings
            k = struct.unpack_from(">i", d, pos)[0]
            pos += 4
            for _ in range(k):
                pos += 2 + struct.unpack_from(">H", d, pos)[0]
        else:
            pos += 4 * size
        attrs[name] = (word, size)
        word += size
    if "velocity" not in attrs:
        sys.exit("%s: no velocity attribute" % path)
    vw = attrs["velocity"][0]
    out = []
    for i in range(npts):
        w = struct.unpack_from(">%df" % word, d, pos + 4 * word * i)
        out.append((w[0], w[1], w[2], w[vw], w[vw + 1], w[vw + 2]))
    return out


def main():
    src, outdir = sys.argv[1], sys.argv[2]
    n = int(sys.argv[3]) if len(sys.argv) > 3 else 500
    pts = read_bgeo(src)
    os.makedirs(outdir, exist_ok=True)
    for k in range(1, n + 1):
        dx = 0.2 * math.sin(2 * math.pi * k / 100)
        dv = 0.2 * 2 * math.pi / 100 * 25 * math.cos(2 * math.pi * k / 100)
        lines = ["x,y,z,vx,vy,vz"]
        lines += ["%.6f,%.6f,%.6f,%.6f,%.6f,%.6f" % (x + dx, y, z, vx + dv, vy, vz) for x, y, z, vx, vy, vz in pts]
        with open(os.path.join(outdir, "p_%d.csv" % k), "w") as f:
            f.write("\n".join(lines) + "\n")
    print("bench_blender_frames: %d frames of %d particles in %s" % (n, len(pts), outdir))


if __name__ == "__main__":
    main()

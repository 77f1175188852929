# bench_blender.py - inside headless Blender: opens a per-frame sequence with the streaming importer and times the open and frame changes (make bench, via bench_blender.sh).
# Usage: blender -b --factory-startup --python bench_blender.py -- SCRIPT PATH OUT.json [SEED [NORMALS]]
#   NORMALS: the importer's normals setting (default RENDER: Blender's own outside renders; ALWAYS: the file's)
# Measures: the open (jetmesh_blender.open_sequence: file names, the first
# frame shown), the process's memory after it, scene.frame_set to 40 frames
# in a seeded random order (each read from its file: none is cached yet), 20
# consecutive frames (playback), the same 40 again with the cache, and the
# process's peak memory (VmHWM) at the end.
import importlib.util
import json
import random
import sys
import time

import bpy

args = sys.argv[sys.argv.index("--") + 1:]
script, path, out = args[0], args[1], args[2]
seed = int(args[3]) if len(args) > 3 else 1
normals = args[4] if len(args) > 4 else "RENDER"


def mem(field):
    with open("/proc/self/status") as f:
        for line in f:
            if line.startswith(field + ":"):
                return int(line.split()[1]) * 1024
    return None


def stats(ms):
    v = sorted(ms)
    return {"n": len(v), "median_ms": v[len(v) // 2] if len(v) % 2 else (v[len(v) // 2 - 1] + v[len(v) // 2]) / 2,
            "max_ms": v[-1], "min_ms": v[0]}


rss_start = mem("VmRSS")
spec = importlib.util.spec_from_file_location("jetmesh_blender", script)
jb = importlib.util.module_from_spec(spec)
spec.loader.exec_module(jb)
jb.register()
t0 = time.perf_counter()
obj = jb.open_sequence(path, cache_size=8, normals=normals)
open_s = time.perf_counter() - t0
seq = jb._runtime(obj)["seq"]
rss_open = mem("VmRSS")
scene = bpy.context.scene
rng = random.Random(seed)
frames = rng.sample(seq.numbers[1:], 40)


def visit(ks):
    ms = []
    for k in ks:
        t = time.perf_counter()
        scene.frame_set(k)
        ms.append(1e3 * (time.perf_counter() - t))
        if len(obj.data.vertices) == 0:
            raise SystemExit("bench_blender: frame %d shows no mesh" % k)
    return ms


random_ms = visit(frames)
start = frames[-1] + 1 if frames[-1] + 20 <= seq.numbers[-1] else seq.numbers[1]
play_ms = visit(range(start, start + 20))
cached_ms = visit(frames[-8:])
r = {"frames": len(seq), "first": seq.numbers[0], "last": seq.numbers[-1], "vertices_last": len(obj.data.vertices),
     "open_s": open_s, "rss_before_bytes": rss_start, "rss_after_open_bytes": rss_open,
     "random_uncached": stats(random_ms), "playback": stats(play_ms), "cached": stats(cached_ms),
     "peak_rss_bytes": mem("VmHWM"), "blender": bpy.app.version_string, "normals": normals}
with open(out, "w") as f:
    json.dump(r, f, indent=1)
print("bench_blender: %s" % json.dumps(r))

# check_sequence.py - run by t_blender.sh inside headless Blender: imports with jetmesh_blender.py and checks frame k shows frame k's mesh with the file's velocity.
# Usage: blender -b --factory-startup --python-exit-code 1 --python check_sequence.py -- SCRIPT PATH FRAMES FPS [FILES...]
#   PATH: the animated .glb/.gltf, or a folder of per-frame files (FILES: the
#   frames' .glb files in order, read for the expected counts and values).
import importlib.util
import sys

args = sys.argv[sys.argv.index("--") + 1:]
script, path, nframes, fps = args[0], args[1], int(args[2]), float(args[3])
files = args[4:]
spec = importlib.util.spec_from_file_location("jetmesh_blender", script)
jb = importlib.util.module_from_spec(spec)
spec.loader.exec_module(jb)
import bpy  # noqa: E402


def fail(msg):
    print("check_sequence: FAIL: " + msg)
    sys.exit(1)


# what the files say: per frame, (positions, velocities) in Blender's axes
expected = []
if files:
    for f in files:
        doc, binary = jb.read_gltf(f)
        attrs, pos = jb.gltf_attributes(doc, binary, 0)
        expected.append(([jb._to_blender(p) for p in pos], attrs.get("velocity")))
else:
    doc, binary = jb.read_gltf(path)
    for node in doc["nodes"]:
        attrs, pos = jb.gltf_attributes(doc, binary, node["mesh"])
        expected.append(([jb._to_blender(p) for p in pos], attrs.get("velocity")))
if len(expected) != nframes:
    fail("%d frames in the file(s), expected %d" % (len(expected), nframes))

objs = jb.import_sequence(path)
scene = bpy.context.scene
if len(objs) != nframes:
    fail("imported %d frame objects, expected %d" % (len(objs), nframes))
if (scene.frame_start, scene.frame_end) != (0, nframes - 1):
    fail("frame range %d-%d, expected 0-%d" % (scene.frame_start, scene.frame_end, nframes - 1))
if abs(scene.render.fps / scene.render.fps_base - fps) > 1e-6:
    fail("scene fps %g, expected %g" % (scene.render.fps / scene.render.fps_base, fps))


def visible(o):
    if o.hide_render or o.hide_viewport:
        return False
    s = o.matrix_world.to_scale()
    return min(abs(s[0]), abs(s[1]), abs(s[2])) > 0.5


for k in range(nframes):
    scene.frame_set(k)
    bpy.context.view_layer.update()
    shown = [o for o in objs if visible(o)]
    if len(shown) != 1:
        fail("frame %d: %d objects visible (%s), expected 1" % (k, len(shown), [o.name for o in shown]))
    o = shown[0]
    pos, vel = expected[k]
    if len(o.data.vertices) != len(pos):
        fail("frame %d: visible mesh %s has %d vertices, frame %d of the file %d" %
             (k, o.name, len(o.data.vertices), k, len(pos)))
    if hasattr(o, "cycles") and getattr(o.cycles, "use_motion_blur", False):
        fail("frame %d: %s has motion blur on" % (k, o.name))
    if vel is None:
        fail("frame %d: the file has no _VELOCITY" % k)
    if "velocity" not in o.data.attributes:
        fail("frame %d: %s has no 'velocity' attribute" % (k, o.name))
    a = o.data.attributes["velocity"]
    if a.data_type != "FLOAT_VECTOR" or a.domain != "POINT":
        fail("velocity is %s on %s, expected FLOAT_VECTOR on POINT" % (a.data_type, a.domain))
    where = {}
    for i, p in enumerate(pos):
        where.setdefault(tuple(round(c, 5) for c in p), i)
    checked = 0
    for i, v in enumerate(o.data.vertices):
        j = where.get(tuple(round(c, 5) for c in v.co))
        if j is None:
            fail("frame %d: vertex %d at %s is not in the file" % (k, i, tuple(v.co)))
        got = a.data[i].vector
        if max(abs(got[c] - vel[j][c]) for c in range(3)) > 1e-6:
            fail("frame %d: vertex %d velocity %s, the file has %s" % (k, i, tuple(got), vel[j]))
        checked += 1
    print("check_sequence: frame %d: %s visible alone, %d vertices, %d velocities as in the file" %
          (k, o.name, len(pos), checked))
print("check_sequence: ok")

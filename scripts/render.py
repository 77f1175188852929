# render.py - renders meshes side by side with Blender Cycles (CPU, no denoising) for the README: blender -b --python scripts/render.py -- OUT.png [--size WxH] [--samples N] [--view side|top|front] [--xfrac A:B [--tight]] FILE...
import bpy, sys, math
import numpy
numpy.bool = bool  # Blender 3.4's glTF importer on this numpy
from mathutils import Vector

argv = sys.argv[sys.argv.index("--") + 1:]
out = argv.pop(0)
W, H, samples, view = 1200, 500, 48, "side"
xfrac = None
tight = False
files = []
while argv:
    a = argv.pop(0)
    if a == "--size":
        W, H = (int(x) for x in argv.pop(0).split("x"))
    elif a == "--samples":
        samples = int(argv.pop(0))
    elif a == "--view":
        view = argv.pop(0)
    elif a == "--xfrac":  # frame only this part of the width, e.g. 0.5:0.8
        xfrac = tuple(float(x) for x in argv.pop(0).split(":"))
    elif a == "--tight":  # with --xfrac: frame only the vertices in that slice (close-ups)
        tight = True
    else:
        files.append(a)

bpy.ops.wm.read_factory_settings(use_empty=True)
sc = bpy.context.scene
mat = bpy.data.materials.new("liquid")
mat.use_nodes = True
bsdf = mat.node_tree.nodes["Principled BSDF"]
bsdf.inputs["Base Color"].default_value = (0.05, 0.25, 0.65, 1)
bsdf.inputs["Roughness"].default_value = 0.12
bsdf.inputs["Specular"].default_value = 0.6
bsdf.inputs["Clearcoat"].default_value = 0.5

groups = []
for f in files:
    before = set(bpy.data.objects)
    if f.endswith(".obj"):
        bpy.ops.wm.obj_import(filepath=f)
    else:
        bpy.ops.import_scene.gltf(filepath=f)
    new = [o for o in bpy.data.objects if o not in before and o.type == "MESH"]
    for o in new:
        o.data.materials.clear()
        o.data.materials.append(mat)
        for p in o.data.polygons:
            p.use_smooth = True
    groups.append(new)

def bounds(objs):
    lo = Vector((1e30,) * 3); hi = Vector((-1e30,) * 3)
    for o in objs:
        for c in o.bound_box:
            w = o.matrix_world @ Vector(c)
            lo = Vector(map(min, lo, w)); hi = Vector(map(max, hi, w))
    return lo, hi

# side by side along x, each group's centre on the x axis, resting on z = 0
sizes = [bounds(g) for g in groups]
span = max(max(hi - lo) for lo, hi in sizes)
x = 0.0
for g, (lo, hi) in zip(groups, sizes):
    c = (lo + hi) / 2
    w = hi.x - lo.x
    shift = Vector((x + w / 2 - c.x, -c.y, -lo.z))
    for o in g:
        o.location += shift
    x += w + 0.15 * span
bpy.context.view_layer.update()
lo, hi = bounds([o for g in groups for o in g])
if xfrac:
    x0 = lo.x + xfrac[0] * (hi.x - lo.x)
    x1 = lo.x + xfrac[1] * (hi.x - lo.x)
    if tight:
        vl = Vector((1e30,) * 3); vh = Vector((-1e30,) * 3)
        for o in (o for g in groups for o in g):
            for v in o.data.vertices:
                w = o.matrix_world @ v.co
                if x0 <= w.x <= x1:
                    vl = Vector(map(min, vl, w)); vh = Vector(map(max, vh, w))
        lo = Vector((x0, vl.y, vl.z))
        hi = Vector((x1, vh.y, vh.z))
    else:
        lo = Vector((x0, lo.y, lo.z))
        hi = Vector((x1, hi.y, hi.z))
centre = (lo + hi) / 2
ext = hi - lo

# floor, light, world
bpy.ops.mesh.primitive_plane_add(size=1, location=(centre.x, centre.y, lo.z))
floor = bpy.context.object
floor.scale = (ext.x * 4 + 1, ext.y * 4 + ext.x + 1, 1)
fm = bpy.data.materials.new("floor")
fm.use_nodes = True
fm.node_tree.nodes["Principled BSDF"].inputs["Base Color"].default_value = (0.8, 0.8, 0.8, 1)
fm.node_tree.nodes["Principled BSDF"].inputs["Roughness"].default_value = 0.8
floor.data.materials.append(fm)
bpy.ops.object.light_add(type="SUN", rotation=(math.radians(40), math.radians(15), math.radians(30)))
bpy.context.object.data.energy = 3.0
bpy.context.object.data.angle = math.radians(8)
world = bpy.data.worlds.new("w")
sc.world = world
world.use_nodes = True
world.node_tree.nodes["Background"].inputs["Color"].default_value = (0.75, 0.8, 0.9, 1)
world.node_tree.nodes["Background"].inputs["Strength"].default_value = 0.6

# camera: frames everything for the aspect ratio
bpy.ops.object.camera_add()
cam = bpy.context.object
sc.camera = cam
cam.data.lens = 50
aspect = W / H
if view == "top":
    d = Vector((0.0, -0.35, 1.0))
elif view == "front":
    d = Vector((0.0, -1.0, 0.12))
else:
    d = Vector((0.0, -1.0, 0.45))
d.normalize()
fov_h = 2 * math.atan(36 / 2 / cam.data.lens)
fov_v = 2 * math.atan(math.tan(fov_h / 2) / aspect)
radius_w = ext.x / 2 * 1.08
radius_h = max(ext.z, ext.y * 0.5) / 2 * 1.25 + 1e-6
dist = max(radius_w / math.tan(fov_h / 2), radius_h / math.tan(fov_v / 2)) + max(ext.y, ext.z) / 2
target = centre + Vector((0, 0, 0))
cam.location = target + d * dist
cam.rotation_euler = (target - cam.location).to_track_quat("-Z", "Y").to_euler()
cam.data.clip_end = dist * 10

sc.render.engine = "CYCLES"
sc.cycles.device = "CPU"
sc.cycles.samples = samples
sc.cycles.use_denoising = False
sc.render.resolution_x = W
sc.render.resolution_y = H
sc.render.film_transparent = False
sc.view_settings.view_transform = "Filmic"
sc.render.filepath = out
bpy.ops.render.render(write_still=True)

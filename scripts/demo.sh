#!/bin/sh
# demo.sh - the main job on the shipped samples: jet sequence to GLB, Draco GLB, OBJ and one animated GLB, with stats and a chart.
# Usage: scripts/demo.sh [BUILD_DIR]   (run by `make demo`)
set -e
BUILD=${1:-build}
J="$BUILD/jetmesh"
OUT=out/demo
rm -rf "$OUT"
mkdir -p "$OUT/glb" "$OUT/draco" "$OUT/obj"

echo "== jet sequence (100 frames, 125 particles, metasphere, marching tetrahedra) -> GLB"
"$J" convert 'samples/jet/jet_{}.csv' -r 0.025 -o "$OUT/glb/jet_{}.glb" \
    --stats "$OUT/stats.csv" --stats-svg "$OUT/stats.svg" -q
tail -n 8 "$OUT/stats.csv" | grep '^#' || true

echo "== the same frames -> glTF with Draco compression (for the web)"
"$J" convert 'samples/jet/jet_{}.csv' -r 0.025 -o "$OUT/draco/jet_{}.draco.glb" \
    --stats "$OUT/stats_draco.json" -q

echo "== the same frames -> OBJ (for MeshLab and anything else)"
"$J" convert 'samples/jet/jet_{}.csv' -r 0.025 -o "$OUT/obj/jet_{}.obj" -q

echo "== the same 100 frames as ONE animated GLB, smoothed into liquid (--smooth 25 --smooth-normals 10; a node per frame, 24 fps)"
"$J" convert 'samples/jet/jet_{}.csv' -r 0.025 --smooth 25 --smooth-normals 10 --animate --fps 24 \
    -o "$OUT/jet_animated.glb" -q

echo "== a real SPlisHSPlasH frame (4,732 particles) -> bulk fluid: the SPH colour field and marching cubes, chosen automatically"
"$J" convert samples/real/double_dam_break_frame_26_4732_particles.vtk -r 0.025 \
    -o "$OUT/dam_break.glb"
echo "== the same frame smoothed (--smooth 25 --smooth-normals 10: no orange peel, volume kept)"
"$J" convert samples/real/double_dam_break_frame_26_4732_particles.vtk -r 0.025 \
    --smooth 25 --smooth-normals 10 -o "$OUT/dam_break_smooth.glb"

script=$("$J" --blender-script)
glb=$(du -sh "$OUT/glb" | cut -f1); drc=$(du -sh "$OUT/draco" | cut -f1); obj=$(du -sh "$OUT/obj" | cut -f1)
cat <<MSG

Done. Everything is in $OUT/:
  glb/jet_000.glb ... jet_099.glb    ($glb)  glTF 2.0 binary, normals and UVs
  draco/jet_*.draco.glb              ($drc)  the same, Draco-compressed
  obj/jet_*.obj                      ($obj)
  jet_animated.glb                   all 100 frames in one animated GLB (--animate), smoothed
  dam_break.glb                      a real frame, SPH colour field
  dam_break_smooth.glb               the same, smoothed (compare them side by side)
  stats.csv, stats_draco.json        per-frame timings and a summary
  stats.svg                          time per frame by stage (open in a browser)

The whole sequence in Blender, streamed as one object (frame range 0-99,
24 fps; each frame's mesh read when the frame changes; press Space to play):
  blender --python "$script" -- $OUT/glb
or the one animated file the same way:
  blender --python "$script" -- $OUT/jet_animated.glb
(after make install: blender --python "\$(jetmesh --blender-script)" -- FOLDER;
installed as an add-on: File > Import > jetmesh sequence.) One frame: File >
Import > glTF 2.0, pick $OUT/glb/jet_050.glb (Debian's Blender cannot read the
Draco ones: its package leaves out Blender's Draco library). The jet is +Y up
like glTF, so it stands the right way; for +Z-up simulations add --z-up.
Velocities for motion blur: convert with --attributes velocity (see man
jetmesh). MeshLab: File > Import Mesh, pick an .obj or .glb.
MSG

#!/bin/sh
# pictures.sh - renders the README's pictures (docs/*.png) with headless Blender: a real splash frame (beside splashsurf's) and the jet.
# Usage: scripts/pictures.sh [BUILD_DIR]   (run by `make pictures`; a few minutes on 2 cores)
set -e
BUILD=${1:-build}
J="$BUILD/jetmesh"
W=$(mktemp -d "${TMPDIR:-/tmp}/jetmesh-pictures.XXXXXX")
trap 'rm -rf "$W"' EXIT
command -v blender >/dev/null 2>&1 || { echo "pictures: needs Blender (apt-get install blender python3-numpy)" >&2; exit 1; }
mkdir -p docs
render() { # out.png size [render.py options] files...
    out=$1 size=$2
    shift 2
    blender -b --factory-startup --python-exit-code 1 --python scripts/render.py -- \
        "$out" --size "$size" --samples 48 "$@" >"$W/blender.log" 2>&1 ||
        { tail -n 20 "$W/blender.log"; exit 1; }
    echo "pictures: $out"
}
R=samples/real/double_dam_break_frame_26_4732_particles.vtk
"$J" convert "$R" -r 0.025 -q -o "$W/db_default.glb"
"$J" convert "$R" -r 0.025 --smooth 25 --smooth-normals 10 -q -o "$W/db_smooth.glb"
"$J" convert "$R" -r 0.025 --anisotropic -q -o "$W/db_aniso.glb"
# splashsurf 0.14 with its recommended post-processing, same field and cube size (issue 31),
# where ../shared has the peer; without it the picture has jetmesh's three panels only
SS=${JETMESH_SHARED:-../shared}/peers/splashsurf/ssbench
if [ -x "$SS" ] && [ -x "$BUILD/tools/to_xyz" ]; then
    "$BUILD/tools/to_xyz" "$R" "$W/db.xyz"
    "$SS" "$W/db.xyz" -r 0.025 -s 0.0125 --mesh-cleanup --mesh-smoothing-weights --mesh-smoothing-iters 25 \
        --normals --normals-smoothing-iters 10 -o "$W/db_ss.obj" >/dev/null
    render docs/dam_break.png 1600x360 "$W/db_default.glb" "$W/db_smooth.glb" "$W/db_aniso.glb" "$W/db_ss.obj"
else
    echo "pictures: no splashsurf peer (../shared/peers/splashsurf): three panels only" >&2
    render docs/dam_break.png 1400x420 "$W/db_default.glb" "$W/db_smooth.glb" "$W/db_aniso.glb"
fi
"$J" convert samples/jet/jet_099.csv -r 0.025 -q -o "$W/jet_default.glb"
"$J" convert samples/jet/jet_099.csv -r 0.025 --smooth 25 --smooth-normals 10 -q -o "$W/jet_smooth.glb"
render docs/jet.png 1200x300 --xfrac 0.55:0.85 --view front "$W/jet_default.glb"
render docs/jet_smooth.png 1200x300 --xfrac 0.55:0.85 --view front "$W/jet_smooth.glb"
# a close-up of three joined beads at cube r/4: the creases where balls and necks meet
"$J" convert samples/jet/jet_099.csv -r 0.025 --cube-size 0.25 -q -o "$W/jet_fine.glb"
render docs/jet_closeup.png 1000x600 --xfrac 0.535:0.575 --tight --view side "$W/jet_fine.glb"

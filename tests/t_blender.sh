#!/bin/sh
# t_blender.sh - Debian's Blender, headless, imports an animated GLB and a folder of frames with share/jetmesh/jetmesh_blender.py: frame k shows frame k's mesh, velocity as in the file.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch blender
command -v blender >/dev/null 2>&1 || fail "blender is missing: run scripts/deps.sh test (apt-get install blender)"
SCRIPT=$("$J" --blender-script) || fail "jetmesh --blender-script found no script"
[ "$SCRIPT" = "$ROOT/share/jetmesh/jetmesh_blender.py" ] || fail "--blender-script printed $SCRIPT"
CHECK=$ROOT/tests/blender/check_sequence.py

# four small frames with a velocity column (jet frames 0-3: 182 to 734 vertices)
mkdir "$T/v"
for i in 0 1 2 3; do
    awk -F, -v k="$i" 'NR == 1 { print "x,y,z,vx,vy,vz"; next }
        { print $0 "," $1 * 2 "," $2 + k "," (NR % 7) * 0.1 }' "$S/jet_00$i.csv" >"$T/v/jet_$i.csv"
done
blend() { # ARGS...: the check inside Blender, its output in $T/blender.log
    HOME=$T blender -b --factory-startup --python-exit-code 1 --python "$CHECK" -- "$SCRIPT" "$@" \
        >"$T/blender.log" 2>&1 || { grep -v '^$' "$T/blender.log" | tail -n 30; fail "blender check: $*"; }
    grep -q '^check_sequence: ok' "$T/blender.log" || { tail -n 30 "$T/blender.log"; fail "no verdict: $*"; }
    grep '^check_sequence: frame' "$T/blender.log"
}

# 1. one animated GLB (fps 12: keys must land on scene frames 0..3)
run 0 convert "$T/v/jet_{}.csv" -r 0.025 --attributes velocity --animate --fps 12 -o "$T/seq.glb"
blend "$T/seq.glb" 4 12
echo "ok: animated GLB: frame k visible alone with frame k's vertices and velocities, range 0-3, 12 fps, motion blur off"

# 2. a folder of per-frame GLBs
run 0 convert "$T/v/jet_{}.csv" -r 0.025 --attributes velocity -o "$T/d/f_{}.glb"
blend "$T/d" 4 24 "$T/d/f_0.glb" "$T/d/f_1.glb" "$T/d/f_2.glb" "$T/d/f_3.glb"
echo "ok: a folder of GLBs imported as one sequence"
echo "all Blender checks passed"

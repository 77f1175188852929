#!/bin/sh
# t_blender.sh - Debian's Blender, headless, streams a 200-frame sequence with share/jetmesh/jetmesh_blender.py: frame k shows frame k's mesh and velocity, motion blur along the velocity, save and reopen, a command-line render, bad input.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch blender
command -v blender >/dev/null 2>&1 || fail "blender is missing: run scripts/deps.sh test (apt-get install blender)"
SCRIPT=$("$J" --blender-script) || fail "jetmesh --blender-script found no script"
[ "$SCRIPT" = "$ROOT/share/jetmesh/jetmesh_blender.py" ] || fail "--blender-script printed $SCRIPT"
CHECK=$ROOT/tests/blender/check_sequence.py
export CHECK_TMP="$T"

# 200 small frames numbered 1-200 (as SPlisHSPlasH numbers them): the jet's
# frames moving along x, a velocity column (vx = 20: a visible blur)
mkdir "$T/v"
awk -F, -v dir="$T/v" -v src="$S" 'BEGIN {
    for (k = 1; k <= 200; k++) {
        f = sprintf("%s/jet_%03d.csv", src, k % 100); out = dir "/jet_" k ".csv"
        print "x,y,z,vx,vy,vz" >out
        getline line <f
        while ((getline line <f) > 0) { split(line, c, ","); print c[1] + 0.01 * k "," c[2] "," c[3] ",20," c[2] "," k * 0.01 >out }
        close(f); close(out)
    } }'
blend() { # LOG ARGS...: blender with ARGS; the check's verdict in $T/LOG
    log=$1; shift
    HOME=$T blender -b --factory-startup --python-exit-code 1 "$@" >"$T/$log" 2>&1 ||
        { grep -v '^$' "$T/$log" | tail -n 30; fail "blender $*"; }
    grep -q '^check_sequence: ok' "$T/$log" || { tail -n 30 "$T/$log"; fail "no verdict: blender $*"; }
    grep '^check_sequence: ' "$T/$log" | grep -v ': ok$'
}
check() { # LOG MODE ARGS...: check_sequence.py MODE in a factory-settings Blender
    log=$1; shift
    blend "$log" --python "$CHECK" -- "$SCRIPT" "$@"
}

# 1. per-frame GLBs: the command-line set-up, three frames, motion blur, saved
run 0 convert "$T/v/jet_{}.csv" -r 0.025 --attributes velocity -o "$T/d/f_{}.glb" -q
check stream.log stream "$T/d" "$T/d/f_%d.glb" 1 200 25 "$T/scene.blend"
echo "ok: 200 per-frame GLBs streamed as one object: frames 1-200, frame k's mesh and velocity, motion blur"

# 2. the saved .blend in a new process, with its stored script (-y)
HOME=$T blender -b --factory-startup -y "$T/scene.blend" --python-exit-code 1 \
    --python "$CHECK" -- "$SCRIPT" reopen "$T/d" "$T/d/f_%d.glb" 1 200 >"$T/reopen.log" 2>&1 ||
    { tail -n 30 "$T/reopen.log"; fail "reopen"; }
grep -q '^check_sequence: ok' "$T/reopen.log" || { tail -n 30 "$T/reopen.log"; fail "reopen: no verdict"; }
echo "ok: the saved .blend reopened with -y loads frames by itself"
# ... or, without -y, with the script installed and enabled as an add-on
mkdir -p "$T/scripts/addons" && cp "$SCRIPT" "$T/scripts/addons/"
HOME=$T BLENDER_USER_SCRIPTS=$T/scripts blender -b --factory-startup "$T/scene.blend" --addons jetmesh_blender \
    --python-exit-code 1 --python "$CHECK" -- "$SCRIPT" reopen "$T/d" "$T/d/f_%d.glb" 1 200 >"$T/addon.log" 2>&1 ||
    { tail -n 30 "$T/addon.log"; fail "reopen with the add-on"; }
grep -q '^check_sequence: ok' "$T/addon.log" || { tail -n 30 "$T/addon.log"; fail "reopen with the add-on: no verdict"; }
echo "ok: the saved .blend reopened with the add-on enabled (no -y) loads frames"

# 3. the command-line render of frames 5-7 (blender -b scene.blend -y -a)
HOME=$T blender -b --factory-startup -y "$T/scene.blend" --python "$CHECK" -o "$T/r_###" -s 5 -e 7 -a \
    -- "$SCRIPT" render "$T/d" "$T/d/f_%d.glb" >"$T/render.log" 2>&1 || { tail -n 30 "$T/render.log"; fail "render"; }
[ "$(grep -c '^check_sequence: rendered frame [567]: [0-9]* vertices, ok' "$T/render.log")" = 3 ] ||
    { grep check_sequence "$T/render.log"; tail -n 20 "$T/render.log"; fail "the rendered frames did not show their own meshes"; }
for k in 005 006 007; do [ -s "$T/r_$k.png" ] || fail "no r_$k.png"; done
! cmp -s "$T/r_005.png" "$T/r_006.png" && ! cmp -s "$T/r_006.png" "$T/r_007.png" || fail "rendered frames are the same image"
echo "ok: blender -b scene.blend -y -a renders every frame's own mesh"

# 4. one --animate file: the same checks on its frames
run 0 convert "$T/v/jet_{}.csv" --frames 1:200 -r 0.025 --attributes velocity --animate --fps 25 -o "$T/seq.glb" -q
check anim.log stream "$T/seq.glb" animated 1 200 25 "$T/anim.blend"
echo "ok: a 200-frame --animate file streamed the same way, with motion blur"

# 5. velocity units and direction: a slab moving at 1 unit/s blurs 0.5 units along x at 2 fps, shutter 1
check blur.log blur "$T/slab"
echo "ok: motion blur along the velocity, its length v * shutter / fps (velocity per second)"

# 6. bad input (an empty folder; a truncated frame and one without velocity
# among good ones; a Draco frame), gaps and an offset, the operator, the panel
mkdir -p "$T/bad/seq" "$T/bad/gaps" "$T/bad/draco"
for k in 0 1 2 4; do cp "$T/d/f_$((k + 1)).glb" "$T/bad/seq/f_$k.glb"; done
head -c 2000 "$T/d/f_3.glb" >"$T/bad/seq/f_2.glb"
run 0 convert "$T/v/jet_4.csv" -r 0.025 -o "$T/bad/seq/f_3.glb" -q
run 0 convert "$T/v/jet_1.csv" -r 0.025 --draco -o "$T/bad/draco/f_0.glb" -q
run 0 convert "$T/v/jet_1.csv" -r 0.025 -o "$T/bad/draco_reference.glb" -q
for k in 0 2 4; do cp "$T/d/f_$((k + 1)).glb" "$T/bad/gaps/f_$k.glb"; done
check cases.log cases "$T/bad"
HOME=$T blender -b --factory-startup --python "$SCRIPT" -- "$T/bad/empty" >"$T/cli.log" 2>&1
st=$?
[ "$st" = 1 ] && grep -q "^jetmesh: error: no frames in $T/bad/empty" "$T/cli.log" ||
    { tail -n 5 "$T/cli.log"; fail "headless, an empty folder: exit $st"; }
grep -q 'jetmesh: error: frame 2: .*f_2.glb: truncated' "$T/cases.log" || fail "the console has no line for the broken frame"
echo "ok: bad input reported in Blender's report and the console, the other frames play; gaps, offset, operator, panel"
echo "all Blender checks passed"

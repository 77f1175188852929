#!/bin/sh
# t_draco_attributes.sh - --draco and .drc carry --attributes as Draco GENERIC attributes: Khronos glTF-Validator 0 errors, draco3d decodes them back within the quantisation bound, per frame and in --animate files.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch dracoattr
JS=$ROOT/tests/js
command -v node >/dev/null 2>&1 && [ -d "$JS/node_modules/draco3d" ] && [ -d "$JS/node_modules/gltf-validator" ] ||
    fail "node and tests/js/node_modules are needed: run scripts/deps.sh test"

validate() { # FILE: 0 errors and 0 warnings
    node "$JS/validate.mjs" --quiet "$1" >"$T/val" 2>&1 || { cat "$T/val"; fail "validator: $1"; }
    grep -q ': ok: 0 errors, 0 warnings' "$T/val" || { cat "$T/val"; fail "validator: $1"; }
}
# decoded FILE NAME REF.glb REFNAME: draco3d's structural checks pass and NAME decodes to REF's REFNAME
# within 1.5 x the 16-bit quantisation bound, each point matched to REF's vertex at its position
decoded() {
    node "$JS/draco_decode.mjs" "$1" --positions "$T/p.f32" --attribute "$2" "$T/a.f32" >"$T/dec" ||
        { cat "$T/dec"; fail "draco3d: $1"; }
    node "$JS/compare_attribute.mjs" "$3" "$4" "$T/p.f32" "$T/a.f32" --pos-tol 1e-3 --bits 16 >"$T/cmp" ||
        { cat "$T/dec" "$T/cmp"; fail "$1: $2 decoded differs from $3's $4"; }
    echo "  $1 $2: $(cat "$T/cmp")"
}

# jet frames with a velocity and a density column
mkdir "$T/v"
for i in 0 1 2 3 4 5; do
    awk -F, -v k="$i" 'NR == 1 { print "x,y,z,vx,vy,vz,density"; next }
        { print $0 "," $1 * 2 "," $2 + k "," (NR % 7) * 0.1 "," 1000 + NR }' "$S/jet_04$i.csv" >"$T/v/jet_$i.csv"
done
run 0 convert "$T/v/jet_{}.csv" -r 0.025 --attributes velocity,density -o "$T/ref/f_{}.glb" -q

# 1. per-frame Draco glTF: _VELOCITY and _DENSITY inside the compressed primitive
run 0 convert "$T/v/jet_{}.csv" -r 0.025 --attributes velocity,density --draco -o "$T/d/f_{}.glb" -q
validate "$T/d/f_2.glb"
for a in _VELOCITY _DENSITY; do decoded "$T/d/f_2.glb" $a "$T/ref/f_2.glb" $a; done
echo "ok: Draco glTF carries _VELOCITY and _DENSITY (validator 0 errors; draco3d within 1.5x the 16-bit bound)"

# 2. a bare .drc: the attributes named by Draco metadata
run 0 convert "$T/v/jet_{}.csv" -r 0.025 --attributes velocity,density -o "$T/drc/f_{}.drc" -q
decoded "$T/drc/f_4.drc" velocity "$T/ref/f_4.glb" _VELOCITY
decoded "$T/drc/f_4.drc" density "$T/ref/f_4.glb" _DENSITY
echo "ok: .drc carries velocity and density, named by metadata"

# 3. one --animate file, Draco: valid, each frame decodes, smaller than without Draco
run 0 convert "$T/v/jet_{}.csv" -r 0.025 --attributes velocity --animate -o "$T/plain.glb" -q
run 0 convert "$T/v/jet_{}.csv" -r 0.025 --attributes velocity --animate --draco -o "$T/anim.glb" -q
validate "$T/anim.glb"
decoded "$T/anim.glb" _VELOCITY "$T/ref/f_0.glb" _VELOCITY
plain=$(wc -c <"$T/plain.glb") small=$(wc -c <"$T/anim.glb")
[ $((small * 3)) -lt "$plain" ] || fail "the Draco animated file ($small bytes) is not a third of the plain one ($plain)"
echo "ok: --animate --draco --attributes velocity: valid, decodes, $small bytes against $plain"

# 4. --z-up turns the compressed velocity with the mesh: (1,2,3) -> (1,3,-2)
awk -F, 'NR == 1 { print "x,y,z,velocity_x,velocity_y,velocity_z"; next } { print $0 ",1,2,3" }' "$S/jet_050.csv" >"$T/const.csv"
run 0 convert "$T/const.csv" -r 0.025 --attributes velocity --z-up --draco -o "$T/const.glb"
node "$JS/draco_decode.mjs" "$T/const.glb" --attribute _VELOCITY "$T/c.f32" >"$T/dec" || { cat "$T/dec"; fail "draco3d: const"; }
bad=$(node -e '
const b = require("fs").readFileSync(process.argv[1]); const v = new Float32Array(b.buffer, b.byteOffset, b.length / 4);
let bad = 0; const w = [1, 3, -2];
for (let i = 0; i < v.length; i++) if (Math.abs(v[i] - w[i % 3]) > 1e-6) bad++;
console.log(v.length > 3000 ? bad : "too few " + v.length);' "$T/c.f32")
[ "$bad" = 0 ] || fail "z-up Draco velocity: $bad values off (1,3,-2)"
echo "ok: --z-up --draco: the velocity turned with the mesh"
echo "all Draco attribute checks passed"

#!/bin/sh
# t_cli_sequences.sh - --animate (one validated animated glTF), --attributes (every reader, every writer, the awkward cases) and the .pvd of VTK/PLY sequences.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch seq
JS=$ROOT/tests/js
command -v node >/dev/null 2>&1 && [ -d "$JS/node_modules/gltf-validator" ] ||
    fail "node and tests/js/node_modules are needed: run scripts/deps.sh test"

no_temps() {
    if find "$T" -name '*jetmesh-tmp*' | grep -q .; then fail "temporaries left: $(find "$T" -name '*jetmesh-tmp*')"; fi
}
validate() { # FILE: Khronos glTF-Validator, 0 errors and 0 warnings
    node "$JS/validate.mjs" --quiet "$1" >"$T/val" 2>&1 || { cat "$T/val"; fail "validator: $1"; }
    grep -q ': ok: 0 errors, 0 warnings' "$T/val" || { cat "$T/val"; fail "validator: $1"; }
}
# json FILE EXPR: evaluates EXPR on the glTF JSON (d) of a .glb or .gltf with node
json() {
    node -e '
const fs = require("fs"); const b = fs.readFileSync(process.argv[1]);
const d = b.toString("latin1", 0, 4) === "glTF" ? JSON.parse(b.toString("utf8", 20, 20 + b.readUInt32LE(12)))
                                             : JSON.parse(b.toString("utf8"));
console.log(eval(process.argv[2]));' "$1" "$2"
}
expect() { [ "$2" = "$3" ] || fail "$1: got '$2', expected '$3'"; }

# frames with per-particle arrays: the jet with a velocity (vx vy vz) and a density column
mkdir "$T/v"
for i in 0 1 2 3 4 5; do
    awk -F, -v k="$i" 'NR == 1 { print "x,y,z,vx,vy,vz,density"; next }
        { print $0 "," $1 * 2 "," $2 + k "," (NR % 7) * 0.1 "," 1000 + NR }' "$S/jet_00$i.csv" >"$T/v/jet_$i.csv"
done

# --- 1. --animate: one file, a node per frame, STEP scale keys, validator 0/0
run 0 convert "$S/jet_{}.csv" --frames 10:19 -r 0.025 --animate --fps 30 -o "$T/jet.glb"
validate "$T/jet.glb"
grep -q 'animated 10 frames at 30 fps' "$T/out" || { cat "$T/out"; fail "no summary line"; }
expect "nodes" "$(json "$T/jet.glb" 'd.nodes.length')" 10
expect "node names" "$(json "$T/jet.glb" 'd.nodes[0].name + " " + d.nodes[9].name')" "frame_0010 frame_0019"
expect "meshes" "$(json "$T/jet.glb" 'd.meshes.length')" 10
expect "channels" "$(json "$T/jet.glb" 'd.animations[0].channels.map(c => c.target.path).join()')" \
    "$(printf 'scale,%.0s' 1 2 3 4 5 6 7 8 9 | sed 's/$/scale/')"
expect "interpolation" "$(json "$T/jet.glb" '[...new Set(d.animations[0].samplers.map(s => s.interpolation))].join()')" STEP
# node 3's keys: 0, 3/30, 4/30 (min and max of its time accessor)
expect "node 3 times" "$(json "$T/jet.glb" 'const a = d.accessors[d.animations[0].samplers[3].input]; [a.count, a.min[0], a.max[0].toFixed(4)].join()')" "3,0,0.1333"
expect "node 0 times" "$(json "$T/jet.glb" 'const a = d.accessors[d.animations[0].samplers[0].input]; [a.count, a.min[0], a.max[0].toFixed(4)].join()')" "2,0,0.0333"
expect "extras" "$(json "$T/jet.glb" 'const s = d.asset.extras.jetmesh_sequence; [s.fps, s.frames, s.frame_numbers[0]].join()')" "30,10,10"
# each frame's mesh is the one a single-frame run makes (vertex counts)
for k in 10 15 19; do
    run 0 convert "$S/jet_0$k.csv" -r 0.025 -o "$T/one_$k.glb"
    want=$(json "$T/one_$k.glb" 'd.accessors[d.meshes[0].primitives[0].attributes.POSITION].count')
    got=$(json "$T/jet.glb" "d.accessors[d.meshes[$((k - 10))].primitives[0].attributes.POSITION].count")
    expect "frame $k vertices" "$got" "$want"
done
# Draco per mesh, and .gltf with its .bin
run 0 convert "$S/jet_{}.csv" --frames 0:4 -r 0.025 --animate --draco -o "$T/jetd.glb"
validate "$T/jetd.glb"
expect "draco" "$(json "$T/jetd.glb" 'd.extensionsRequired.join()')" KHR_draco_mesh_compression
run 0 convert "$S/jet_{}.csv" --frames 0:4 -r 0.025 --animate -o "$T/sep/jet.gltf"
[ -f "$T/sep/jet.bin" ] || fail "no jet.bin beside jet.gltf"
validate "$T/sep/jet.gltf"
[ ! -e "$T/jet.glb.frames" ] || fail "the frames' temporary was renamed into place"
no_temps
echo "ok: --animate: one validated file, a node per frame, STEP scale keys 0 / k/fps / (k+1)/fps, Draco, .gltf + .bin"

# streamed: the 100 frames (39 MB of GLB) are not held: the process peaks
# no higher than a run writing one file per frame (+8 MB of slack)
run 0 convert "$S/jet_{}.csv" -r 0.025 --animate -o "$T/all.glb" --stats "$T/anim.csv" --frame-jobs 1
run 0 convert "$S/jet_{}.csv" -r 0.025 -o "$T/pf/j_{}.glb" --stats "$T/pf.csv" --frame-jobs 1
peak() { awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "peak_rss_bytes") c = i }
  $1 == 99 { print int($c / 1048576) }' "$1"; }
size=$(($(wc -c <"$T/all.glb") / 1048576))
[ "$size" -ge 30 ] || fail "the 100-frame GLB is only $size MiB"
[ "$(peak "$T/anim.csv")" -le $(($(peak "$T/pf.csv") + 8)) ] ||
    fail "--animate peaked at $(peak "$T/anim.csv") MiB, one file per frame at $(peak "$T/pf.csv") MiB"
echo "ok: streamed: a $size MiB animated GLB, peak $(peak "$T/anim.csv") MiB (one file per frame: $(peak "$T/pf.csv") MiB)"
rm -rf "$T/pf" "$T/all.glb"

# usage errors
run 2 convert "$S/jet_{}.csv" -r 0.025 --animate -o "$T/jet_{}.glb"
grep -q 'without a frame placeholder' "$T/err" || fail "template with --animate: $(cat "$T/err")"
run 2 convert "$S/jet_{}.csv" -r 0.025 --animate -o "$T/jet.obj"
grep -q 'NAME.glb or NAME.gltf' "$T/err" || fail "--animate to OBJ: $(cat "$T/err")"
run 2 convert "$S/jet_{}.csv" -r 0.025 --animate --resume -o "$T/jet.glb"
run 2 convert "$S/jet_{}.csv" -r 0.025 --animate --embed -o "$T/jet.gltf"
run 2 convert "$S/jet_{}.csv" -r 0.025 --fps 0 -o "$T/x.glb"
cp "$S/jet_001.csv" "$T/in.glb"
run 2 convert "$S/jet_000.csv" "$T/in.glb" --input-format csv -r 0.025 --animate -o "$T/in.glb"
grep -q 'refusing to overwrite the input file' "$T/err" || fail "--animate over an input: $(cat "$T/err")"
cmp -s "$S/jet_001.csv" "$T/in.glb" || fail "--animate overwrote its input"

# a bad frame: without --keep-going nothing is written; with it, an empty node keeps the timing
mkdir "$T/bad"
for i in 0 1 2 3; do cp "$S/jet_00$i.csv" "$T/bad/"; done
printf 'x,y,z\n0.1,0.2\n' >"$T/bad/jet_002.csv"
run 1 convert "$T/bad/jet_{}.csv" -r 0.025 --animate -o "$T/bad.glb"
[ ! -e "$T/bad.glb" ] || fail "an animated file was written after a failure"
grep -q 'bad.glb not written' "$T/err" || fail "no word that the file was not written: $(cat "$T/err")"
run 1 convert "$T/bad/jet_{}.csv" -r 0.025 --animate --keep-going -o "$T/bad.glb"
validate "$T/bad.glb"
expect "nodes with meshes" "$(json "$T/bad.glb" 'd.nodes.map(n => n.mesh === undefined ? "-" : "m").join("")')" "mm-m"
no_temps
echo "ok: a failed frame: no file (stop) or an empty node (--keep-going)"

# --- 2. --attributes: interpolated to the vertices, in glTF, PLY and VTK
run 0 convert "$T/v/jet_{}.csv" -r 0.025 --attributes velocity,density --animate -o "$T/va.glb"
validate "$T/va.glb"
expect "custom attributes" "$(json "$T/va.glb" 'Object.keys(d.meshes[2].primitives[0].attributes).filter(k => k[0] == "_").sort().join()')" "_DENSITY,_VELOCITY"
expect "velocity type" "$(json "$T/va.glb" 'd.accessors[d.meshes[2].primitives[0].attributes._VELOCITY].type')" VEC3
run 0 convert "$T/v/jet_{}.csv" -r 0.025 --attributes all -o "$T/va/f_{}.gltf"
validate "$T/va/f_3.gltf"
expect "all" "$(json "$T/va/f_3.gltf" 'Object.keys(d.meshes[0].primitives[0].attributes).filter(k => k[0] == "_").sort().join()')" "_DENSITY,_VELOCITY"
run 0 convert "$T/v/jet_{}.csv" -r 0.025 --attributes velocity -o "$T/ply/f_{}.ply"
grep -a -q 'property float velocity_z' "$T/ply/f_1.ply" || fail "PLY without velocity properties"
run 0 convert "$T/v/jet_{}.csv" -r 0.025 --attributes density,velocity -o "$T/vtk/f_{}.vtk"
grep -a -q '^FIELD FieldData 2$' "$T/vtk/f_1.vtk" && grep -a -q '^velocity 3 [0-9]* float$' "$T/vtk/f_1.vtk" ||
    fail "VTK without the FIELD arrays"
# a constant velocity comes out constant; --z-up rotates it with the mesh: (1,2,3) -> (1,3,-2)
awk -F, 'NR == 1 { print "x,y,z,velocity_x,velocity_y,velocity_z"; next } { print $0 ",1,2,3" }' "$S/jet_050.csv" >"$T/const.csv"
run 0 convert "$T/const.csv" -r 0.025 --attributes velocity --z-up -o "$T/const.glb"
got=$(node -e '
const b = require("fs").readFileSync(process.argv[1]); const jl = b.readUInt32LE(12);
const d = JSON.parse(b.toString("utf8", 20, 20 + jl)); const bin = 20 + jl + 8;
const a = d.accessors[d.meshes[0].primitives[0].attributes._VELOCITY]; const v = d.bufferViews[a.bufferView];
let bad = 0;
for (let i = 0; i < a.count; i++) {
  const o = bin + (v.byteOffset || 0) + 12 * i, w = [1, 3, -2];
  for (let k = 0; k < 3; k++) if (Math.abs(b.readFloatLE(o + 4 * k) - w[k]) > 1e-6) bad++;
}
console.log(a.count > 1000 ? bad : "too few " + a.count);' "$T/const.glb")
expect "constant z-up velocity mismatches" "$got" 0
# and they read back as attributes of the written files: PLY and VTK round trip
run 0 convert "$T/ply/f_1.ply" -r 0.025 --attributes velocity -o "$T/rt.glb"
run 0 convert "$T/vtk/f_1.vtk" -r 0.025 --attributes velocity,density -o "$T/rt2.ply"
# formats that cannot hold them: a clear error, not silence
run 2 convert "$T/v/jet_{}.csv" -r 0.025 --attributes velocity -o "$T/o/f_{}.obj"
grep -q 'obj cannot hold per-vertex attributes' "$T/err" || fail "OBJ: $(cat "$T/err")"
[ ! -e "$T/o" ] || [ -z "$(ls "$T/o")" ] || fail "outputs written despite the error"
echo "ok: --attributes: glTF _VELOCITY/_DENSITY (validated), PLY properties, VTK FIELD arrays; OBJ refused (Draco: t_draco_attributes.sh)"

# real frames of every particle format carrying velocities
D=${JETMESH_SHARED:-$ROOT/../shared}/data/splashsurf
if [ -d "$D" ]; then
    for f in ParticleData_Fluid_5.vtk ParticleData_Fluid_50.bgeo fluid_250_particles.vtu dam_break_frame_9_6859_particles.bgeo; do
        run 0 convert "$D/$f" -r 0.025 --attributes velocity -o "$T/real_$f.glb"
        validate "$T/real_$f.glb"
    done
    run 0 convert "$D/dam_break_frame_9_6859_particles.bgeo" -r 0.025 --attributes all -o "$T/real_all.glb"
    expect "bgeo all" "$(json "$T/real_all.glb" 'Object.keys(d.meshes[0].primitives[0].attributes).filter(k => k[0] == "_").sort().join()')" "_DENSITY,_VELOCITY"
    echo "ok: real VTK, BGEO and VTU frames with velocities"
fi

# --- 3. the awkward cases
# an attribute missing in some frames: that frame fails, naming file and attribute
mkdir "$T/miss"
cp "$T/v/"jet_*.csv "$T/miss/"
cut -d, -f1-3 "$T/v/jet_2.csv" >"$T/miss/jet_2.csv"
run 1 convert "$T/miss/jet_{}.csv" -r 0.025 --attributes velocity -o "$T/m/f_{}.glb"
grep -q "jet_2.csv: no per-particle attribute 'velocity' in this file" "$T/err" || fail "missing: $(cat "$T/err")"
run 1 convert "$T/miss/jet_{}.csv" -r 0.025 --attributes velocity --keep-going -o "$T/m/f_{}.glb"
for i in 0 1 3 4 5; do [ -f "$T/m/f_$i.glb" ] || fail "frame $i not converted with --keep-going"; done
# frames that differ in which attributes they carry: --attributes all takes the
# first frame's set, a later frame without one of them fails by name; naming
# only what all carry converts all
cut -d, -f1-6 "$T/v/jet_3.csv" >"$T/miss/jet_2.csv"   # frame 2: velocity only
run 1 convert "$T/miss/jet_{}.csv" -r 0.025 --attributes all -o "$T/m2/f_{}.glb"
grep -q "jet_2.csv: no per-particle attribute 'density'" "$T/err" || fail "differing frames: $(cat "$T/err")"
run 0 convert "$T/miss/jet_{}.csv" -r 0.025 --attributes velocity -o "$T/m3/f_{}.glb"
# wrong length: a VTK FIELD array one value short
n=5
{
    printf '# vtk DataFile Version 4.1\nshort\nASCII\nDATASET UNSTRUCTURED_GRID\nPOINTS %d float\n' $n
    printf '0 0 0\n0.03 0 0\n0.06 0 0\n0.09 0 0\n0.12 0 0\n'
    printf 'POINT_DATA %d\nFIELD FieldData 1\nvelocity 3 %d float\n' $n $((n - 1))
    printf '1 0 0\n1 0 0\n1 0 0\n1 0 0\n'
} >"$T/short.vtk"
run 1 convert "$T/short.vtk" -r 0.025 --attributes velocity -o "$T/short.glb"
grep -q "short.vtk: attribute 'velocity' has 4 values for 5 particles" "$T/err" || fail "wrong length: $(cat "$T/err")"
# NaN in an attribute: an error naming file and attribute, or --drop-invalid drops the particle
sed '3s/,0\.[0-9]*,\([0-9]*\)$/,nan,\1/' "$T/v/jet_1.csv" >"$T/nan.csv"
grep -q nan "$T/nan.csv" || fail "test setup: no nan written"
run 1 convert "$T/nan.csv" -r 0.025 --attributes velocity -o "$T/nan.glb"
grep -q "nan.csv: attribute 'velocity' of particle 1 is NaN" "$T/err" || fail "NaN: $(cat "$T/err")"
grep -q -- '--drop-invalid' "$T/err" || fail "NaN: no hint of --drop-invalid"
run 0 convert "$T/nan.csv" -r 0.025 --attributes velocity --drop-invalid -o "$T/nan.glb"
grep -q '(1 dropped)' "$T/out" || fail "--drop-invalid: $(cat "$T/out")"
# a NaN in an array not asked for is no error
run 0 convert "$T/nan.csv" -r 0.025 --attributes density -o "$T/nan2.glb"
no_temps
echo "ok: missing in some frames, differing frames, wrong length, NaN (error or --drop-invalid)"

# --- 4. ParaView: a .pvd beside VTK and PLY sequences
run 0 convert "$S/jet_{}.csv" --frames 4:6 -r 0.025 -o "$T/pv/jet_{}.vtk" --pvd --time-step 0.5
[ -f "$T/pv/jet.pvd" ] || fail "no jet.pvd beside the VTK sequence"
if command -v xmllint >/dev/null 2>&1; then xmllint --noout "$T/pv/jet.pvd" || fail "jet.pvd is not XML"; fi
expect "pvd sets" "$(grep -c '<DataSet ' "$T/pv/jet.pvd")" 3
grep -q 'timestep="2" group="" part="0" file="jet_004.vtk"' "$T/pv/jet.pvd" || { cat "$T/pv/jet.pvd"; fail "pvd time of frame 4"; }
grep -q 'timestep="3" .*file="jet_006.vtk"' "$T/pv/jet.pvd" || fail "pvd time of frame 6"
run 0 convert "$S/jet_{}.csv" --frames 4:5 -r 0.025 -o "$T/pp/fluid_{}.ply" --pvd --fps 10
grep -q 'timestep="0.5" .*file="fluid_005.ply"' "$T/pp/fluid.pvd" || { cat "$T/pp/fluid.pvd"; fail "pvd with --fps"; }
run 0 convert "$S/jet_{}.csv" --frames 4:5 -r 0.025 -o "$T/pn/f_{}.vtk"
[ ! -e "$T/pn/f.pvd" ] || fail "a .pvd without --pvd"
run 0 convert "$S/jet_{}.csv" --frames 4:5 -r 0.025 -o "$T/pg/f_{}.glb" --pvd
[ -z "$(find "$T/pg" -name '*.pvd')" ] || fail "a .pvd beside glTF"
no_temps
echo "ok: --pvd beside VTK/PLY sequences, times from --time-step or --fps; none by default or beside glTF"
echo "all sequence checks passed"

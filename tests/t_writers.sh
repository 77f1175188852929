#!/bin/sh
# t_writers.sh - writes the test meshes in every output format and variant, validates glTF/GLB, decodes Draco twice, checks OBJ/PLY/VTK.
#
# Env: JETMESH_BUILD (build dir with tools/write_sample), JETMESH_ROOT (repo).
# Needs node with tests/js/node_modules (scripts/deps.sh test) and Debian's
# draco_decoder (package draco).
set -e

B=${JETMESH_BUILD:-$(pwd)/build}
R=${JETMESH_ROOT:-$(pwd)}
W="$B/tools/write_sample"
JS="$R/tests/js"

fail() { echo "t_writers: FAIL: $*" >&2; exit 1; }
note() { echo "t_writers: $*"; }

[ -x "$W" ] || fail "$W is missing: run make $B/tools/write_sample"
command -v node >/dev/null 2>&1 || fail "node is missing: run scripts/deps.sh test"
[ -d "$JS/node_modules/gltf-validator" ] && [ -d "$JS/node_modules/draco3d" ] ||
  fail "$JS/node_modules is missing: run scripts/deps.sh test (npm ci in tests/js)"
command -v draco_decoder >/dev/null 2>&1 || fail "draco_decoder is missing: apt-get install draco"

T=$(mktemp -d "${TMPDIR:-/tmp}/t_writers.XXXXXX")
trap 'rm -rf "$T"' EXIT INT TERM

# field JSON KEY: a scalar of our own one-line JSON outputs
field() { printf '%s\n' "$1" | sed -n "s/.*\"$2\": *\"\{0,1\}\([^,\"}]*\).*/\1/p"; }

# expect_eq WHAT GOT WANT
expect_eq() {
  [ "$2" = "$3" ] || { echo "t_writers: FAIL: $1: got '$2', expected '$3'" >&2; return 1; }
}

# write MESH OUT [options] -> writes, keeps the source summary in OUT.src.json
write() {
  mesh=$1 out=$2
  shift 2
  "$W" "$mesh" "$T/$out" "$@" >"$T/$out.src.json" || fail "write_sample $mesh $out $*"
}

# --- 1. Every format and variant --------------------------------------------
note "writing"
MESHES="octahedron icosphere:3 grid empty"
for m in $MESHES; do
  n=$(echo "$m" | tr ':' '_')
  for ext in obj ply vtk gltf glb draco.glb draco.gltf; do write "$m" "$n.$ext"; done
  write "$m" "$n.embed.gltf" --embed
  write "$m" "$n.zup.gltf" --z-up
  write "$m" "$n.zup.draco.glb" --z-up --positions "$T/$n.zup.f32"
  write "$m" "$n.nonormals.gltf" --no-normals --no-uvs --embed
  [ "$m" = empty ] || write "$m" "$n.drc" --positions "$T/$n.f32"
done
write torus:255x257 u16.glb            # 65535 vertices: max index 65534 -> 16-bit
write torus:256x256 u32.glb            # 65536 vertices -> 32-bit
write torus:255x257 u16.draco.gltf
write torus:256x256 u32.draco.glb
write grid grid.bits11.drc --bits 11,8,10 --speed 10 --positions "$T/grid.bits11.f32"
write grid grid.forced --format glb --draco
leftover=$(find "$T" -name '*.jetmesh-tmp-*' | head -n 1)
[ -z "$leftover" ] || fail "temporary file left behind: $leftover"

# --- 2. glTF-Validator: 0 errors, 0 warnings --------------------------------
note "validating glTF/GLB"
set +e
(cd "$T" && node "$JS/validate.mjs" --quiet ./*.gltf ./*.glb grid.forced) >"$T/validate.log" 2>&1
rc=$?
set -e
cat "$T/validate.log"
[ $rc = 0 ] || fail "glTF-Validator reported errors or warnings (see above)"
# 8 glTF/GLB variants of each of the 4 meshes, 4 index-type cases, 1 forced format
expect_eq "files validated" "$(grep -c ': ok: 0 errors, 0 warnings' "$T/validate.log")" 37 || fail "validation count"

# --- 3. Index types, z-up, buffers, generator (one node run reads every file) ----
note "checking index types, z-up rotation, buffers and generator"
version=$(sed -n 's/^#define JM_VERSION_STRING "\(.*\)"/\1/p' "$R/lib/jetmesh.h")
node - "$T" "$version" <<'JS' || fail "glTF content checks (see above)"
const fs = require('fs');
const [dir, version] = process.argv.slice(2);
let bad = 0;
const check = (ok, what) => { if (!ok) { bad++; console.error(`t_writers: FAIL: ${what}`); } };
const gltf = (name) => {
  const b = fs.readFileSync(`${dir}/${name}`);
  const text = b.readUInt32LE(0) === 0x46546c67 ? b.subarray(20, 20 + b.readUInt32LE(12)) : b;
  return JSON.parse(text.toString());
};
const src = (name) => JSON.parse(fs.readFileSync(`${dir}/${name}.src.json`, 'utf8'));
const prim = (g) => g.meshes[0].primitives[0];
const indexType = (name) => { const g = gltf(name); return g.accessors[prim(g).indices].componentType; };
for (const [name, want] of [['u16.glb', 5123], ['u32.glb', 5125], ['grid.glb', 5125], ['octahedron.glb', 5123],
                            ['u16.draco.gltf', 5123], ['u32.draco.glb', 5125]])
  check(indexType(name) === want, `${name}: index componentType ${indexType(name)}, expected ${want}`);
const f = Math.fround;
for (const m of ['octahedron', 'icosphere_3', 'grid']) {
  for (const [name, rot] of [[`${m}.gltf`, false], [`${m}.zup.gltf`, true], [`${m}.zup.draco.glb`, true]]) {
    const g = gltf(name), s = src(name), P = g.accessors[prim(g).attributes.POSITION];
    const [x0, y0, z0] = s.min.map(f), [x1, y1, z1] = s.max.map(f);
    const want = rot ? [[x0, z0, -y1], [x1, z1, -y0]] : [[x0, y0, z0], [x1, y1, z1]];
    check(JSON.stringify([P.min, P.max]) === JSON.stringify(want),
          `${name}: POSITION min/max ${JSON.stringify([P.min, P.max])}, expected ${JSON.stringify(want)}` +
          (rot ? ' = (x, z, -y) of the source' : ''));
  }
}
check(gltf('empty.gltf').meshes === undefined, 'empty.gltf: has a mesh');
check(gltf('empty.gltf').nodes?.length === 1, 'empty.gltf: no node');
check(!fs.existsSync(`${dir}/empty.bin`), 'empty.gltf: a .bin was written for no data');
const oct = gltf('octahedron.gltf');
check(oct.buffers[0].uri === 'octahedron.bin', `octahedron.gltf: buffer uri ${oct.buffers[0].uri}`);
check(fs.statSync(`${dir}/octahedron.bin`).size === oct.buffers[0].byteLength, 'octahedron.bin: size is not byteLength');
check(gltf('octahedron.embed.gltf').buffers[0].uri.startsWith('data:application/octet-stream;base64,'),
      'octahedron.embed.gltf: buffer not embedded');
check(!fs.existsSync(`${dir}/octahedron.embed.bin`), 'octahedron.embed.gltf: a .bin was written');
check(gltf('grid.glb').asset.generator === `jetmesh ${version}`, `generator "${gltf('grid.glb').asset.generator}"`);
const np = gltf('octahedron.nonormals.gltf');
check(JSON.stringify(Object.keys(prim(np).attributes)) === '["POSITION"]', 'no-normals/no-uvs: extra attributes');
process.exitCode = bad ? 1 : 0;
JS

# --- 4. Draco: draco3d and Debian's draco_decoder ---------------------------
# check_draco OUT REF.f32 SRC.json POSITION_BITS
check_draco() {
  out=$1 ref=$2 srcj=$(cat "$3") bits=$4
  nv=$(field "$srcj" vertices) nt=$(field "$srcj" triangles)
  # Draco quantizes every axis over the largest extent L: error <= L/(2^bits-1)/2.
  tol=$(printf '%s\n' "$srcj" | sed 's/.*"min": \[\([^]]*\)\], "max": \[\([^]]*\)\].*/\1, \2/' |
        awk -F', ' -v b="$bits" '{ L = 0; for (k = 1; k <= 3; k++) if ($(k+3) - $k > L) L = $(k+3) - $k;
                                   printf "%.9g\n", 1.5 * L / 2 ^ b }')
  d=$(node "$JS/draco_decode.mjs" "$T/$out" --positions "$T/$out.dec.f32" --extract "$T/$out.x.drc") ||
    { echo "$d" >&2; echo "t_writers: FAIL: draco3d: $out" >&2; return 1; }
  expect_eq "$out: draco3d points" "$(field "$d" points)" "$nv" &&
  expect_eq "$out: draco3d faces" "$(field "$d" faces)" "$nt" &&
  expect_eq "$out: draco3d collapsed faces" "$(field "$d" collapsed_faces)" 0 &&
  node "$JS/compare_positions.mjs" "$ref" "$T/$out.dec.f32" --tol "$tol" >"$T/$out.cmp1" ||
    { cat "$T/$out.cmp1" >&2; echo "t_writers: FAIL: $out: draco3d positions" >&2; return 1; }
  draco_decoder -i "$T/$out.x.drc" -o "$T/$out.dec.obj" >/dev/null ||
    { echo "t_writers: FAIL: draco_decoder could not decode $out" >&2; return 1; }
  expect_eq "$out: draco_decoder vertices" "$(grep -c '^v ' "$T/$out.dec.obj")" "$nv" &&
  expect_eq "$out: draco_decoder faces" "$(grep -c '^f ' "$T/$out.dec.obj")" "$nt" &&
  node "$JS/compare_positions.mjs" "$ref" "$T/$out.dec.obj" --tol "$tol" >"$T/$out.cmp2" ||
    { cat "$T/$out.cmp2" >&2; echo "t_writers: FAIL: $out: draco_decoder positions" >&2; return 1; }
  echo "t_writers:   $out: $nv points, $nt faces, max error $(field "$(cat "$T/$out.cmp1")" max_error_a_to_b) (draco3d), $(field "$(cat "$T/$out.cmp2")" max_error_a_to_b) (draco_decoder), bound $tol"
}
note "decoding Draco outputs"
for m in octahedron icosphere_3 grid; do
  check_draco "$m.drc" "$T/$m.f32" "$T/$m.drc.src.json" 16
  check_draco "$m.draco.glb" "$T/$m.f32" "$T/$m.draco.glb.src.json" 16
  check_draco "$m.draco.gltf" "$T/$m.f32" "$T/$m.draco.gltf.src.json" 16
  check_draco "$m.zup.draco.glb" "$T/$m.zup.f32" "$T/$m.zup.draco.glb.src.json" 16
done
check_draco grid.bits11.drc "$T/grid.bits11.f32" "$T/grid.bits11.drc.src.json" 11
check_draco grid.forced "$T/grid.f32" "$T/grid.forced.src.json" 16

# --- 5. OBJ, PLY, VTK ------------------------------------------------------------
note "checking OBJ, PLY, VTK"
# check_obj FILE NV NT
check_obj() {
  expect_eq "$1: v lines" "$(grep -c '^v ' "$T/$1" || true)" "$2" &&
  expect_eq "$1: vt lines" "$(grep -c '^vt ' "$T/$1" || true)" "$2" &&
  expect_eq "$1: vn lines" "$(grep -c '^vn ' "$T/$1" || true)" "$2" &&
  expect_eq "$1: f a/a/a lines" "$(grep -c '^f [0-9]*/[0-9]*/[0-9]* [0-9]*/[0-9]*/[0-9]* [0-9]*/[0-9]*/[0-9]*$' "$T/$1" || true)" "$3" &&
  expect_eq "$1: largest index" "$(awk '/^f /{for(i=2;i<=4;i++){split($i,a,"/"); if(a[1]+0>m)m=a[1]+0}} END{print m+0}' "$T/$1")" "$2"
}
# check_ply FILE NV NT: header counts, and the size: 32 bytes a vertex, 13 a face
check_ply() {
  hdr=$(grep -a -b -m1 '^end_header$' "$T/$1" | cut -d: -f1)
  size=$(wc -c <"$T/$1")
  expect_eq "$1: format" "$(sed -n 2p "$T/$1")" "format binary_little_endian 1.0" &&
  expect_eq "$1: element vertex" "$(grep -a -m1 '^element vertex' "$T/$1")" "element vertex $2" &&
  expect_eq "$1: element face" "$(grep -a -m1 '^element face' "$T/$1")" "element face $3" &&
  expect_eq "$1: size" "$size" "$((hdr + 11 + 32 * $2 + 13 * $3))"
}
# check_vtk FILE NV NT: sections and the size
check_vtk() {
  size=$(wc -c <"$T/$1")
  title=$(sed -n 2p "$T/$1")
  text="# vtk DataFile Version 3.0
$title
BINARY
DATASET POLYDATA
POINTS $2 float

POLYGONS $3 $((4 * $3))

POINT_DATA $2
NORMALS Normals float

TEXTURE_COORDINATES TCoords 2 float
"
  [ "$2" = 0 ] && text="# vtk DataFile Version 3.0
$title
BINARY
DATASET POLYDATA
POINTS 0 float

POLYGONS 0 0
"
  expect_eq "$1: POINTS" "$(grep -a -m1 '^POINTS' "$T/$1")" "POINTS $2 float" &&
  expect_eq "$1: POLYGONS" "$(grep -a -m1 '^POLYGONS' "$T/$1")" "POLYGONS $3 $((4 * $3))" &&
  expect_eq "$1: size" "$size" "$(($(printf '%s\n' "$text" | wc -c) + 32 * $2 + 16 * $3))"
}
for m in octahedron icosphere_3 grid empty; do
  srcj=$(cat "$T/$m.obj.src.json")
  nv=$(field "$srcj" vertices) nt=$(field "$srcj" triangles)
  check_obj "$m.obj" "$nv" "$nt" || fail "$m.obj"
  check_ply "$m.ply" "$nv" "$nt" || fail "$m.ply"
  check_vtk "$m.vtk" "$nv" "$nt" || fail "$m.vtk"
done

# --- 6. Failures are reported, and leave nothing behind ----------------------------
note "checking failures"
mkdir "$T/adir"
if "$W" octahedron "$T/adir" --format obj >/dev/null 2>"$T/err"; then fail "writing to a directory succeeded"; fi
grep -q 'is a directory' "$T/err" || fail "writing to a directory: unclear message: $(cat "$T/err")"
if "$W" octahedron "$T/missing/x.glb" >/dev/null 2>"$T/err"; then fail "writing into a missing directory succeeded"; fi
grep -q 'missing/x.glb' "$T/err" || fail "missing directory: message does not name the file: $(cat "$T/err")"
if "$W" empty "$T/empty.drc" >/dev/null 2>"$T/err"; then fail "an empty .drc was written"; fi
grep -q 'empty mesh' "$T/err" || fail "empty .drc: unclear message: $(cat "$T/err")"
[ ! -e "$T/empty.drc" ] || fail "a failed .drc write left a file"
if "$W" octahedron "$T/x.unknown" >/dev/null 2>"$T/err"; then fail "an unknown extension was accepted"; fi
grep -q 'unknown output format' "$T/err" || fail "unknown extension: unclear message: $(cat "$T/err")"
if "$W" octahedron "$T/x.obj" --draco >/dev/null 2>"$T/err"; then fail "Draco OBJ was accepted"; fi
if [ -w /dev/full ] && [ -c /dev/full ]; then
  if "$W" grid /dev/full --format ply >/dev/null 2>"$T/err"; then fail "writing to /dev/full succeeded"; fi
  grep -q 'No space left' "$T/err" || fail "/dev/full: unclear message: $(cat "$T/err")"
fi
cp "$T/octahedron.obj" "$T/good.obj"
if "$W" octahedron "$T/good.obj" --draco >/dev/null 2>&1; then fail "Draco OBJ was accepted"; fi
cmp -s "$T/octahedron.obj" "$T/good.obj" || fail "a refused write changed the existing file"
leftover=$(find "$T" -name '*.jetmesh-tmp-*' | head -n 1)
[ -z "$leftover" ] || fail "temporary file left behind: $leftover"

# --- 7. The checks can fail ------------------------------------------------------
note "checking that the checks catch mistakes"
if check_obj octahedron.obj 7 8 2>/dev/null; then fail "check_obj accepted a wrong vertex count"; fi
if check_ply grid.ply 70000 139999 2>/dev/null; then fail "check_ply accepted a wrong face count"; fi
if check_vtk icosphere_3.vtk 642 1279 2>/dev/null; then fail "check_vtk accepted a wrong face count"; fi
if check_draco grid.bits11.drc "$T/grid.bits11.f32" "$T/grid.bits11.drc.src.json" 16 >/dev/null 2>&1; then
  fail "check_draco accepted 11-bit positions against a 16-bit bound"
fi
head -c 1000 "$T/grid.glb" >"$T/truncated.glb"
if node "$JS/validate.mjs" "$T/truncated.glb" >/dev/null 2>&1; then fail "the validator accepted a truncated GLB"; fi
sed 's/"count": 24/"count": 23/' "$T/octahedron.embed.gltf" >"$T/bad.gltf"
if node "$JS/validate.mjs" "$T/bad.gltf" >/dev/null 2>&1; then fail "the validator accepted a wrong index count"; fi

note "ok"

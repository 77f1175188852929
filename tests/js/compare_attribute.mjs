// compare_attribute.mjs - checks a decoded per-vertex attribute against an uncompressed glTF's, vertex by vertex matched by position.
//
// Usage: node compare_attribute.mjs REF.glb NAME DEC_POSITIONS.f32 DEC_VALUES.f32 --pos-tol P --tol T|--bits B
// REF.glb: an uncompressed GLB whose first primitive has POSITION and the
// accessor NAME (e.g. _VELOCITY); the decoded files are raw float32 (x y z
// per point; NAME's components per point, in the same order), as
// draco_decode.mjs writes them. Each decoded point is matched to the
// reference vertex nearest to it (it must lie within P on each axis), and
// its values must equal that vertex's within T; --bits B: T is 1.5 times
// Draco's quantisation bound for B bits, R / (2^B - 1) / 2 with R the
// largest range of a component in the reference. Prints JSON (points, largest
// position and value errors); exit status 1 when a point has no match or a
// value is off by more than T.
import { readFile } from 'node:fs/promises';

function glb(bytes) {
  const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  const jlen = dv.getUint32(12, true);
  const json = JSON.parse(new TextDecoder().decode(bytes.subarray(20, 20 + jlen)));
  return { json, bin: bytes.subarray(20 + jlen + 8) };
}

function accessor({ json, bin }, index) {
  const a = json.accessors[index];
  const v = json.bufferViews[a.bufferView];
  const n = { SCALAR: 1, VEC2: 2, VEC3: 3, VEC4: 4 }[a.type];
  const off = bin.byteOffset + (v.byteOffset ?? 0) + (a.byteOffset ?? 0);
  return { n, values: new Float32Array(bin.buffer.slice(off, off + a.count * n * 4)) };
}

async function f32(file) {
  const b = await readFile(file);
  return new Float32Array(b.buffer.slice(b.byteOffset, b.byteOffset + b.length));
}

const args = process.argv.slice(2);
const [refFile, name, decPosFile, decValFile] = args;
const ptol = +args[args.indexOf('--pos-tol') + 1];
const bits = args.includes('--bits') ? +args[args.indexOf('--bits') + 1] : 0;
let tol = args.includes('--tol') ? +args[args.indexOf('--tol') + 1] : 0;
if (args.length < 8 || !(ptol > 0) || !(tol > 0 || bits > 0)) {
  console.error('usage: node compare_attribute.mjs REF.glb NAME DEC_POSITIONS.f32 DEC_VALUES.f32 --pos-tol P --tol T|--bits B');
  process.exit(2);
}
const ref = glb(new Uint8Array(await readFile(refFile)));
const prim = ref.json.meshes[0].primitives[0];
const rp = accessor(ref, prim.attributes.POSITION).values;
const rv = accessor(ref, prim.attributes[name]);
if (bits) {
  let range = 0;
  for (let c = 0; c < rv.n; c++) {
    let lo = Infinity, hi = -Infinity;
    for (let i = c; i < rv.values.length; i += rv.n) { lo = Math.min(lo, rv.values[i]); hi = Math.max(hi, rv.values[i]); }
    range = Math.max(range, hi - lo);
  }
  tol = 1.5 * range / (2 ** bits - 1) / 2;
}
const dp = await f32(decPosFile), dv = await f32(decValFile);
const nc = rv.n, nr = rp.length / 3, nd = dp.length / 3;
// the reference sorted by x: each decoded point scans the slab x +- ptol
const order = Array.from({ length: nr }, (_, i) => i).sort((a, b) => rp[3 * a] - rp[3 * b]);
const xs = Float64Array.from(order, (i) => rp[3 * i]);
let maxPos = 0, maxVal = 0, unmatched = 0;
for (let i = 0; i < nd; i++) {
  const x = dp[3 * i];
  let lo = 0, hi = nr;
  while (lo < hi) { const m = (lo + hi) >> 1; if (xs[m] < x - ptol) lo = m + 1; else hi = m; }
  let best = -1, bestD = Infinity;
  for (let k = lo; k < nr && xs[k] <= x + ptol; k++) {
    const j = order[k];
    const d = Math.max(...[0, 1, 2].map((c) => Math.abs(rp[3 * j + c] - dp[3 * i + c])));
    if (d < bestD) { bestD = d; best = j; }
  }
  if (best < 0 || bestD > ptol) { unmatched++; continue; }
  maxPos = Math.max(maxPos, bestD);
  for (let c = 0; c < nc; c++) maxVal = Math.max(maxVal, Math.abs(rv.values[nc * best + c] - dv[nc * i + c]));
}
const ok = nd === nr && dv.length === nd * nc && unmatched === 0 && maxVal <= tol;
console.log(JSON.stringify({ reference: nr, decoded: nd, components: nc, unmatched, max_position_error: maxPos,
                             max_value_error: maxVal, tol, ok }));
process.exitCode = ok ? 0 : 1;

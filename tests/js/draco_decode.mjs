// draco_decode.mjs - decodes a .drc file, or the Draco primitive of a .glb/.gltf, with draco3d and prints a JSON summary.
//
// Usage: node draco_decode.mjs FILE [--positions OUT.f32] [--extract OUT.drc] [--attribute NAME OUT.f32]
// Prints one JSON object: points, faces, the attributes (Draco type, unique
// id, components), the positions' bounding box, how many faces collapsed to
// zero area in decoding, and for glTF/GLB the checks of the
// KHR_draco_mesh_compression structure that the glTF-Validator leaves out
// (extension declared and required, bufferView present, every attribute id
// found in the Draco data, accessors without bufferView whose counts match
// the decoded data). --positions writes the decoded positions as raw
// little-endian float32 x y z; --extract writes the Draco bytes of a
// glTF/GLB primitive as a bare .drc (for Draco's own draco_decoder);
// --attribute writes a GENERIC attribute's decoded values (float32, its
// components per point, in the positions' order): NAME is the glTF semantic
// ("_VELOCITY", through the extension's ids) or, in a .drc, the attribute
// metadata entry "name" ("velocity").
// Exit status 1 when decoding or a check fails.
import { readFile, writeFile } from 'node:fs/promises';
import path from 'node:path';
import draco3d from 'draco3d';

const EXT = 'KHR_draco_mesh_compression';

function parseGlb(bytes) {
  const dv = new DataView(bytes.buffer, bytes.byteOffset, bytes.byteLength);
  if (dv.getUint32(0, true) !== 0x46546c67) throw new Error('not a GLB (bad magic)');
  let json = null;
  let bin = null;
  for (let off = 12; off + 8 <= bytes.length; ) {
    const len = dv.getUint32(off, true);
    const type = dv.getUint32(off + 4, true);
    const body = bytes.subarray(off + 8, off + 8 + len);
    if (type === 0x4e4f534a) json = JSON.parse(new TextDecoder().decode(body));
    else if (type === 0x004e4942) bin = body;
    off += 8 + len;
  }
  if (!json) throw new Error('GLB without a JSON chunk');
  return { json, bin };
}

async function bufferData(gltf, index, bin, dir) {
  const b = gltf.buffers?.[index];
  if (!b) throw new Error(`buffer ${index} missing`);
  if (b.uri === undefined) {
    if (!bin) throw new Error('GLB buffer without a BIN chunk');
    return bin;
  }
  if (b.uri.startsWith('data:')) {
    const comma = b.uri.indexOf(',');
    return new Uint8Array(Buffer.from(b.uri.slice(comma + 1), 'base64'));
  }
  return new Uint8Array(await readFile(path.resolve(dir, decodeURIComponent(b.uri))));
}

// Returns { data, gltf, prim } for the first primitive with the extension.
async function extractFromGltf(file, bytes, checks) {
  const isGlb = bytes.length >= 4 && bytes[0] === 0x67 && bytes[1] === 0x6c && bytes[2] === 0x54;
  const { json, bin } = isGlb
    ? parseGlb(bytes)
    : { json: JSON.parse(new TextDecoder().decode(bytes)), bin: null };
  const check = (ok, what) => checks.push({ ok: !!ok, what });
  check(json.extensionsUsed?.includes(EXT), `extensionsUsed lists ${EXT}`);
  check(json.extensionsRequired?.includes(EXT), `extensionsRequired lists ${EXT}`);
  for (const mesh of json.meshes ?? []) {
    for (const prim of mesh.primitives ?? []) {
      const ext = prim.extensions?.[EXT];
      if (!ext) continue;
      const view = json.bufferViews?.[ext.bufferView];
      check(view, `extension bufferView ${ext.bufferView} exists`);
      if (!view) return { data: null, gltf: json, prim };
      const buf = await bufferData(json, view.buffer, bin, path.dirname(path.resolve(file)));
      const start = view.byteOffset ?? 0;
      check(start + view.byteLength <= buf.length, 'bufferView inside its buffer');
      return { data: buf.subarray(start, start + view.byteLength), gltf: json, prim };
    }
  }
  check(false, `a primitive with ${EXT}`);
  return { data: null, gltf: json, prim: null };
}

function typeName(M, t) {
  for (const n of ['POSITION', 'NORMAL', 'COLOR', 'TEX_COORD', 'GENERIC']) if (M[n] === t) return n;
  return String(t);
}

function floatsOf(M, decoder, mesh, attr) {
  const n = mesh.num_points() * attr.num_components();
  const ptr = M._malloc(n * 4);
  decoder.GetAttributeDataArrayForAllPoints(mesh, attr, M.DT_FLOAT32, n * 4, ptr);
  const out = new Float32Array(M.HEAPF32.buffer, ptr, n).slice();
  M._free(ptr);
  return out;
}

async function main() {
  const args = process.argv.slice(2);
  const file = args[0];
  const pi = args.indexOf('--positions');
  const dumpTo = pi > 0 ? args[pi + 1] : null;
  const xi = args.indexOf('--extract');
  const extractTo = xi > 0 ? args[xi + 1] : null;
  const ai = args.indexOf('--attribute');
  const attrName = ai > 0 ? args[ai + 1] : null;
  const attrTo = ai > 0 ? args[ai + 2] : null;
  if (!file || (pi > 0 && !dumpTo) || (xi > 0 && !extractTo) || (ai > 0 && !attrTo)) {
    console.error('usage: node draco_decode.mjs FILE.drc|FILE.glb|FILE.gltf [--positions OUT.f32] [--extract OUT.drc] ' +
                  '[--attribute NAME OUT.f32]');
    return 2;
  }
  const bytes = new Uint8Array(await readFile(file));
  const checks = [];
  const out = { file };
  let data = bytes;
  let gltf = null;
  let prim = null;
  if (!/\.drc$/i.test(file)) {
    ({ data, gltf, prim } = await extractFromGltf(file, bytes, checks));
    out.container = 'gltf';
  } else {
    out.container = 'drc';
  }
  if (!data) {
    out.checks = checks;
    out.ok = false;
    console.log(JSON.stringify(out));
    return 1;
  }

  if (extractTo) await writeFile(extractTo, data);

  const M = await draco3d.createDecoderModule({});
  const decoder = new M.Decoder();
  const dbuf = new M.DecoderBuffer();
  dbuf.Init(new Int8Array(data.buffer, data.byteOffset, data.byteLength), data.byteLength);
  const geomType = decoder.GetEncodedGeometryType(dbuf);
  if (geomType !== M.TRIANGULAR_MESH) {
    out.error = `not a Draco triangular mesh (geometry type ${geomType})`;
    out.ok = false;
    console.log(JSON.stringify(out));
    return 1;
  }
  const mesh = new M.Mesh();
  const status = decoder.DecodeBufferToMesh(dbuf, mesh);
  if (!status.ok() || mesh.ptr === 0) {
    out.error = `Draco decoding failed: ${status.error_msg()}`;
    out.ok = false;
    console.log(JSON.stringify(out));
    return 1;
  }
  const np = mesh.num_points();
  const nf = mesh.num_faces();
  out.points = np;
  out.faces = nf;
  out.attributes = [];
  for (let i = 0; i < mesh.num_attributes(); i++) {
    const a = decoder.GetAttribute(mesh, i);
    out.attributes.push({
      type: typeName(M, a.attribute_type()),
      unique_id: a.unique_id(),
      components: a.num_components(),
    });
  }

  const posAttr = decoder.GetAttribute(mesh, decoder.GetAttributeId(mesh, M.POSITION));
  const pos = floatsOf(M, decoder, mesh, posAttr);
  const min = [Infinity, Infinity, Infinity];
  const max = [-Infinity, -Infinity, -Infinity];
  for (let i = 0; i < np; i++)
    for (let k = 0; k < 3; k++) {
      const x = pos[3 * i + k];
      if (x < min[k]) min[k] = x;
      if (x > max[k]) max[k] = x;
    }
  out.bbox = { min, max };

  const tptr = M._malloc(nf * 12);
  decoder.GetTrianglesUInt32Array(mesh, nf * 12, tptr);
  const tri = new Uint32Array(M.HEAPU32.buffer, tptr, nf * 3).slice();
  M._free(tptr);
  let collapsed = 0;
  let badIndex = 0;
  for (let f = 0; f < nf; f++) {
    const [a, b, c] = [tri[3 * f], tri[3 * f + 1], tri[3 * f + 2]];
    if (a >= np || b >= np || c >= np) {
      badIndex++;
      continue;
    }
    const e1 = [0, 1, 2].map((k) => pos[3 * b + k] - pos[3 * a + k]);
    const e2 = [0, 1, 2].map((k) => pos[3 * c + k] - pos[3 * a + k]);
    const cx = e1[1] * e2[2] - e1[2] * e2[1];
    const cy = e1[2] * e2[0] - e1[0] * e2[2];
    const cz = e1[0] * e2[1] - e1[1] * e2[0];
    if (cx === 0 && cy === 0 && cz === 0) collapsed++;
  }
  out.collapsed_faces = collapsed;
  checks.push({ ok: badIndex === 0, what: 'every face index below the point count' });

  if (gltf && prim) {
    const ext = prim.extensions[EXT];
    const semantics = {};
    for (const [sem, id] of Object.entries(ext.attributes ?? {})) {
      const a = decoder.GetAttributeByUniqueId(mesh, id);
      semantics[sem] = id;
      checks.push({ ok: a && a.ptr !== 0, what: `${sem}: Draco attribute with unique id ${id}` });
      const acc = gltf.accessors?.[prim.attributes?.[sem]];
      checks.push({ ok: acc, what: `${sem}: listed in primitive.attributes` });
      if (!acc) continue;
      checks.push({ ok: acc.bufferView === undefined, what: `${sem}: accessor without bufferView` });
      checks.push({ ok: acc.count === np, what: `${sem}: accessor count ${acc.count} = ${np} decoded points` });
    }
    for (const sem of Object.keys(prim.attributes ?? {}))
      checks.push({ ok: sem in semantics, what: `${sem}: in the extension's attributes` });
    const idx = gltf.accessors?.[prim.indices];
    checks.push({ ok: idx && idx.count === 3 * nf, what: `indices accessor count = 3 x ${nf} faces` });
    checks.push({ ok: idx && idx.bufferView === undefined, what: 'indices accessor without bufferView' });
    const pacc = gltf.accessors?.[prim.attributes?.POSITION];
    checks.push({ ok: pacc?.min?.length === 3 && pacc?.max?.length === 3, what: 'POSITION accessor has min and max' });
    out.gltf_attributes = semantics;
  }
  out.checks = checks.filter((c) => !c.ok).map((c) => 'FAILED: ' + c.what);
  out.checks_passed = checks.filter((c) => c.ok).length;
  out.ok = checks.every((c) => c.ok);

  if (dumpTo) await writeFile(dumpTo, new Uint8Array(pos.buffer));
  if (attrTo) {
    let a = null;
    if (gltf && prim) {
      const id = prim.extensions[EXT].attributes?.[attrName];
      if (id !== undefined) a = decoder.GetAttributeByUniqueId(mesh, id);
    } else {
      const id = decoder.GetAttributeIdByMetadataEntry(mesh, 'name', attrName);
      if (id >= 0) a = decoder.GetAttribute(mesh, id);
    }
    if (!a || a.ptr === 0) {
      out.ok = false;
      out.checks.push(`FAILED: no Draco attribute ${attrName}`);
    } else {
      out.attribute = { name: attrName, type: typeName(M, a.attribute_type()), components: a.num_components() };
      await writeFile(attrTo, new Uint8Array(floatsOf(M, decoder, mesh, a).buffer));
    }
  }
  M.destroy(mesh);
  M.destroy(dbuf);
  M.destroy(decoder);
  console.log(JSON.stringify(out));
  return out.ok ? 0 : 1;
}

process.exitCode = await main();

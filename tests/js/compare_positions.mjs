// compare_positions.mjs - checks that two vertex sets match point for point within a per-axis tolerance, in any order.
//
// Usage: node compare_positions.mjs A B --tol T
// A and B are raw little-endian float32 x y z files (.f32) or OBJ files
// ("v x y z" lines). Every point of A must have a point of B within T on
// each axis, and every point of B one of A (so a decoder that reorders
// vertices, as Draco's Edgebreaker does, still compares). Prints JSON with
// the counts and the largest per-axis error found each way; exit status 1
// when the counts differ or an error exceeds T.
import { readFile } from 'node:fs/promises';

async function load(file) {
  if (/\.obj$/i.test(file)) {
    const text = await readFile(file, 'utf8');
    const v = [];
    for (const line of text.split('\n')) {
      if (!line.startsWith('v ')) continue;
      const p = line.trim().split(/\s+/);
      v.push(+p[1], +p[2], +p[3]);
    }
    return Float32Array.from(v);
  }
  const b = await readFile(file);
  if (b.length % 12) throw new Error(`${file}: size ${b.length} is not a multiple of 12`);
  return new Float32Array(b.buffer.slice(b.byteOffset, b.byteOffset + b.length));
}

// Largest over the points of a of the per-axis (Chebyshev) distance to the
// nearest point of b within tol (Infinity when a point has none): b sorted
// along its longest axis, each point of a scans the slab of width 2 tol.
function maxNearest(a, b, tol) {
  const nb = b.length / 3;
  const ext = [0, 1, 2].map((k) => {
    let lo = Infinity, hi = -Infinity;
    for (let i = k; i < b.length; i += 3) {
      lo = Math.min(lo, b[i]);
      hi = Math.max(hi, b[i]);
    }
    return hi - lo;
  });
  const ax = ext.indexOf(Math.max(...ext));
  const order = Uint32Array.from({ length: nb }, (_, i) => i).sort((i, j) => b[3 * i + ax] - b[3 * j + ax]);
  const key = Float64Array.from(order, (i) => b[3 * i + ax]);
  let worst = 0;
  const axis = [0, 0, 0];
  for (let i = 0; i < a.length / 3; i++) {
    const x = a[3 * i], y = a[3 * i + 1], z = a[3 * i + 2];
    const c = a[3 * i + ax];
    let lo = 0, hi = nb; // first key >= c - tol
    while (lo < hi) {
      const mid = (lo + hi) >> 1;
      if (key[mid] < c - tol) lo = mid + 1;
      else hi = mid;
    }
    let best = Infinity, bx = 0, by = 0, bz = 0;
    for (let s = lo; s < nb && key[s] <= c + tol; s++) {
      const j = order[s];
      const ex = Math.abs(b[3 * j] - x), ey = Math.abs(b[3 * j + 1] - y), ez = Math.abs(b[3 * j + 2] - z);
      const d = ex > ey ? (ex > ez ? ex : ez) : ey > ez ? ey : ez;
      if (d < best) {
        best = d;
        bx = ex;
        by = ey;
        bz = ez;
      }
    }
    if (best > tol) best = Infinity;
    if (best > worst) worst = best;
    if (best < Infinity) {
      axis[0] = Math.max(axis[0], bx);
      axis[1] = Math.max(axis[1], by);
      axis[2] = Math.max(axis[2], bz);
    }
  }
  return { worst, axis };
}

async function main() {
  const args = process.argv.slice(2);
  const ti = args.indexOf('--tol');
  const tol = ti >= 0 ? Number(args[ti + 1]) : NaN;
  const files = args.filter((_, i) => i !== ti && i !== ti + 1);
  if (files.length !== 2 || !(tol >= 0)) {
    console.error('usage: node compare_positions.mjs A.f32|A.obj B.f32|B.obj --tol T');
    return 2;
  }
  const [a, b] = await Promise.all(files.map(load));
  const ab = maxNearest(a, b, tol);
  const ba = maxNearest(b, a, tol);
  const out = {
    a: files[0],
    b: files[1],
    a_points: a.length / 3,
    b_points: b.length / 3,
    tol,
    max_error_a_to_b: ab.worst === Infinity ? 'none nearby' : ab.worst,
    max_error_b_to_a: ba.worst === Infinity ? 'none nearby' : ba.worst,
    max_axis_error: ab.axis.map((e, k) => Math.max(e, ba.axis[k])),
  };
  out.ok = out.a_points === out.b_points && ab.worst <= tol && ba.worst <= tol;
  console.log(JSON.stringify(out));
  return out.ok ? 0 : 1;
}

process.exitCode = await main();

#!/bin/sh
# t_draco_dense.sh - Draco output of dense lattices (cube r/4) keeps every triangle: no collapsed faces after decoding.
set -e
root=${JETMESH_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
J=${JETMESH:-$root/build/jetmesh}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
for m in mt mc; do
  "$J" convert "$root/samples/jet/jet_099.csv" -r 0.025 -c 0.25 --method $m -o "$tmp/jet_$m.drc" -q
  "$J" convert "$root/samples/jet/jet_099.csv" -r 0.025 -c 0.25 --method $m -o "$tmp/jet_$m.draco.glb" -q
  "$J" convert "$root/samples/jet/jet_099.csv" -r 0.025 -c 0.25 --method $m -o "$tmp/jet_$m.obj" -q
  tris=$(grep -c '^f ' "$tmp/jet_$m.obj")
  for f in "$tmp/jet_$m.drc" "$tmp/jet_$m.draco.glb"; do
    node "$root/tests/js/draco_decode.mjs" "$f" > "$tmp/out.json"
    node -e '
      const r = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
      const want = Number(process.argv[2]);
      if (!r.ok) { console.error("decode checks failed", r); process.exit(1); }
      if (r.faces !== want) { console.error(`faces ${r.faces} != ${want}`); process.exit(1); }
      if (r.collapsed_faces !== 0) { console.error(`${r.collapsed_faces} collapsed faces`); process.exit(1); }
      console.log(`${process.argv[3]}: ${r.faces} faces, none collapsed`);
    ' "$tmp/out.json" "$tris" "$(basename "$f")"
  done
done
# and 12 bits does collapse some (the check above can fail)
"$J" convert "$root/samples/jet/jet_099.csv" -r 0.025 -c 0.25 --draco-position-bits 12 -o "$tmp/low.drc" -q
node "$root/tests/js/draco_decode.mjs" "$tmp/low.drc" > "$tmp/low.json"
node -e 'const r = JSON.parse(require("fs").readFileSync(process.argv[1], "utf8"));
  if (!(r.collapsed_faces > 0)) { console.error("12 bits collapsed nothing: the check is blind"); process.exit(1); }
  console.log(`12 bits: ${r.collapsed_faces} collapsed (as expected)`);' "$tmp/low.json"

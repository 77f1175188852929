#!/bin/sh
# t_splat_variants.sh - the AVX-512, AVX2, SSE2 and plain C field kernels (SPH, anisotropic SPH, metasphere, the interior proofs), the smoothing's and the interpolated attributes' AVX2 and plain C paths, give byte-identical meshes.
set -e
root=${JETMESH_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root"
J=${JETMESH:-$root/build/jetmesh}
B=${JETMESH_BUILD:-$root/build}
[ -f "$B/libjetmesh_formats.a" ] || { echo "FAIL: build first (make all)"; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
in=samples/real/double_dam_break_frame_26_4732_particles.vtk
"$J" convert "$in" -r 0.025 --field sph --method mc -o "$tmp/auto.obj" -q
"$J" convert samples/jet/jet_099.csv -r 0.025 -o "$tmp/meta.obj" -q
"$J" convert "$in" -r 0.025 --field sph --anisotropic --method mc -o "$tmp/aniso.obj" -q
# smoothing: binary PLY (every bit of every float)
smooth="--field sph --method mc --smooth 25 --smooth-normals 10"
"$J" convert "$in" -r 0.025 $smooth -o "$tmp/smooth.ply" -q
# a lattice block: full blocks, whose nodes the box pass proves inside
# (inside_boxes.c: AVX-512 against plain C)
"$J" generate block 40000 -q -o "$tmp/block.xyz"
bargs="-r 0.025 --field sph --smoothing-length 2 --threshold 0.6 --method mc"
"$J" convert "$tmp/block.xyz" $bargs -o "$tmp/block.ply" -q
# velocities on the vertices (interpolate.c: the AVX2 sums against plain C)
"$J" convert "$in" -r 0.025 --field sph --method mc --attributes velocity -o "$tmp/attrs.ply" -q
for v in 1 2 3; do
  # variant 3 (plain C) also builds the smoothing's plain code only
  extra=; [ "$v" = 3 ] && extra=-DJM_SMOOTH_PLAIN
  # only lib/ differs between the variants: the library is built with the
  # variant's flags and linked with the main build's CLI and formats
  make --no-print-directory -j2 BUILD="build-splat$v" CFLAGS="-DJM_SPLAT_VARIANT=$v $extra" "build-splat$v/libjetmesh.a" >/dev/null
  ${CC:-cc} -o "build-splat$v/jetmesh" $(find "$B/cli" -name '*.o' | sort) "$B/libjetmesh_formats.a" \
    "build-splat$v/libjetmesh.a" $(make --no-print-directory -s print-libs)
  "build-splat$v/jetmesh" convert "$in" -r 0.025 --field sph --method mc -o "$tmp/v$v.obj" -q
  if cmp -s "$tmp/auto.obj" "$tmp/v$v.obj"; then
    echo "variant $v: identical ($(grep -c '^f ' "$tmp/v$v.obj") triangles)"
  else
    echo "variant $v differs from the CPU's default kernel"; exit 1
  fi
  "build-splat$v/jetmesh" convert samples/jet/jet_099.csv -r 0.025 -o "$tmp/meta$v.obj" -q
  cmp -s "$tmp/meta.obj" "$tmp/meta$v.obj" || { echo "variant $v: the metasphere runs differ"; exit 1; }
  echo "variant $v: metasphere identical"
  "build-splat$v/jetmesh" convert "$in" -r 0.025 --field sph --anisotropic --method mc -o "$tmp/aniso$v.obj" -q
  cmp -s "$tmp/aniso.obj" "$tmp/aniso$v.obj" || { echo "variant $v: the anisotropic runs differ"; exit 1; }
  echo "variant $v: anisotropic identical"
  "build-splat$v/jetmesh" convert "$in" -r 0.025 $smooth -o "$tmp/smooth$v.ply" -q
  cmp -s "$tmp/smooth.ply" "$tmp/smooth$v.ply" || { echo "variant $v: the smoothed runs differ"; exit 1; }
  echo "variant $v: smoothed identical"
  "build-splat$v/jetmesh" convert "$tmp/block.xyz" $bargs -o "$tmp/block$v.ply" -q
  cmp -s "$tmp/block.ply" "$tmp/block$v.ply" || { echo "variant $v: the lattice block's runs differ"; exit 1; }
  echo "variant $v: lattice block identical"
  "build-splat$v/jetmesh" convert "$in" -r 0.025 --field sph --method mc --attributes velocity -o "$tmp/attrs$v.ply" -q
  cmp -s "$tmp/attrs.ply" "$tmp/attrs$v.ply" || { echo "variant $v: the interpolated velocities differ"; exit 1; }
  echo "variant $v: interpolated velocities identical"
done

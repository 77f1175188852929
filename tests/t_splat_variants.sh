#!/bin/sh
# t_splat_variants.sh - the AVX2, SSE2 and plain C field kernels give byte-identical meshes (any machine, same bits).
set -e
root=${JETMESH_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root"
J=${JETMESH:-$root/build/jetmesh}
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
in=samples/real/double_dam_break_frame_26_4732_particles.vtk
"$J" convert "$in" -r 0.025 --field sph --method mc -o "$tmp/auto.obj" -q
for v in 1 2; do
  make --no-print-directory -j2 BUILD="build-splat$v" CFLAGS="-DJM_SPLAT_VARIANT=$v" "build-splat$v/jetmesh" >/dev/null
  "build-splat$v/jetmesh" convert "$in" -r 0.025 --field sph --method mc -o "$tmp/v$v.obj" -q
  if cmp -s "$tmp/auto.obj" "$tmp/v$v.obj"; then
    echo "variant $v: identical ($(grep -c '^f ' "$tmp/v$v.obj") triangles)"
  else
    echo "variant $v differs from the CPU's default kernel"; exit 1
  fi
done

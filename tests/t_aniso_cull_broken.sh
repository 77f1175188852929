#!/bin/sh
# t_aniso_cull_broken.sh - test_aniso_cull fails when the anisotropic culling is deliberately broken (a block bound too low, partial sums or box bounds too high).
set -u
root=${JETMESH_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
B=${JETMESH_BUILD:-$root/build}
cd "$root" || exit 1
[ -f "$B/tests/test_aniso_cull.o" ] && [ -f "$B/libjetmesh.a" ] || { echo "FAIL: build first (make tests-build)"; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
CC=${CC:-cc}
flags="-std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -Ilib -O2 -fno-math-errno -fno-trapping-math -pthread"
# each broken object replaces the library's own (the linker takes an archive
# member only for symbols still undefined)
# break 1 (the block bound) only shows on the real frames of ../shared/data:
# without them test_aniso_cull skips those, so only break 2 can be checked
SHARED=${JETMESH_SHARED:-$root/../shared}
breaks="1 2 3"
if [ ! -f "$SHARED/data/splashsurf/bunny_frame_14_7705_particles.vtk" ]; then
  echo "break 1: not checked: $SHARED/data not found (its real frames show it)"
  breaks="2 3"
fi
tutil=$(make --no-print-directory -s BUILD="$B" print-tutil)
for brk in $breaks; do
  src=lib/field/aniso/aniso_cull.c; [ "$brk" = 2 ] && src=lib/field/aniso/aniso_splat.c; [ "$brk" = 3 ] && src=lib/field/aniso/aniso_boxes.c
  $CC $flags -DJM_AN_CULL_BREAK=$brk -c "$src" -o "$tmp/broken$brk.o" || { echo "FAIL: compiling $src"; exit 1; }
  # shellcheck disable=SC2086 # tutil: a list of objects
  $CC -o "$tmp/t$brk" "$B/tests/test_aniso_cull.o" $tutil "$tmp/broken$brk.o" "$B/libjetmesh_formats.a" \
      "$B/libjetmesh.a" -lcmocka -ltinygltf -ldraco -lz -lmeshoptimizer -lstdc++ -lm -pthread || { echo "FAIL: linking"; exit 1; }
  if "$tmp/t$brk" >"$tmp/out$brk" 2>&1; then
    echo "FAIL: break $brk ($src) went unnoticed by test_aniso_cull"; exit 1
  fi
  grep -q "FAILED" "$tmp/out$brk" || { cat "$tmp/out$brk"; echo "FAIL: break $brk: no failed test"; exit 1; }
  echo "break $brk ($src): test_aniso_cull fails, as it must ($(grep -c '^\[  FAILED  \]\|^\[  ERROR   \]' "$tmp/out$brk") lines)"
done

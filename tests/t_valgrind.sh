#!/bin/sh
# t_valgrind.sh - a small CLI run (read, mesh with 2 threads, write GLB and Draco) is clean under valgrind memcheck.
set -e
root=${JETMESH_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
J=${JETMESH:-$root/build/jetmesh}
command -v valgrind >/dev/null || { echo "valgrind missing (scripts/deps.sh installs it)"; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
vg="valgrind --error-exitcode=9 --leak-check=full --errors-for-leak-kinds=definite,indirect --quiet"
$vg "$J" convert "$root/samples/jet/jet_080.csv" -r 0.025 -j 2 -o "$tmp/a.glb" -q
$vg "$J" convert "$root/samples/jet/jet_080.csv" -r 0.025 --field sph --method mc -o "$tmp/b.draco.glb" -q
printf 'x,y,z\n1,2,nan\n' > "$tmp/nan.csv"
set +e
$vg "$J" convert "$tmp/nan.csv" -r 0.025 -o "$tmp/c.glb" -q 2>/dev/null
rc=$?
set -e
[ "$rc" = 1 ] || { echo "expected exit 1 for a NaN coordinate under valgrind, got $rc"; exit 1; }
[ -s "$tmp/a.glb" ] && [ -s "$tmp/b.draco.glb" ] && [ ! -e "$tmp/c.glb" ]
echo "valgrind: clean"

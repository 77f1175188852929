#!/bin/sh
# t_splat_variants.sh - every vector level of the one CPU dispatch (plain C, SSE2, AVX2, AVX-512: the field kernels, the interior proofs, the metasphere's probe, normals and finish, the interpolated attributes, both smoothings) and the build with the plain kernels only give byte-identical meshes.
set -e
root=${JETMESH_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root"
J=${JETMESH:-$root/build/jetmesh}
B=${JETMESH_BUILD:-$root/build}
[ -f "$B/libjetmesh_formats.a" ] || { echo "FAIL: build first (make all)"; exit 1; }
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
in=samples/real/double_dam_break_frame_26_4732_particles.vtk
# a lattice block: full blocks, whose nodes the box pass proves inside
"$J" generate block 40000 -q -o "$tmp/block.xyz"
bargs="-r 0.025 --field sph --smoothing-length 2 --threshold 0.6 --method mc"
# name, input, arguments: the cases every build and level must agree on
cases() {
  echo "sph $in -r 0.025 --field sph --method mc"
  echo "meta samples/jet/jet_099.csv -r 0.025"
  echo "aniso $in -r 0.025 --field sph --anisotropic --method mc"
  echo "smooth $in -r 0.025 --field sph --method mc --smooth 25 --smooth-normals 10"
  echo "steady $in -r 0.025 --field sph --method mt --smooth 25 --smooth-normals 10 --smooth-implicit"
  echo "block $tmp/block.xyz $bargs"
  echo "attrs $in -r 0.025 --field sph --method mc --attributes velocity"
}
# mesh NAME COMMAND...: every case into $tmp/NAME.CASE.ply (binary PLY: every bit of every float)
mesh() {
  name=$1; shift
  cases | while read -r c f a; do
    # shellcheck disable=SC2086
    "$@" convert "$f" $a -o "$tmp/$name.$c.ply" -q
  done
}
# same NAME: every case of NAME as the CPU's best level gave it
same() {
  cases | while read -r c f a; do
    cmp -s "$tmp/best.$c.ply" "$tmp/$1.$c.ply" || { echo "FAIL: $1: the $c meshes differ"; exit 1; }
  done
  echo "$1: identical"
}
mesh best "$J"
# the CLI hands JETMESH_TESTING_CPU to the library (jm_testing_force_cpu):
# bench reports the level that ran
for l in 0 1; do
  want=$(printf 'plain C\nSSE2' | sed -n "$((l + 1))p")
  JETMESH_TESTING_CPU=$l "$J" bench jet --repeat 1 --min-time 0 -j 1 -q --json | grep -q "\"cpu_detail\": *\"$want" ||
    { echo "FAIL: JETMESH_TESTING_CPU=$l did not run the $want kernels"; exit 1; }
done
# the hand-written kernels, one level at a time (a level above the CPU's runs the CPU's)
for l in 0 1 2 3; do
  mesh "level$l" env JETMESH_TESTING_CPU=$l "$J"
  same "level$l"
done
# the library built with the plain kernels only (-DJM_NO_CLONES, as the
# ThreadSanitizer build is), linked with the main build's CLI and formats
make --no-print-directory -j2 BUILD=build-noclones CFLAGS=-DJM_NO_CLONES build-noclones/libjetmesh.a >/dev/null
${CC:-cc} -o build-noclones/jetmesh $(find "$B/cli" -name '*.o' | sort) "$B/libjetmesh_formats.a" \
  build-noclones/libjetmesh.a $(make --no-print-directory -s print-libs)
mesh noclones build-noclones/jetmesh
same noclones

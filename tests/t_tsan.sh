#!/bin/sh
# t_tsan.sh - ThreadSanitizer over the threaded paths: the library's pool, and frames converted at once with failures.
set -u
root=${JETMESH_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root" || exit 1
fail() { echo "FAIL: $*"; exit 1; }
# JM_NO_CLONES: the plain-C kernels only (one path per loop to instrument);
# every level gives the same bits (t_splat_variants.sh)
make --no-print-directory -j2 BUILD=build-tsan SAN="-fsanitize=thread" OPT="-O1 -g" LIB_OPT="-O1 -g" \
    CFLAGS="-DJM_NO_CLONES" build-tsan/jetmesh >/dev/null || fail "TSan build failed"
export TSAN_OPTIONS="halt_on_error=1 exitcode=66"
T=$(mktemp -d "${TMPDIR:-/tmp}/jetmesh-tsan.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
J=build-tsan/jetmesh
tsan() { # expected-status args...
    want=$1; shift
    "$J" "$@" >"$T/out" 2>"$T/err"
    st=$?
    [ "$st" != 66 ] || { cat "$T/err"; fail "ThreadSanitizer report: jetmesh $*"; }
    [ "$st" = "$want" ] || { cat "$T/err"; fail "exit $st, not $want: jetmesh $*"; }
}
# the library's threads on one frame, both fields
tsan 0 convert samples/real/double_dam_break_frame_26_4732_particles.vtk -r 0.025 --field sph --method mc -j 4 \
    -o "$T/dam.obj" -q
tsan 0 convert samples/real/double_dam_break_frame_26_4732_particles.vtk -r 0.025 --field sph --anisotropic \
    --method mc -j 4 -o "$T/dam_aniso.obj" -q
tsan 0 convert samples/jet/jet_099.csv -r 0.025 -j 4 -o "$T/jet.glb" -q
# the particle groups' unions, the clip's pieces and the interpolated
# velocities on the threads
tsan 0 convert samples/real/double_dam_break_frame_26_4732_particles.vtk -r 0.025 --field sph --method mc -j 4 \
    --min-piece-particles 3 --min-piece-volume 10 --mesh-aabb-min -1,0,-1 --mesh-aabb-max 0.5,1,1 \
    --mesh-aabb-clamp-vertices --attributes velocity -o "$T/select.ply" -q
# a frame large enough for the grid's chunked passes and two-ended
# placement (2^17 particles or more) and the threads' union-find of the
# mesh's pieces (2^17 triangles or more)
"$J" generate block 140000 -q -o "$T/block.xyz" || fail "generate"
tsan 0 convert "$T/block.xyz" -r 0.025 --field sph --method mc -j 4 -o "$T/block.ply" -q
# frames at once, with a failure in the middle: with and without --keep-going
mkdir "$T/in"
for i in 90 91 92 93 94 95 96; do cp samples/jet/jet_0$i.csv "$T/in/"; done
printf 'x,y,z\n1,2\n' >"$T/in/jet_093.csv"
tsan 1 convert "$T/in/jet_{}.csv" -r 0.025 -o "$T/kg/m_{}.glb" --frame-jobs 3 -j 4 -q --keep-going
[ "$(ls "$T/kg" | wc -l)" = 6 ] || fail "--keep-going: expected 6 outputs"
tsan 1 convert "$T/in/jet_{}.csv" -r 0.025 -o "$T/stop/m_{}.glb" --frame-jobs 3 -j 4 -q
[ "$(ls "$T/stop" | wc -l)" = 3 ] || fail "stop: expected 3 outputs"
# a memory share too small: frames redone alone
tsan 0 convert "$T"/in/jet_09[4-6].csv -r 0.025 -o "$T/mem/" --frame-jobs 3 -j 3 --max-memory 12M -q
echo "ThreadSanitizer: no reports (library pool, selection and clipping, --attributes, a frame of 140,000 particles, frames at once, stop, keep-going, retry alone)"

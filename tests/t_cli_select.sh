#!/bin/sh
# t_cli_select.sh - --particle-aabb-min/max, --min-piece-particles, --min-piece-volume, --mesh-aabb-min/max and --mesh-aabb-clamp-vertices: what they keep, the same bytes on 1 and 2 threads, bench takes them, refused ranges named.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch select
IN="$ROOT/samples/real/double_dam_break_frame_26_4732_particles.vtk"

# bounds BOX_MIN BOX_MAX FILE.obj: every vertex inside the box (x,y,z)
inside() {
    awk -v lo="$1" -v hi="$2" 'BEGIN { split(lo, a, ","); split(hi, b, ",") }
        $1 == "v" { n++; for (k = 1; k <= 3; k++) if ($(k + 1) < a[k] || $(k + 1) > b[k]) { bad++; break } }
        END { if (!n || bad) { printf "%d of %d vertices outside\n", bad, n; exit 1 } }' "$3"
}
verts() { grep -c '^v ' "$1"; }

run 0 convert "$IN" -r 0.025 -o "$T/full.obj"
full=$(verts "$T/full.obj")
read -r lo hi <<EOF
$(awk '$1 == "v" { for (k = 2; k <= 4; k++) { if (!(k in a) || $k < a[k]) a[k] = $k; if (!(k in b) || $k > b[k]) b[k] = $k } }
    END { printf "%g,%g,%g %g,%g,%g\n", a[2], a[3], a[4], b[2], b[3], b[4] }' "$T/full.obj")
EOF
echo "full mesh: $full vertices in $lo .. $hi"

# the particle box: a part of the frame, said on the frame's line; a box
# with no particle: no surface and no warning about the threshold
x0=${lo%%,*}
x1=${hi%%,*}
mid=$(awk -v a="$x0" -v b="$x1" 'BEGIN { printf "%g", (a + b) / 2 }')
run 0 convert "$IN" -r 0.025 -o "$T/pbox.obj" --particle-aabb-min "-10,-10,-10" --particle-aabb-max "$mid,10,10"
grep -q "4732 particles ([0-9]* meshed)" "$T/out" || { cat "$T/out"; fail "the frame's line does not say how many were meshed"; }
pv=$(verts "$T/pbox.obj")
[ "$pv" -gt 100 ] && [ "$pv" -lt "$full" ] || fail "particle box: $pv vertices against $full"
reach=$(awk -v m="$mid" 'BEGIN { printf "%g", m + 0.15 }') # the surface reaches past the particles by under 6 r
inside "-10,-10,-10" "$reach,10,10" "$T/pbox.obj" || fail "particle box: the surface reaches past the box"
run 0 convert "$IN" -r 0.025 -o "$T/none.obj" --particle-aabb-min 10,10,10 --particle-aabb-max 11,11,11
grep -q "(0 meshed), 0 vertices, 0 triangles" "$T/out" || { cat "$T/out"; fail "an empty particle box meshed something"; }
grep -q "warning" "$T/err" && { cat "$T/err"; fail "a warning about the threshold for an empty selection"; }
echo "ok: particle box"

# the clip box, open and closed: every vertex inside it
clo="-10,-10,-10"
chi="$mid,10,10"
run 0 convert "$IN" -r 0.025 -o "$T/clip.obj" --mesh-aabb-min "$clo" --mesh-aabb-max "$chi"
inside "$clo" "$chi" "$T/clip.obj" || fail "clip box: vertices outside"
run 0 convert "$IN" -r 0.025 -o "$T/clamp.obj" --mesh-aabb-min "$clo" --mesh-aabb-max "$chi" --mesh-aabb-clamp-vertices
inside "$clo" "$chi" "$T/clamp.obj" || fail "clamped clip box: vertices outside"
cv=$(verts "$T/clip.obj")
kv=$(verts "$T/clamp.obj")
[ "$cv" -gt 100 ] && [ "$cv" -lt "$kv" ] && [ "$kv" -le "$full" ] || fail "clip: $cv open, $kv clamped, $full in all"
# the clamped mesh closes the cut: vertices on the box's face x = mid
grep -c "^v $mid " "$T/clamp.obj" | awk '$1 < 20 { exit 1 }' || fail "clamped: no face on the cut"
echo "ok: clip box"

# small pieces: the frame has isolated droplets (sphere templates); a
# volume above a droplet's removes them, the particle count removes them too
run 0 convert "$IN" -r 0.025 -o "$T/vol.obj" --min-piece-volume 20
run 0 convert "$IN" -r 0.025 -o "$T/grp.obj" --min-piece-particles 3 -v
vv=$(verts "$T/vol.obj")
gv=$(verts "$T/grp.obj")
[ "$vv" -lt "$full" ] && [ "$gv" -lt "$full" ] || fail "small pieces: $vv and $gv vertices against $full"
grep -q "0 isolated" "$T/out" || { cat "$T/out"; fail "--min-piece-particles 3 left isolated particles"; }
echo "ok: small pieces ($full -> $vv by volume, $gv by particles)"

# everything at once: the same bytes on 1 and 2 threads (and frames at once)
all="--particle-aabb-min -10,-10,-10 --particle-aabb-max $x1,10,10 --min-piece-particles 4 --min-piece-volume 10
     --mesh-aabb-min $clo --mesh-aabb-max $chi --mesh-aabb-clamp-vertices --smooth 3 --attributes velocity"
# shellcheck disable=SC2086
run 0 convert "$IN" -r 0.025 -q -j 1 -o "$T/all1.ply" $all
# shellcheck disable=SC2086
run 0 convert "$IN" -r 0.025 -q -j 2 -o "$T/all2.ply" $all
cmp -s "$T/all1.ply" "$T/all2.ply" || fail "1 and 2 threads differ with every option on"
echo "ok: the same bytes on 1 and 2 threads"

# bench takes them
run 0 bench --scene block:1000 --field sph --method mc --min-time 0 --repeat 1 -j 1 -q \
    --particle-aabb-min 0,0,0 --particle-aabb-max 0.2,1,1 --min-piece-volume 5 \
    --mesh-aabb-min 0,0,0 --mesh-aabb-max 0.15,1,1 --mesh-aabb-clamp-vertices --min-piece-particles 2
echo "ok: bench"

# refused: the option named, the range said, exit 2
bad() { # expected-words... -- args
    want=
    while [ "$1" != -- ]; do want="$want|$1"; shift; done
    shift
    "$J" convert "$IN" -r 0.025 -o "$T/bad.obj" "$@" >"$T/out" 2>"$T/err"
    st=$?
    [ "$st" = 2 ] || { cat "$T/err"; fail "exit $st, not 2: $*"; }
    IFS='|'
    for w in $want; do
        [ -z "$w" ] || grep -qF -- "$w" "$T/err" || { unset IFS; cat "$T/err"; fail "no '$w' in the message for: $*"; }
    done
    unset IFS
}
bad "--particle-aabb-min 0,2,0 and --particle-aabb-max 1,1,1" "on y the minimum 2 is not below the maximum 1" -- \
    --particle-aabb-min 0,2,0 --particle-aabb-max 1,1,1
bad "--mesh-aabb-min" "on z" -- --mesh-aabb-min 0,0,1 --mesh-aabb-max 1,1,1
bad "--particle-aabb-min needs X,Y,Z" -- --particle-aabb-min -1 -1 -1 --particle-aabb-max 1,1,1
bad "--particle-aabb-max needs X,Y,Z" -- --particle-aabb-min 0,0,0 --particle-aabb-max 1,1,inf
bad "--mesh-aabb-max needs --mesh-aabb-min" -- --mesh-aabb-max 1,1,1
bad "--mesh-aabb-clamp-vertices needs the clip box" -- --mesh-aabb-clamp-vertices
bad "the box is empty" -- --particle-aabb-min 0,0,0 --particle-aabb-max 0,0,0
bad "--min-piece-volume must be a number from 0" -- --min-piece-volume -1
bad "--min-piece-particles must be a whole number" -- --min-piece-particles 2.5
"$J" bench --scene jet --mesh-aabb-min 1,1,1 --mesh-aabb-max 0,2,2 >"$T/out" 2>"$T/err"
[ $? = 2 ] && grep -q "on x the minimum 1 is not below the maximum 0" "$T/err" || { cat "$T/err"; fail "bench: a refused box"; }
echo "ok: refused ranges"
echo "all selection checks passed"

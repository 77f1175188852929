#!/bin/sh
# t_cli_animate_limit.sh - --animate refuses a run whose file would pass its limit (2 GiB; lowered here by JETMESH_TEST_ANIMATE_LIMIT, for tests only): exit 3, a message saying why and what to write instead, nothing left behind.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch animlimit

no_temps() {
    left=$(find "$T" -name '*jetmesh-tmp*' -o -name '*.frames')
    [ -z "$left" ] || fail "temporaries left: $left"
}

# the whole jet as one file, no limit in reach: its size
run 0 convert "$S/jet_{}.csv" -r 0.025 --animate -o "$T/all.glb" -q
size=$(wc -c <"$T/all.glb")

# 1. a limit a third of that: refused at the frame that would pass it, the run stops there
JETMESH_TEST_ANIMATE_LIMIT=$((size / 3)) run 3 convert "$S/jet_{}.csv" -r 0.025 --animate -o "$T/big.glb"
for want in "would pass $((size / 3)) bytes at frame" "GLB ends at 4 GiB" "one file per frame" \
            "jetmesh --blender-script" "--draco" "big.glb not written" "frames not converted"; do
    grep -q -e "$want" "$T/err" || { cat "$T/err"; fail "the refusal does not say '$want'"; }
done
grep -q 'warning: .* would pass the' "$T/err" || { cat "$T/err"; fail "no early warning of the limit"; }
[ ! -e "$T/big.glb" ] || fail "a file was written past the limit"
converted=$(grep -c '^frame [0-9]* .*-> ' "$T/out")
[ "$converted" -lt 100 ] || fail "$converted frames converted: the run went on past the limit"
no_temps
echo "ok: refused at a third of the file ($converted frames in): exit 3, why, and per-frame output plus the streaming import"

# --keep-going does not go on either (the file cannot be written), and .gltf + .bin has the same limit
JETMESH_TEST_ANIMATE_LIMIT=$((size / 3)) run 3 convert "$S/jet_{}.csv" -r 0.025 --animate --keep-going -o "$T/kg.glb" -q
grep -q 'cannot hold the whole run' "$T/err" || { cat "$T/err"; fail "--keep-going past the limit"; }
JETMESH_TEST_ANIMATE_LIMIT=$((size / 3)) run 3 convert "$S/jet_{}.csv" -r 0.025 --animate -o "$T/sep/jet.gltf" -q
[ ! -e "$T/sep/jet.gltf" ] && [ ! -e "$T/sep/jet.bin" ] || fail ".gltf or .bin written past the limit"
no_temps
echo "ok: --keep-going stops too; .gltf + .bin refused the same way"

# 2. the boundary: the file fits a limit 8 KiB over its size, not one byte under it
JETMESH_TEST_ANIMATE_LIMIT=$((size + 8192)) run 0 convert "$S/jet_{}.csv" -r 0.025 --animate -o "$T/fits.glb" -q
cmp -s "$T/all.glb" "$T/fits.glb" || fail "the file under a limit differs from the one without"
JETMESH_TEST_ANIMATE_LIMIT=$((size - 1)) run 3 convert "$S/jet_{}.csv" -r 0.025 --animate -o "$T/over.glb" -q
grep -q "would pass $((size - 1)) bytes" "$T/err" || { cat "$T/err"; fail "one byte over: $(cat "$T/err")"; }
[ ! -e "$T/over.glb" ] || fail "a file one byte over the limit was written"
no_temps
echo "ok: a $size-byte file is written under a limit of size + 8 KiB and refused at size - 1"

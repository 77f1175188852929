#!/bin/sh
# t_cli_generate.sh - jetmesh generate: the shipped jet sample regenerates byte for byte; block and spray are as specified.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch gen

# 1. the sample is exactly what `jetmesh generate jet` writes (see samples/README.md)
"$J" generate jet -q -o "$T/jet/jet_%03d.csv" || fail "generate jet"
[ "$(ls "$T/jet" | wc -l)" = 100 ] || fail "expected 100 jet frames"
[ "$(ls "$S" | grep -c '^jet_[0-9][0-9][0-9]\.csv$')" = 100 ] || fail "samples/jet does not hold 100 frames"
diff -r "$T/jet" "$S" >/dev/null || fail "samples/jet differs from 'jetmesh generate jet' (regenerate it)"
"$J" generate jet -q -o "$T/one.csv" || fail "generate jet single"
cmp -s "$T/one.csv" "$S/jet_099.csv" || fail "a single jet file is not frame 99"
"$J" generate jet -q --frames 0:2 -o "$T/b_{}.csv" || fail "generate jet {}"
[ -f "$T/b_0.csv" ] && [ -f "$T/b_2.csv" ] && cmp -s "$T/b_2.csv" "$S/jet_002.csv" || fail "{} frames"
echo "ok: jet sample reproduces byte for byte"

# 2. the jet: 1 particle in frame 0, 125 in frame 99, emitted along +x, falling along -y
[ "$(tail -n +2 "$S/jet_000.csv" | wc -l)" = 1 ] || fail "frame 0 is not 1 particle"
[ "$(tail -n +2 "$S/jet_099.csv" | wc -l)" = 125 ] || fail "frame 99 is not 125 particles"
tail -n +2 "$S/jet_099.csv" | awk -F, '
    { if ($1 < 0 || $1 > 5) bad = 1; if ($2 > 0.001 || $2 < -1) bad = 1; if ($3 > 0.03 || $3 < -0.03) bad = 1 }
    END { exit bad }' || fail "jet particles outside the expected region"
# near the nozzle (x < 0.5 = 20r) neighbours are 1.2r to 1.8r apart: one column
tail -n +2 "$S/jet_099.csv" | sort -t, -k1,1g | awk -F, '
    NR > 1 && $1 < 0.5 { d = sqrt(($1-px)^2 + ($2-py)^2 + ($3-pz)^2); if (d < 0.03 || d > 0.045) bad = 1; n++ }
    { px = $1; py = $2; pz = $3 }
    END { exit bad || n < 8 }' || fail "the jet is not a 1.5r column near the nozzle"
echo "ok: jet shape"

# 3. block: N lines, lattice 2r jittered by at most 0.1r, deterministic, seeded
"$J" generate block 1000 -q -o "$T/block.csv" || fail "generate block"
[ "$(tail -n +2 "$T/block.csv" | wc -l)" = 1000 ] || fail "block 1000 has not 1000 particles"
"$J" generate block 1000 -q -o "$T/block2.csv" && cmp -s "$T/block.csv" "$T/block2.csv" || fail "block not deterministic"
"$J" generate block 1000 -q --seed 7 -o "$T/block3.csv" && ! cmp -s "$T/block.csv" "$T/block3.csv" || fail "--seed changes nothing"
# every coordinate is within 0.1r = 0.0025 of a multiple of 2r = 0.05 (lattice centred: 10 per side -> offset r)
tail -n +2 "$T/block.csv" | awk -F, '
    { for (i = 1; i <= 3; i++) { v = ($i + 0.225) / 0.05; d = (v - int(v + 0.5)) * 0.05; if (d < 0) d = -d; if (d > 0.00251) bad = 1 } }
    END { exit bad }' || fail "block is not a jittered 2r lattice"
echo "ok: block"

# 4. spray: isolated (every pair at least 8r = 0.2 apart); XYZ output is 12 bytes a particle
"$J" generate spray 300 -q -o "$T/spray.csv" || fail "generate spray"
tail -n +2 "$T/spray.csv" | awk -F, '
    { x[NR] = $1; y[NR] = $2; z[NR] = $3 }
    END { for (i = 1; i <= NR; i++) for (j = i + 1; j <= NR; j++) {
            d = (x[i]-x[j])^2 + (y[i]-y[j])^2 + (z[i]-z[j])^2; if (d < 0.2 * 0.2 - 1e-9) exit 1 }
          exit NR != 300 }' || fail "spray particles closer than 8r"
"$J" generate spray 300 -q -o "$T/spray.xyz" || fail "generate spray xyz"
[ "$(wc -c <"$T/spray.xyz")" = 3600 ] || fail "spray.xyz is not 300 x 12 bytes"
# every spray particle meshes as its own sphere
"$J" convert "$T/spray.xyz" -r 0.025 -v -o "$T/spray.obj" >"$T/out" 2>&1 || { cat "$T/out"; fail "convert spray.xyz"; }
grep -q ': 300 particles,' "$T/out" || fail "spray.xyz does not read back as 300 particles"
grep -q ' 300 isolated,' "$T/out" || { cat "$T/out"; fail "spray particles are not all isolated"; }
"$J" convert "$T/spray.csv" -r 0.025 -o "$T/spray2.obj" -q || fail "convert spray.csv"
[ "$(grep -c '^f ' "$T/spray.obj")" = "$(grep -c '^f ' "$T/spray2.obj")" ] || fail "CSV and XYZ meshes differ"
echo "ok: spray"

# 5. empty scenes and sequences of block
"$J" generate block 0 -q -o "$T/empty.csv" || fail "block 0"
[ "$(cat "$T/empty.csv")" = "x,y,z" ] || fail "block 0 is not an empty CSV"
"$J" generate block 8 -q --frames 0:1 -o "$T/bs_{}.csv" || fail "block sequence"
! cmp -s "$T/bs_0.csv" "$T/bs_1.csv" || fail "block frames do not differ (seed S+F)"
"$J" generate block 8 -q --seed 2 -o "$T/bs2.csv" && cmp -s "$T/bs_1.csv" "$T/bs2.csv" || fail "frame F is not seed S+F"
echo "all generate checks passed"

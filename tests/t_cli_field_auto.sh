#!/bin/sh
# t_cli_field_auto.sh - no --field: the metasphere for the jet and spray, SPH + marching cubes for bulk fluid, one choice per run, said in the summary, -v and the statistics.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch fieldauto
REAL="$ROOT/samples/real/double_dam_break_frame_26_4732_particles.vtk"

# the shipped jet: the metasphere with marching tetrahedra, today's bytes
run 0 convert "$S/jet_099.csv" -r 0.025 -o "$T/auto.glb"
grep -q '; field metasphere, method mt (auto)$' "$T/out" || { cat "$T/out"; fail "jet: not the metasphere by choice"; }
run 0 convert "$S/jet_099.csv" -r 0.025 --field metasphere --method mt -o "$T/given.glb"
grep -q '(given)$' "$T/out" || fail "explicit field not reported as given"
cmp -s "$T/auto.glb" "$T/given.glb" || fail "the jet with no --field differs from --field metasphere --method mt"
echo "ok: jet: metasphere + mt, the same bytes as given explicitly"

# spray of droplets: the metasphere
"$J" generate spray 300 -q -o "$T/spray.csv" || fail "generate spray"
run 0 convert "$T/spray.csv" -r 0.025 -o "$T/spray.obj" -v
grep -q 'field metasphere, method mt (auto: 0.00 neighbours in frame' "$T/out" || { cat "$T/out"; fail "spray: -v does not say the choice"; }

# bulk fluid, a real frame and a block: SPH with marching cubes
run 0 convert "$REAL" -r 0.025 -o "$T/real.obj" --stats "$T/real.csv"
grep -q '; field sph, method mc (auto)$' "$T/out" || { cat "$T/out"; fail "real frame: not sph/mc"; }
grep -q '^# summary field=sph$' "$T/real.csv" && grep -q '^# summary method=mc$' "$T/real.csv" &&
    grep -q '^# summary field_choice=auto$' "$T/real.csv" && grep -q '^# summary neighbours=' "$T/real.csv" ||
    fail "the statistics do not record the choice"
[ -z "$(cat "$T/err")" ] || { cat "$T/err"; fail "unexpected warning"; }
run 0 convert "$REAL" -r 0.025 --field sph --method mc -o "$T/real2.obj"
cmp -s "$T/real.obj" "$T/real2.obj" || fail "the real frame with no --field differs from --field sph --method mc"
"$J" generate block 2000 -q -o "$T/block.csv" || fail "generate block"
run 0 convert "$T/block.csv" -r 0.025 -o "$T/block.obj" --stats "$T/block.json"
grep -q '"field": "sph", "method": "mc", "field_choice": "auto", "neighbours": ' "$T/block.json" ||
    fail "JSON statistics do not record the choice"
echo "ok: bulk fluid (a real frame, a block): sph + mc, in the summary and the statistics"

# --method given with the auto field: the method stays
run 0 convert "$T/block.csv" -r 0.025 --method mt -o "$T/block_mt.obj"
grep -q '; field sph, method mt (auto)$' "$T/out" || { cat "$T/out"; fail "--method mt lost with the auto field"; }

# the metasphere given on bulk fluid: one warning, with the alternative
run 0 convert "$T/block.csv" -r 0.025 --field metasphere -o "$T/block_meta.obj"
[ "$(grep -c 'warning: .*looks like bulk fluid.*--field sph --method mc' "$T/err")" = 1 ] ||
    { cat "$T/err"; fail "no warning for the metasphere on bulk fluid"; }

# --threshold means something else for each field: it needs --field
run 2 convert "$T/block.csv" -r 0.025 --threshold 0.5 -o "$T/x.obj"
grep -q -- '--threshold.*give --field metasphere or --field sph' "$T/err" || fail "no usage error for --threshold alone"

# a jet filling a pool: sparse first, dense later; one field throughout,
# from the first frame, said once in the summary
mkdir "$T/pool"
cp "$S/jet_030.csv" "$T/pool/f_1.csv"
cp "$T/block.csv" "$T/pool/f_2.csv"
run 0 convert "$T/pool/f_{}.csv" -r 0.025 -o "$T/pool/m_{}.ply" --stats "$T/pool/s.csv" -v
grep -q 'field metasphere, method mt (auto: .* neighbours in frame 1)' "$T/out" || { cat "$T/out"; fail "pool: the choice is not from frame 1"; }
grep -q '; field metasphere, method mt (auto)$' "$T/out" || fail "pool: the summary does not say metasphere"
grep -q '^# summary field=metasphere$' "$T/pool/s.csv" || fail "pool: statistics"
run 0 convert "$T/pool/f_2.csv" -r 0.025 --field metasphere --method mt -o "$T/pool/ref_2.ply"
cmp -s "$T/pool/m_2.ply" "$T/pool/ref_2.ply" || fail "pool: the dense frame was not meshed with the metasphere"
# the other way round: dense first, sph for all
cp "$T/block.csv" "$T/pool/g_1.csv"
cp "$S/jet_030.csv" "$T/pool/g_2.csv"
run 0 convert "$T/pool/g_{}.csv" -r 0.025 -o "$T/pool/n_{}.ply"
grep -q '; field sph, method mc (auto)$' "$T/out" || fail "pool reversed: not sph"
echo "ok: a sequence keeps the field of its first frame and says which"
# --field sph alone takes the documented default method, mc (it took mt)
run 0 convert "$T/block.csv" -r 0.025 --field sph -o "$T/sph_default.ply"
run 0 convert "$T/block.csv" -r 0.025 --field sph --method mc -o "$T/sph_mc.ply"
run 0 convert "$T/block.csv" -r 0.025 --field sph --method mt -o "$T/sph_mt.ply"
cmp -s "$T/sph_default.ply" "$T/sph_mc.ply" || fail "--field sph without --method is not mc"
cmp -s "$T/sph_mc.ply" "$T/sph_mt.ply" && fail "mc and mt gave the same mesh: the check above proves nothing"
echo "ok: --field sph defaults to marching cubes, as --help and the man page say"
echo "all field choice checks passed"

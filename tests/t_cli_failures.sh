#!/bin/sh
# t_cli_failures.sh - a bad frame among good ones, --keep-going, untouched outputs, no overwriting inputs, --resume, exit 3.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch fail

no_temps() {
    if find "$T" -name '*jetmesh-tmp*' | grep -q .; then fail "temporaries left: $(find "$T" -name '*jetmesh-tmp*')"; fi
}

mkdir "$T/in" "$T/out_dir"
for i in 20 21 22 23; do cp "$S/jet_0$i.csv" "$T/in/"; done
printf 'x,y,z\n0.1,0.2\n' >"$T/in/jet_021.csv" # frame 21 is malformed
# an existing good output of the failing frame must survive
cp "$S/jet_099.csv" "$T/keep.csv"
run 0 convert "$T/keep.csv" -r 0.025 -o "$T/out_dir/m_021.obj"
cp "$T/out_dir/m_021.obj" "$T/m_021.saved"

# 1. without --keep-going: stops at frame 21, exit 1, names the file
run 1 convert "$T/in/jet_{}.csv" -r 0.025 -o "$T/out_dir/m_{}.obj"
grep -q 'jet_021.csv:2:' "$T/err" || { cat "$T/err"; fail "the error does not name the file and line"; }
[ -f "$T/out_dir/m_020.obj" ] || fail "frame 20 was not converted"
[ ! -e "$T/out_dir/m_022.obj" ] && [ ! -e "$T/out_dir/m_023.obj" ] || fail "went on after the failure"
grep -q 'keep-going' "$T/err" || fail "no hint that --keep-going converts the others"
cmp -s "$T/out_dir/m_021.obj" "$T/m_021.saved" || fail "the existing output of the failed frame changed"
no_temps
echo "ok: stops at the first failure with exit 1; existing output untouched"

# 2. with --keep-going: the others are converted, exit 1, failures listed at the end
run 1 convert "$T/in/jet_{}.csv" -r 0.025 -o "$T/out_dir/m_{}.obj" --keep-going
for i in 20 22 23; do [ -f "$T/out_dir/m_0$i.obj" ] || fail "frame $i not converted with --keep-going"; done
grep -q '1 of 4 frames failed' "$T/err" || { cat "$T/err"; fail "no failure list"; }
tail -n 1 "$T/err" | grep -q '^  frame 21: .*jet_021.csv' || { cat "$T/err"; fail "the list does not end with frame 21"; }
[ "$(grep -c '^frame ' "$T/out")" = 3 ] || fail "expected 3 frame lines"
cmp -s "$T/out_dir/m_021.obj" "$T/m_021.saved" || fail "the existing output of the failed frame changed"
no_temps
echo "ok: --keep-going converts the others and lists the failure"

# 3. a missing frame of a %03d range is a failed frame naming the file
run 1 convert "$T/in/jet_%03d.csv" --frames 22:24 -r 0.025 -o "$T/out_dir/r_{}.obj" --keep-going
grep -q 'jet_024.csv' "$T/err" || { cat "$T/err"; fail "the missing file is not named"; }
[ -f "$T/out_dir/r_022.obj" ] && [ -f "$T/out_dir/r_023.obj" ] || fail "frames 22, 23 not converted"
echo "ok: missing file in a range"

# 4. --resume: skips existing outputs (which stay untouched), converts the rest
rm "$T/out_dir/m_022.obj"
cp "$T/out_dir/m_020.obj" "$T/m_020.saved"
touch -t 200001010000 "$T/out_dir/m_020.obj"
printf 'x,y,z\n0.1,0.2,0.3\n' >"$T/in/jet_021.csv" # repaired
run 0 convert "$T/in/jet_{}.csv" -r 0.025 -o "$T/out_dir/m_{}.obj" --resume
[ "$(grep -c ': skipped, .* exists (--resume)$' "$T/out")" = 3 ] || { cat "$T/out"; fail "expected 3 skipped frames"; }
grep -q '^frame 22 .*-> .*m_022.obj$' "$T/out" || fail "frame 22 not converted by --resume"
[ -f "$T/out_dir/m_022.obj" ] || fail "m_022.obj missing after --resume"
cmp -s "$T/out_dir/m_021.obj" "$T/m_021.saved" || fail "--resume rewrote an existing output"
[ -z "$(find "$T/out_dir/m_020.obj" -newer "$T/m_020.saved")" ] || fail "--resume touched m_020.obj"
grep -q '(0 failed, 3 skipped)' "$T/out" || fail "summary does not count skipped frames"
echo "ok: --resume"

# 5. never write over an input
cp "$T/in/jet_020.csv" "$T/in.saved"
run 2 convert "$T/in/jet_020.csv" -r 0.025 --format obj -o "$T/in/jet_020.csv"
grep -q 'refusing to overwrite' "$T/err" || fail "no refusal message"
ln -s "$T/in/jet_020.csv" "$T/link.obj"
run 2 convert "$T/in/jet_020.csv" -r 0.025 -o "$T/link.obj"
ln "$T/in/jet_020.csv" "$T/hard.obj"
run 2 convert "$T/in/jet_020.csv" -r 0.025 -o "$T/hard.obj"
run 2 convert "$T/in/jet_{}.csv" -r 0.025 --format obj -o "$T/in/jet_{}.csv"
run 2 convert "$T/in/jet_020.csv" -r 0.025 -o "$T/x.obj" --stats "$T/in/jet_020.csv"
cmp -s "$T/in/jet_020.csv" "$T/in.saved" || fail "an input was overwritten"
for i in 20 21 22 23; do [ "$(head -n 1 "$T/in/jet_0$i.csv")" = "x,y,z" ] || fail "input $i damaged"; done
echo "ok: refuses to overwrite inputs (same path, symlink, hard link, template, stats)"

# 6. resource errors exit 3 with the estimate and the hint
run 3 convert "$S/jet_099.csv" -r 0.025 -o "$T/big.obj" --max-memory 64K
grep -q 'raise --max-memory' "$T/err" || { cat "$T/err"; fail "no --max-memory hint"; }
grep -Eq 'about [0-9.]+ [KMG]?i?B' "$T/err" || { cat "$T/err"; fail "no estimate in the message"; }
[ ! -e "$T/big.obj" ] || fail "output written despite the limit"
run 0 convert "$S/jet_099.csv" -r 0.025 -o "$T/big.obj" --max-memory 0
run 0 convert "$S/jet_099.csv" -r 0.025 -o "$T/big2.obj" --max-memory 1G
# a resource failure wins over ordinary ones for the exit status, with --keep-going
printf 'x,y,z\n1,2\n' >"$T/bad.csv"
run 3 convert "$T/bad.csv" "$S/jet_099.csv" -r 0.025 -o "$T/mix/" --max-memory 64K --keep-going
grep -q '2 of 2 frames failed' "$T/err" || { cat "$T/err"; fail "expected both frames to fail"; }
no_temps
echo "ok: exit 3 for --max-memory"

# 7. a write failure (output directory is a file) fails the frame, names the file
: >"$T/notadir"
run 1 convert "$S/jet_020.csv" -r 0.025 -o "$T/notadir/x.obj"
grep -q 'notadir' "$T/err" || { cat "$T/err"; fail "write error does not name the path"; }

# 8. a lattice absurdly fine for the particles' spread: refused at once (not
#    hours of sampling), even with no memory limit, with the option to change
run 3 convert "$S/jet_050.csv" -r 1 -c 0.001 --field sph --max-memory 0 -o "$T/fine.glb"
grep -q -- '--cube-size' "$T/err" || { cat "$T/err"; fail "no hint to raise --cube-size"; }
[ ! -e "$T/fine.glb" ] || fail "an output was written for a refused frame"
echo "ok: absurd lattice refused"
echo "all failure checks passed"

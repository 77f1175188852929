#!/bin/sh
# t_cli_outputs.sh - a run's outputs never overwrite each other or an input, an unwritable place fails before meshing, and plans, threads and memory shares stay bounded.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch outputs
F="$S/jet_099.csv"

# outputs that are one file: refused before anything is written
printf 'keep\n' >"$T/m.obj"
run 2 convert "$F" -r 0.025 -o "$T/m.obj" --stats-svg "$T/m.obj"
grep -q -- "--stats-svg FILE must end in .svg" "$T/err" || { cat "$T/err"; fail "--stats-svg m.obj accepted"; }
run 2 convert "$F" -r 0.025 -o "$T/n.obj" --stats "$T/s.csv" --stats-svg "$T/s.csv"
run 2 convert "$F" -r 0.025 --format obj -o "$T/m.json" --stats "$T/m.json"
grep -q "the output of frame 99 and --stats would both write" "$T/err" || { cat "$T/err"; fail "mesh and --stats on one file"; }
mkdir "$T/d"
run 2 convert "$F" -r 0.025 --format obj -o "$T/d/m.csv" --stats "$T/d/../d/./m.csv"
grep -q "would both write" "$T/err" || { cat "$T/err"; fail "one file spelled two ways"; }
ln -s "$T/d" "$T/link"
run 2 convert "$F" -r 0.025 --format obj -o "$T/d/m.csv" --stats "$T/link/m.csv"
grep -q "would both write" "$T/err" || { cat "$T/err"; fail "one file through a symbolic link"; }
run 2 convert "$F" -r 0.025 -o "$T/x.glb" --stats-svg "$T/chart.txt"
[ "$(cat "$T/m.obj")" = keep ] || fail "a refused run touched an existing file"
[ ! -e "$T/n.obj" ] && [ ! -e "$T/s.csv" ] && [ ! -e "$T/m.json" ] && [ ! -e "$T/d/m.csv" ] || fail "a refused run wrote something"
echo "ok: outputs that are one file are refused, nothing written"

# an unwritable place fails before any frame is meshed, even with --keep-going
run 1 convert "$S/jet_09{}.csv" -r 0.025 --keep-going -o /dev/null/sub/m_{}.obj
grep -q "cannot create the directory of /dev/null/sub/m_" "$T/err" || { cat "$T/err"; fail "no up-front directory error"; }
if grep -q '^frame ' "$T/out"; then fail "frames were meshed before the directory error"; fi
run 1 convert "$S/jet_09{}.csv" -r 0.025 --keep-going -o /proc/m_{}.obj
grep -q "cannot write in the directory of /proc/m_" "$T/err" || { cat "$T/err"; fail "no up-front unwritable error"; }
if ls -A /proc | grep -q jetmesh-probe; then fail "probe left"; fi
echo "ok: an unwritable output directory fails before meshing"

# a newline in a file name stays escaped in the frame line: one line a frame
nl='
'
cp "$F" "$T/a${nl}b.csv"
run 0 convert "$T/a${nl}b.csv" -r 0.025 -o "$T/o${nl}p.obj"
[ "$(wc -l <"$T/out")" = 2 ] || { cat "$T/out"; fail "the frame line was split by a newline"; }
grep -q 'a\\nb.csv: 125 particles.* -> .*o\\np.obj$' "$T/out" || { cat "$T/out"; fail "newline not escaped"; }
echo "ok: control characters in names are escaped in the report"

# threads: -j beyond what a context starts is capped, and said
run 0 convert "$S/jet_09{}.csv" -r 0.025 -j 4096 -o "$T/j/" -v
grep -q 'threads 256 (-j 4096 capped at 256), frames at once 10' "$T/out" || { head -1 "$T/out"; fail "-j not capped or not said"; }

# a memory limit shared by frames at once: a share of 0 is no "no limit"
run 3 convert "$S/jet_{}.csv" -r 0.025 --max-memory 15 --frame-jobs 16 -o "$T/mm/" -q
run 3 convert "$S/jet_{}.csv" -r 0.025 --max-memory 15 --frame-jobs 1 -o "$T/mm1/" -q
[ -z "$(ls -A "$T/mm" 2>/dev/null)" ] || fail "frames converted under a 15-byte limit"
echo "ok: -j capped and said; a tiny --max-memory refuses with frames at once too"

# the plan is bounded and says how many frames
run 2 convert "$T/none_%07d.csv" --frames 0:9999999 -r 0.025 -o "$T/p_{}.obj"
grep -q "names 10000000 frames, more than the 1000000 one run plans" "$T/err" || { cat "$T/err"; fail "unbounded plan"; }
echo "all output checks passed"

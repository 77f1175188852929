#!/bin/sh
# t_cli_frame_jobs.sh - frames converted at once (--frame-jobs) give the bytes, lines and order of one at a time; memory shares.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch fjobs

mkdir "$T/in"
for i in 90 91 92 93 94 95 96 97 98 99; do cp "$S/jet_0$i.csv" "$T/in/"; done
# frame lines without their times, which vary
# statistics rows: index, input, counts and bytes (not the output path or times)
rows() { grep -v '^#' "$1" | cut -d, -f1,2,4-8; }
lines() { grep '^frame ' "$1" | sed -e 's/, [0-9.]* ms -> .*\/\([^/]*\)$/ -> \1/'; }

# 1. the same bytes, the same lines in the same order, whatever the frames at
#    once and the threads; and the statistics rows in frame order
run 0 convert "$T/in/jet_{}.csv" -r 0.025 -o "$T/one/m_{}.glb" --frame-jobs 1 -j 2 --stats "$T/one.csv"
lines "$T/out" >"$T/one.lines"
for cfg in "2 2" "4 2" "3 3" "16 1" "0 0"; do
    set -- $cfg
    run 0 convert "$T/in/jet_{}.csv" -r 0.025 -o "$T/m$1_$2/m_{}.glb" --frame-jobs "$1" -j "$2" --stats "$T/s$1_$2.csv"
    for i in 90 91 92 93 94 95 96 97 98 99; do
        cmp -s "$T/one/m_0$i.glb" "$T/m$1_$2/m_0$i.glb" || fail "frame $i differs with --frame-jobs $1 -j $2"
    done
    lines "$T/out" | diff "$T/one.lines" - >/dev/null || { lines "$T/out"; fail "lines differ with --frame-jobs $1 -j $2"; }
    [ "$(rows "$T/s$1_$2.csv")" = "$(rows "$T/one.csv")" ] ||
        fail "statistics rows out of order with --frame-jobs $1 -j $2"
done
[ "$(grep -c '^frame ' "$T/one.lines")" = 10 ] || fail "expected 10 frame lines"
echo "ok: same bytes, lines and statistics order for 1, 2, 3, 4, 16 and auto frames at once"

# 2. a failure in the middle, without --keep-going: frames after it made ahead
#    are removed, so the disk holds what one at a time leaves
printf 'x,y,z\n0.1,0.2\n' >"$T/in/jet_093.csv"
run 1 convert "$T/in/jet_{}.csv" -r 0.025 -o "$T/stop/m_{}.obj" --frame-jobs 4 -j 4
for i in 90 91 92; do [ -f "$T/stop/m_0$i.obj" ] || fail "frame $i before the failure not converted"; done
for i in 93 94 95 96 97 98 99; do [ ! -e "$T/stop/m_0$i.obj" ] || fail "frame $i after the failure was left on disk"; done
grep -q '6 frames not converted' "$T/err" || { cat "$T/err"; fail "wrong count of frames not converted"; }
[ "$(grep -c '^frame ' "$T/out")" = 3 ] || fail "expected 3 frame lines"
if find "$T" -name '*jetmesh-tmp*' | grep -q .; then fail "temporaries left"; fi
run 1 convert "$T/in/jet_{}.csv" -r 0.025 -o "$T/kg/m_{}.obj" --frame-jobs 4 -j 4 --keep-going
[ "$(find "$T/kg" -name '*.obj' | wc -l)" = 9 ] || fail "--keep-going did not convert the 9 others"
tail -n 1 "$T/err" | grep -q '^  frame 93: ' || { cat "$T/err"; fail "failure list wrong"; }
echo "ok: a failure stops where one at a time stops; --keep-going converts the others"
cp "$S/jet_093.csv" "$T/in/"

# 3. memory shares: a frame over its share of --max-memory (the limit / frames
#    at once) but within the whole limit is converted alone, not failed
est() { # threads: the library's estimate for jet_099, in KiB, from its refusal
    "$J" convert "$S/jet_099.csv" -r 0.025 -o "$T/x.glb" -j "$1" --max-memory 64K 2>&1 |
        sed -n 's/.*need about \([0-9.]*\) \([KM]\)iB.*/\1 \2/p' |
        awk '{ printf "%d", $2 == "M" ? $1 * 1024 : $1 }'
}
e1=$(est 1) e2=$(est 2)
[ -n "$e1" ] && [ -n "$e2" ] || fail "no estimate in the refusal message"
limit=$((e2 + 64))
[ $((limit / 2)) -lt "$e1" ] || fail "test set-up: half of ${limit}K is not under the 1-thread estimate ${e1}K"
run 3 convert "$T/in/jet_099.csv" -r 0.025 -o "$T/half.glb" -j 1 --max-memory "$((limit / 2))K"
mkdir "$T/same"
for i in 1 2 3; do cp "$S/jet_099.csv" "$T/same/f_$i.csv"; done
run 0 convert "$T/same/f_{}.csv" -r 0.025 -o "$T/mem/m_{}.glb" --frame-jobs 2 -j 2 --max-memory "${limit}K"
for i in 1 2 3; do
    cmp -s "$T/one/m_099.glb" "$T/mem/m_$i.glb" || fail "frame $i differs after a retry alone"
done
echo "ok: frames over their share of --max-memory (${limit}K / 2 < ${e1}K) are converted alone"
echo "all frame-jobs checks passed"

#!/bin/sh
# t_cli_shard.sh - --shard I/N and slurm: N shards convert every frame once, byte-identical to one run; stats merge rules.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch shard
IN="$S/jet_%03d.csv"

# the reference: one run
run 0 convert "$IN" --frames 0:99 -r 0.025 -q -o "$T/ref/jet_{}.glb" --stats "$T/ref.csv"

# 3 shards (100 = 34 + 33 + 33), one after the other; CSV and JSON stats
for i in 0 1 2; do
    ext=csv; [ "$i" = 1 ] && ext=json
    run 0 convert "$IN" --frames 0:99 -r 0.025 -o "$T/sh/jet_{}.glb" --shard "$i/3" --stats "$T/st_$i.$ext"
    grep -q "^shard $i/3: 3[34] of the 100 frames" "$T/out" || { cat "$T/out"; fail "shard $i: no share line"; }
done
# interleaved: shard 1 converted positions 1, 4, 7...
grep -q "^frame 1 .* -> $T/sh/jet_001.glb" "$T/out" && fail "shard 2 converted frame 1" || true
grep -q "^frame 2 .*jet_002.csv" "$T/out" || fail "shard 2 did not convert frame 2"
grep -q "^frame 5 .*jet_005.csv" "$T/out" || fail "shard 2 did not convert frame 5"
diff -r "$T/ref" "$T/sh" >/dev/null || fail "shards' outputs differ from one run's"
[ "$(ls "$T/sh" | wc -l)" = 100 ] || fail "not 100 outputs"

# merged: every frame once, in frame order, summary over all
run 0 stats merge "$T/st_2.csv" "$T/st_0.csv" "$T/st_1.json" -o "$T/all.csv" --svg "$T/all.svg"
grep -q "^merged 3 files: 100 frames (100 ok, 0 failed, 0 skipped)" "$T/out" || { cat "$T/out"; fail "merge line"; }
grep -v '^#' "$T/all.csv" | tail -n +2 | cut -d, -f1 >"$T/idx"
seq 0 99 | cmp -s - "$T/idx" || fail "merged rows are not frames 0..99 once, in order"
for k in frames=100 ok=100 failed=0 skipped=0 shards=3 field=metasphere method=mt field_choice=auto; do
    grep -q "^# summary $k\$" "$T/all.csv" || fail "merged summary lacks $k"
done
# the summary's times are recomputed over all frames: the same as one run's
# summary computed from the same rows (ms_total_max is the max of the rows)
max=$(grep -v '^#' "$T/all.csv" | awk -F, 'NR == 1 { for (i = 1; i <= NF; i++) if ($i == "ms_total") c = i; next }
  { if ($c > m) m = $c } END { printf "%.3f", m }')
grep -q "^# summary ms_total_max=$max\$" "$T/all.csv" || fail "ms_total_max is not the rows' max $max"
[ "$(head -n 1 "$T/all.csv")" = "$(head -n 1 "$T/ref.csv")" ] || fail "merged header differs from convert's"
if command -v xmllint >/dev/null 2>&1; then
    xmllint --noout "$T/all.svg" || fail "merged SVG is not well-formed"
fi
grep -q "100 frames" "$T/all.svg" || fail "chart does not cover 100 frames"
# JSON output, read back
run 0 stats merge "$T/all.csv" -o "$T/all.json" -q
run 0 stats merge "$T/all.json" -o "$T/again.csv" -q
[ "$(grep -c ',ok,' "$T/again.csv")" = 100 ] || fail "JSON round trip"
grep -q '^# summary field=metasphere$' "$T/again.csv" || fail "the field lost through JSON"
# shards meshed with different fields: said, and no field in the merge
sed 's/^# summary field=metasphere$/# summary field=sph/' "$T/st_0.csv" >"$T/other_0.csv"
run 0 stats merge "$T/other_0.csv" "$T/st_1.json" "$T/st_2.csv" -o "$T/mixed.csv"
grep -q "warning: .* was meshed with field sph, method mt, but .* with metasphere, mt" "$T/err" ||
    { cat "$T/err"; fail "no warning for shards of different fields"; }
if grep -q '^# summary field=' "$T/mixed.csv"; then fail "a field written for mixed shards"; fi

# a frame ok in two files: an error naming both
run 1 stats merge "$T/st_0.csv" "$T/st_0.csv" -o "$T/dup.csv"
grep -q "frame 0 (.*jet_000.csv) was converted in both .*st_0.csv and .*st_0.csv" "$T/err" || { cat "$T/err"; fail "overlap message"; }
[ ! -e "$T/dup.csv" ] || fail "wrote a report despite the overlap"

# --resume across shards: a second pass skips everything; ok wins over skipped
run 0 convert "$IN" --frames 0:99 -r 0.025 -q -o "$T/sh/jet_{}.glb" --shard 0/3 --resume --stats "$T/again_0.csv"
[ "$(grep -c ',skipped,' "$T/again_0.csv")" = 34 ] || fail "resumed shard did not skip its 34 frames"
run 0 stats merge "$T/st_0.csv" "$T/again_0.csv" "$T/st_1.json" "$T/st_2.csv" -o "$T/m.csv" -q
grep -q "^# summary ok=100" "$T/m.csv" || fail "ok row did not win over skipped"
run 0 stats merge "$T/again_0.csv" "$T/st_1.json" "$T/st_2.csv" -o "$T/m.csv" -q
grep -q "^# summary skipped=34" "$T/m.csv" || fail "skipped rows lost"
# failed < skipped < ok; the later file wins a tie
printf 'index,input,output,status,error\n6,%s,x,failed,first\n' "$S/jet_006.csv" >"$T/f1.csv"
printf 'index,input,output,status,error\n6,%s,x,failed,second\n' "$S/jet_006.csv" >"$T/f2.csv"
run 0 stats merge "$T/f1.csv" "$T/f2.csv" -o "$T/m.csv" -q
grep -q ',failed,second$' "$T/m.csv" || fail "later file did not win a tie"
run 0 stats merge "$T/f1.csv" "$T/st_1.json" "$T/st_2.csv" "$T/again_0.csv" -o "$T/m.csv" -q
grep -q "^6,.*,skipped," "$T/m.csv" || fail "skipped did not win over failed"
grep -q "^# summary frames=100" "$T/m.csv" || fail "a frame counted twice"
# bad inputs
printf 'a,b\n1,2\n' >"$T/bad.csv"
run 1 stats merge "$T/bad.csv" -o "$T/m2.csv"
grep -q "bad.csv:1: not a jetmesh statistics CSV" "$T/err" || { cat "$T/err"; fail "bad CSV message"; }
run 1 stats merge "$T/nope.csv" -o "$T/m2.csv"
run 2 stats merge "$T/st_0.csv" -o "$T/m2.txt"
run 2 stats merge -o "$T/m2.csv"
run 2 stats frobnicate

# more shards than frames: the empty shard succeeds and writes empty stats
run 0 convert "$IN" --frames 0:2 -r 0.025 -o "$T/few/jet_{}.obj" --shard 5/8 --stats "$T/few.csv"
grep -q "^# summary frames=0" "$T/few.csv" || fail "empty shard stats"
[ ! -e "$T/few" ] || fail "empty shard wrote outputs"

# --shard slurm reads the array task's variables
SLURM_ARRAY_TASK_ID=6 SLURM_ARRAY_TASK_MIN=5 SLURM_ARRAY_TASK_COUNT=4 SLURM_ARRAY_TASK_STEP=1 \
    "$J" convert "$IN" --frames 0:9 -r 0.025 -o "$T/sl/jet_{}.obj" --shard slurm >"$T/out" 2>"$T/err" || fail "--shard slurm"
grep -q "^shard 1/4: 3 of the 10 frames" "$T/out" || { cat "$T/out"; fail "--shard slurm is not 1/4"; }
[ "$(ls "$T/sl")" = "$(printf 'jet_001.obj\njet_005.obj\njet_009.obj')" ] || fail "--shard slurm took other frames"
SLURM_ARRAY_TASK_ID=2 SLURM_ARRAY_TASK_COUNT=2 SLURM_ARRAY_TASK_STEP=2 \
    "$J" convert "$IN" -r 0.025 -o "$T/sl/" --shard slurm 2>"$T/err" && fail "a stepped array accepted"
grep -q "contiguous" "$T/err" || fail "stepped array message"
env -u SLURM_ARRAY_TASK_ID "$J" convert "$IN" -r 0.025 -o "$T/sl/" --shard slurm 2>"$T/err"
[ $? = 2 ] || fail "--shard slurm outside an array"
grep -q "not a task of a Slurm job array" "$T/err" || fail "outside-array message"

# malformed --shard
for bad in 4/4 -1/4 1/0 1 /4 a/b 1/4/2 ""; do
    run 2 convert "$IN" -r 0.025 -o "$T/x/" --shard "$bad"
    grep -q -- "--shard" "$T/err" || fail "--shard '$bad': no message"
done
echo "ok"

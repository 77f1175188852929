#!/bin/sh
# bench.sh - runs the fixed benchmark suite (jetmesh bench --json) into BUILD/bench.json and writes BENCHMARKS.md.
#
# Usage: scripts/bench.sh [BUILD_DIR]        (make bench builds first, then calls this)
# Env:   JETMESH_SHARED  the shared data folder (default: ../shared beside the repo)
#        BENCH_QUICK=1   one timed run per case, no time floor: checks the script
#                        itself in a minute or two; its numbers are NOT medians
#        BENCH_MD=FILE   where to write the report (default BENCHMARKS.md)
#        BENCH_BASELINE=FILE  a build/bench.json of an older commit on the same
#                        machine: the jet's and the metasphere dam break's
#                        targets (issue 34) are then ratios against its medians
# Needs node to turn the JSON into BENCHMARKS.md tables; without it the report
# holds the bench's own text tables instead.
# Exit status: 0 every case ran, 1 a case (or the report) failed, 2 usage.
set -u

BUILD=${1:-build}
root=$(cd "$(dirname "$0")/.." && pwd)
cd "$root" || exit 2
J="$BUILD/jetmesh"
[ -x "$J" ] || { echo "bench.sh: $J is missing: run make all" >&2; exit 2; }
SHARED=${JETMESH_SHARED:-../shared}
MD=${BENCH_MD:-BENCHMARKS.md}
OUT="$BUILD/bench"
rm -rf "$OUT"
mkdir -p "$OUT" || exit 1
: >"$OUT/commands.sh"
QUICK=""
[ "${BENCH_QUICK:-0}" = 1 ] && QUICK="--min-time 0 --repeat 1"
status=0
started=$(date +%s)
load_before=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo "?")

# The sph reference case of the issue: cube 0.5 r, smoothing length 2 r, threshold 0.6.
SPH="--field sph --smoothing-length 2 --threshold 0.6"

# group NAME ARGS... : one `jetmesh bench` run; JSON in $OUT/NAME.json, table in $OUT/NAME.txt
group() {
  name=$1
  shift
  # shellcheck disable=SC2086
  set -- "$@" $QUICK
  echo "$J bench $* --json-out $OUT/$name.json" >>"$OUT/commands.sh"
  echo "== $name: $J bench $*"
  "$J" bench "$@" --json-out "$OUT/$name.json" >"$OUT/$name.txt"
  rc=$?
  cat "$OUT/$name.txt"
  echo
  echo "$name $rc" >>"$OUT/exit"
  [ "$rc" = 0 ] || { echo "bench.sh: $name: exit $rc" >&2; status=1; }
}

# --- the suite ----------------------------------------------------------------
group jet --scene jet --field metasphere,sph --method mt,mc -j 1,2
# the paper's case at cube r too (issue 34's targets)
group jet_r --scene jet --field metasphere --method mt --cube-size 1 -j 1,2

# The jet's two-thread speed-up (issue 34) in alternating rounds: a round
# runs one 1-thread and one 2-thread `jetmesh bench` case, 0.5 s each, so
# the shared machine's slow phases, which last minutes, fall on both alike
# (the jet group above runs them a second apart, once).
median() { # DIGITS: the median of the numbers on standard input to DIGITS decimals, or null
  sort -n | awk -v f="%.$1f" '{ a[NR] = $1 } END { if (NR) printf f, NR % 2 ? a[(NR + 1) / 2] : (a[NR / 2] + a[NR / 2 + 1]) / 2; else print "null" }'
}
JROUNDS=7
[ -n "$QUICK" ] && JROUNDS=1
: >"$OUT/jet_threads.times"
jt_cmd="$J bench --scene jet --field metasphere --method mt -j T --min-time 0.5 --json"
echo "$jt_cmd" >>"$OUT/commands.sh"
echo "== jet threads: $jt_cmd, T = 1 then 2 ($JROUNDS rounds)"
r=0
while [ $r -lt "$JROUNDS" ]; do
  for t in 1 2; do
    # shellcheck disable=SC2086
    ms=$("$J" bench --scene jet --field metasphere --method mt -j $t --min-time 0.5 $QUICK --json 2>/dev/null |
      node -e 'const o = JSON.parse(require("fs").readFileSync(0, "utf8")); console.log(o.cases[0].ms.total.median)') ||
      ms=fail
    echo "$t $ms" >>"$OUT/jet_threads.times"
  done
  r=$((r + 1))
done
if grep -q ' fail$' "$OUT/jet_threads.times"; then
  echo "bench.sh: a jet threads round failed" >&2
  status=1
fi
jt1=$(awk '$1 == 1 && $2 != "fail" { print $2 }' "$OUT/jet_threads.times" | median 4)
jt2=$(awk '$1 == 2 && $2 != "fail" { print $2 }' "$OUT/jet_threads.times" | median 4)
echo "jet threads (median of $JROUNDS rounds): 1 thread $jt1 ms, 2 threads $jt2 ms"

REAL1="$SHARED/data/derived/dam_break_frame_23_24389_particles.xyz"
REAL2="$SHARED/data/splashsurf/bunny_frame_14_7705_particles.vtk"
if [ -f "$REAL1" ] && [ -f "$REAL2" ]; then
  group real "$REAL1" "$REAL2" -r 0.025 --field metasphere,sph --method mt,mc -j 1,2 --min-time 0 --repeat 3
else
  echo "== real: skipped: $REAL1 or $REAL2 is missing (set JETMESH_SHARED)"
  echo "real skipped" >>"$OUT/exit"
fi

group block_sph --scene block:10000 --scene block:100000 $SPH --method mc,mt -j 1,2
group block_meta --scene block:10000 --field metasphere --method mt,mc -j 1,2
# the anisotropic kernels against the isotropic field, side by side in one run
group block_aniso --scene block:100000 --field sph,sph-aniso --smoothing-length 2 --threshold 0.6 --method mc -j 1,2
# the flicker figure (issue 31): an 8,000-particle block moved by a quarter
# cube a frame, raw, anisotropic and smoothed, each against the raw mesh of
# the same method (the figure is geometry: one timed run per case)
group flicker --scene block:8000 --field sph,sph-aniso --method mc,mt -j 2 --min-time 0 --repeat 1 --flicker 4
group flicker_smooth --scene block:8000 --field sph --method mc,mt -j 2 --min-time 0 --repeat 1 --flicker 4 \
  --smooth 25 --smooth-normals 10
group flicker_implicit --scene block:8000 --field sph --method mc,mt -j 2 --min-time 0 --repeat 1 --flicker 4 \
  --smooth 25 --smooth-normals 10 --smooth-implicit
group block_1m --scene block:1000000 $SPH --method mc -j 1,2 --min-time 0 --repeat 3 --write glb
group spray --scene spray:10000 --field metasphere,sph --method mt -j 1,2 --templates both

# --- a 100-frame jet sequence to GLB vs. 100 process starts ---------------------
# Five rounds, each running every variant once in turn (the machine's load
# drifts; alternating keeps the comparison fair); medians are reported.
now_ns() { date +%s%N; }
T=$(mktemp -d "${TMPDIR:-/tmp}/jetmesh-bench.XXXXXX") || exit 1
trap 'rm -rf "$T"' EXIT INT TERM
seq_cmd="$J convert 'samples/jet/jet_{}.csv' -r 0.025 -o \"\$TMP/jet_{}.glb\" -q"
starts_cmd="for i in \$(seq 100); do $J --version >/dev/null; done"
echo "$seq_cmd" >>"$OUT/commands.sh"
echo "$seq_cmd --frame-jobs 1" >>"$OUT/commands.sh"
echo "$seq_cmd --no-sync" >>"$OUT/commands.sh"
echo "$starts_cmd" >>"$OUT/commands.sh"
echo "== sequence: $seq_cmd (default, --frame-jobs 1, --no-sync; 5 rounds)"
ROUNDS=${JETMESH_BENCH_ROUNDS:-5}
[ -n "$QUICK" ] && ROUNDS=1
seq_ok=false seq_files=0
: >"$OUT/sequence.log"
: >"$OUT/sequence.times"
convert_s() { # extra options...: the wall seconds of one conversion, or "fail"
  rm -rf "$T"/jet_*.glb
  t0=$(now_ns)
  if "$J" convert 'samples/jet/jet_{}.csv' -r 0.025 -o "$T/jet_{}.glb" -q "$@" >>"$OUT/sequence.log" 2>&1; then
    t1=$(now_ns)
    awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", (b - a) / 1e9 }'
  else
    echo fail
  fi
}
if [ -f samples/jet/jet_000.csv ]; then
  r=0
  while [ $r -lt "$ROUNDS" ]; do
    echo "default $(convert_s)" >>"$OUT/sequence.times"
    [ $r = 0 ] && seq_files=$(find "$T" -name 'jet_*.glb' | wc -l)
    echo "one_at_a_time $(convert_s --frame-jobs 1)" >>"$OUT/sequence.times"
    echo "no_sync $(convert_s --no-sync)" >>"$OUT/sequence.times"
    t0=$(now_ns)
    i=0
    while [ $i -lt 100 ]; do "$J" --version >/dev/null; i=$((i + 1)); done
    t1=$(now_ns)
    echo "starts $(awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", (b - a) / 1e9 }')" >>"$OUT/sequence.times"
    r=$((r + 1))
  done
  [ "$seq_files" -eq 100 ] && ! grep -q ' fail$' "$OUT/sequence.times" && seq_ok=true
  $seq_ok || echo "bench.sh: a sequence conversion failed (see $OUT/sequence.log)" >&2
fi
median_of() { # name: the median seconds of that variant, or null
  awk -v k="$1" '$1 == k && $2 != "fail" { print $2 }' "$OUT/sequence.times" | median 3
}
seq_s=$(median_of default) one_s=$(median_of one_at_a_time) nosync_s=$(median_of no_sync) starts_s=$(median_of starts)
echo "sequence (median of $ROUNDS): $seq_s s ($seq_files GLB files, ok=$seq_ok), one at a time $one_s s," \
  "--no-sync $nosync_s s; 100 process starts: $starts_s s"

# --- --attributes velocity on a 501-frame run (issue 32) -------------------------
# A real SPlisHSPlasH frame with velocities (6,859 particles) repeated as a
# 501-frame sequence, converted to per-frame GLBs with and without
# --attributes velocity, alternating rounds; medians, and their ratio.
VEL_IN="$SHARED/data/splashsurf/dam_break_frame_9_6859_particles.bgeo"
VFRAMES=${JETMESH_BENCH_VEL_FRAMES:-501}
VROUNDS=3
[ -n "$QUICK" ] && VROUNDS=1
vel_plain=null vel_attr=null vel_ratio=null vel_ok=false
: >"$OUT/velocity.times"
if [ -f "$VEL_IN" ]; then
  vel_abs="$(cd "$(dirname "$VEL_IN")" && pwd)/$(basename "$VEL_IN")"
  mkdir -p "$T/vel"
  i=0
  while [ $i -lt "$VFRAMES" ]; do ln -s "$vel_abs" "$T/vel/f_$(printf %04d $i).bgeo"; i=$((i + 1)); done
  vel_cmd="$J convert '<$VFRAMES links to $VEL_IN>/f_{}.bgeo' -r 0.025 -o '\$TMP/f_{}.glb' -q"
  echo "$vel_cmd" >>"$OUT/commands.sh"
  echo "$vel_cmd --attributes velocity" >>"$OUT/commands.sh"
  echo "== velocity: $vel_cmd [--attributes velocity] ($VROUNDS rounds)"
  vel_s() { # extra options...: the wall seconds of one conversion, or "fail"
    rm -rf "$T/velout"
    t0=$(now_ns)
    if "$J" convert "$T/vel/f_{}.bgeo" -r 0.025 -o "$T/velout/f_{}.glb" -q "$@" >>"$OUT/velocity.log" 2>&1 &&
      [ "$(find "$T/velout" -name 'f_*.glb' | wc -l)" -eq "$VFRAMES" ]; then
      t1=$(now_ns)
      awk -v a="$t0" -v b="$t1" 'BEGIN { printf "%.3f", (b - a) / 1e9 }'
    else
      echo fail
    fi
  }
  r=0
  while [ $r -lt "$VROUNDS" ]; do
    echo "plain $(vel_s)" >>"$OUT/velocity.times"
    echo "velocity $(vel_s --attributes velocity)" >>"$OUT/velocity.times"
    r=$((r + 1))
  done
  rm -rf "$T/vel" "$T/velout"
  if grep -q ' fail$' "$OUT/velocity.times"; then
    echo "bench.sh: a velocity conversion failed (see $OUT/velocity.log)" >&2
    status=1
  else
    vel_ok=true
  fi
  vel_plain=$(awk '$1 == "plain" && $2 != "fail" { print $2 }' "$OUT/velocity.times" | median 3)
  vel_attr=$(awk '$1 == "velocity" && $2 != "fail" { print $2 }' "$OUT/velocity.times" | median 3)
  [ "$vel_plain" != null ] && [ "$vel_attr" != null ] &&
    vel_ratio=$(awk -v a="$vel_attr" -v b="$vel_plain" 'BEGIN { printf "%.3f", a / b }')
  echo "velocity (median of $VROUNDS, $VFRAMES frames): $vel_plain s without, $vel_attr s with --attributes velocity: ${vel_ratio}x"
else
  echo "== velocity: skipped: $VEL_IN is missing (set JETMESH_SHARED)"
fi

# --- side by side with splashsurf (../shared/peers/splashsurf/ssbench) -----------
# The same 100k block file, alternating rounds: splashsurf 0.14 read +
# reconstruct at 1 and 2 threads and its recommended post-processing, against
# jetmesh bench's library time and --smooth 25 --smooth-normals 10.
PEER="$SHARED/peers/splashsurf/ssbench"
PEER_DIR="$OUT/peer"
mkdir -p "$PEER_DIR"
peer_build=""
if [ -x "$PEER" ]; then
  if grep -q avx512f /proc/cpuinfo 2>/dev/null; then peer_build="v4 (AVX-512)"; else peer_build="v3 (AVX2)"; fi
  "$J" generate block 100000 -q -o "$T/block100k.xyz" || status=1
  PROUNDS=3
  [ -n "$QUICK" ] && PROUNDS=1
  echo "== peer: $PEER ($peer_build) beside $J bench, 100k block, $PROUNDS rounds"
  r=1
  while [ $r -le "$PROUNDS" ]; do
    for t in 1 2; do
      "$PEER" "$T/block100k.xyz" -r 0.025 -s 0.0125 --threads $t >"$PEER_DIR/ss_t${t}_$r.json" 2>>"$PEER_DIR/log" || status=1
      # shellcheck disable=SC2086
      "$J" bench "$T/block100k.xyz" $SPH --method mc -j $t $QUICK --json-out "$PEER_DIR/jm_t${t}_$r.json" >/dev/null || status=1
    done
    "$PEER" "$T/block100k.xyz" -r 0.025 -s 0.0125 --threads 1 --mesh-cleanup --mesh-smoothing-weights \
      --mesh-smoothing-iters 25 --normals --normals-smoothing-iters 10 >"$PEER_DIR/ss_post_$r.json" 2>>"$PEER_DIR/log" || status=1
    # shellcheck disable=SC2086
    "$J" bench "$T/block100k.xyz" $SPH --method mc -j 1 --smooth 25 --smooth-normals 10 $QUICK \
      --json-out "$PEER_DIR/jm_post_$r.json" >/dev/null || status=1
    # shellcheck disable=SC2086
    "$J" bench "$T/block100k.xyz" $SPH --method mc -j 1 --smooth 25 --smooth-normals 10 --smooth-implicit $QUICK \
      --json-out "$PEER_DIR/jm_posti_$r.json" >/dev/null || status=1
    r=$((r + 1))
  done
  echo "$PEER <block100k.xyz> -r 0.025 -s 0.0125 --threads 1|2 [--mesh-cleanup --mesh-smoothing-weights --mesh-smoothing-iters 25 --normals --normals-smoothing-iters 10]" >>"$OUT/commands.sh"
  # the 1M block the same way (one timed jetmesh run per round)
  "$J" generate block 1000000 -q -o "$T/block1m.xyz" || status=1
  echo "== peer: $PEER ($peer_build) beside $J bench, 1M block, $PROUNDS rounds"
  r=1
  while [ $r -le "$PROUNDS" ]; do
    for t in 1 2; do
      "$PEER" "$T/block1m.xyz" -r 0.025 -s 0.0125 --threads $t >"$PEER_DIR/ss1m_t${t}_$r.json" 2>>"$PEER_DIR/log" || status=1
      # shellcheck disable=SC2086
      "$J" bench "$T/block1m.xyz" $SPH --method mc -j $t --min-time 0 --repeat 1 --json-out "$PEER_DIR/jm1m_t${t}_$r.json" >/dev/null || status=1
    done
    r=$((r + 1))
  done
  rm -f "$T/block1m.xyz"
  echo "$PEER <block1m.xyz> -r 0.025 -s 0.0125 --threads 1|2" >>"$OUT/commands.sh"
else
  echo "== peer: skipped: $PEER is missing (set JETMESH_SHARED)"
fi

# --- whole process, side by side with splashsurf (issue 10) -----------------------
# The 1M block file read, meshed and written by each process: `jetmesh convert
# -o x.glb` (SPH, mc, GLB with normals and UVs, flushed to disk before its
# rename, as by default) against `ssbench -o x.obj` (read + reconstruct + its
# only mesh output, an OBJ with normals). Alternating rounds; wall seconds and
# peak RSS of each process from /usr/bin/time, jetmesh's library peak from its
# --stats. Medians in BENCHMARKS.md.
WHOLE_DIR="$OUT/whole"
mkdir -p "$WHOLE_DIR"
if [ -x "$PEER" ] && [ -x /usr/bin/time ]; then
  "$J" generate block 1000000 -q -o "$T/block1m.xyz" || status=1
  echo "== whole process: $J convert -o .glb beside $PEER -o .obj, 1M block, $PROUNDS rounds"
  r=1
  while [ $r -le "$PROUNDS" ]; do
    for t in 1 2; do
      /usr/bin/time -f '{"wall_s": %e, "max_rss_kb": %M}' -o "$WHOLE_DIR/ss_t${t}_$r.time" \
        "$PEER" "$T/block1m.xyz" -r 0.025 -s 0.0125 --threads $t -o "$T/ss1m.obj" \
        >"$WHOLE_DIR/ss_t${t}_$r.json" 2>>"$WHOLE_DIR/log" || status=1
      rm -f "$T/ss1m.obj"
      # shellcheck disable=SC2086
      /usr/bin/time -f '{"wall_s": %e, "max_rss_kb": %M}' -o "$WHOLE_DIR/jm_t${t}_$r.time" \
        "$J" convert "$T/block1m.xyz" -r 0.025 $SPH --method mc -j $t -q -o "$T/jm1m.glb" \
        --stats "$WHOLE_DIR/jm_t${t}_$r.json" >>"$WHOLE_DIR/log" 2>&1 || status=1
      rm -f "$T/jm1m.glb"
    done
    r=$((r + 1))
  done
  rm -f "$T/block1m.xyz"
  echo "$PEER <block1m.xyz> -r 0.025 -s 0.0125 --threads 1|2 -o <x.obj>   (whole process, /usr/bin/time)" >>"$OUT/commands.sh"
  echo "$J convert <block1m.xyz> -r 0.025 $SPH --method mc -j 1|2 -q -o <x.glb> --stats <x.json>   (whole process, /usr/bin/time)" >>"$OUT/commands.sh"
else
  echo "== whole process: skipped: $PEER or /usr/bin/time is missing"
fi
# --- end of the whole-process block ----------------------------------------------

# --- the Blender streaming import at real scale (issue 32) ------------------------
# 500 frames of a real 6,859-particle frame, moving, as per-frame GLBs with
# velocities: headless Blender opens them with share/jetmesh/jetmesh_blender.py
# and steps to 40 random frames (scripts/bench_blender.sh; skipped without
# Blender). QUICK: 60 frames.
BLENDER_DIR="$OUT/blender"
bl_frames=500
[ -n "$QUICK" ] && bl_frames=60
echo "== blender: $bl_frames frames of 6,859 particles streamed into headless Blender"
BENCH_BLENDER_FRAMES=$bl_frames JETMESH_SHARED="$SHARED" scripts/bench_blender.sh "$BUILD" "$BLENDER_DIR" || status=1
echo "BENCH_BLENDER_FRAMES=$bl_frames scripts/bench_blender.sh $BUILD $BLENDER_DIR   (Blender streaming import)" >>"$OUT/commands.sh"

# --- build/bench.json -------------------------------------------------------------
load_after=$(cut -d' ' -f1-3 /proc/loadavg 2>/dev/null || echo "?")
commit=$(git rev-parse --short HEAD 2>/dev/null || echo unknown)
if [ -n "$(git status --porcelain --untracked-files=no 2>/dev/null)" ]; then commit="$commit-dirty"; fi
mem_kb=$(awk '/^MemTotal:/ { print $2 }' /proc/meminfo 2>/dev/null)
jstr() { printf '"%s"' "$(printf '%s' "$1" | sed 's/\\/\\\\/g; s/"/\\"/g')"; }
{
  printf '{\n  "commit": %s,\n  "date": %s,\n  "quick": %s,\n' "$(jstr "$commit")" \
    "$(jstr "$(date -u +%Y-%m-%dT%H:%M:%SZ)")" "$([ -n "$QUICK" ] && echo true || echo false)"
  printf '  "load_before": %s,\n  "load_after": %s,\n' "$(jstr "$load_before")" "$(jstr "$load_after")"
  printf '  "memory_bytes": %s,\n  "shared": %s,\n  "groups": [\n' "$(( ${mem_kb:-0} * 1024 ))" "$(jstr "$SHARED")"
  first=1
  while read -r name rc; do
    [ $first = 1 ] || printf ',\n'
    first=0
    cmd=$(grep -F -- "--json-out $OUT/$name.json" "$OUT/commands.sh" 2>/dev/null | head -n 1)
    printf '    {"name": %s, "exit": %s, "command": %s, "result": ' "$(jstr "$name")" \
      "$(jstr "$rc")" "$(jstr "$cmd")"
    if [ -s "$OUT/$name.json" ]; then cat "$OUT/$name.json"; else printf 'null'; fi
    printf '}'
  done <"$OUT/exit"
  printf '\n  ],\n  "sequence": {"frames": 100, "rounds": %s, "glb_files": %s, "ok": %s, "convert_s": %s, ' \
    "$ROUNDS" "$seq_files" "$seq_ok" "$seq_s"
  printf '"one_at_a_time_s": %s, "no_sync_s": %s, ' "$one_s" "$nosync_s"
  printf '"process_starts": 100, "starts_s": %s,\n    "convert_command": %s, "starts_command": %s},\n' \
    "$starts_s" "$(jstr "$seq_cmd")" "$(jstr "$starts_cmd")"
  printf '  "blender": '
  if [ -s "$BLENDER_DIR/blender.json" ]; then cat "$BLENDER_DIR/blender.json"; else printf 'null'; fi
  printf ',\n'
  printf '  "velocity": {"frames": %s, "rounds": %s, "ok": %s, "plain_s": %s, "velocity_s": %s, "ratio": %s},\n' \
    "$VFRAMES" "$VROUNDS" "$vel_ok" "$vel_plain" "$vel_attr" "$vel_ratio"
  printf '  "jet_threads": {"rounds": %s, "one_thread_ms": %s, "two_threads_ms": %s}\n}\n' "$JROUNDS" "$jt1" "$jt2"
} >"$BUILD/bench.json"
echo "wrote $BUILD/bench.json"

# --- BENCHMARKS.md -------------------------------------------------------------
elapsed=$(( $(date +%s) - started ))
if command -v node >/dev/null 2>&1; then
  node - "$BUILD/bench.json" "$OUT/commands.sh" "$elapsed" "$PEER_DIR" "$peer_build" "$WHOLE_DIR" "${BENCH_BASELINE:-}" >"$MD.tmp" <<'EOF' || status=1
const fs = require("fs");
const [file, cmdfile, elapsed, peerDir, peerBuild, wholeDir, baseFile] = process.argv.slice(2);
const B = JSON.parse(fs.readFileSync(file, "utf8"));
const cmds = fs.readFileSync(cmdfile, "utf8").trim();
const out = [];
const p = (s = "") => out.push(s);
const groups = B.groups.filter((g) => g.result);
const m = groups.length ? groups[0].result.machine : {cpu_model: "?", cores: "?", os: "?"};
const ver = groups.length ? groups[0].result.jetmesh_version : "?";
const f = (x, d = 3) => (x == null || !isFinite(x) ? "–" : Number(x).toFixed(d));
const ms = (x) => x == null ? "–" : x >= 100 ? x.toFixed(1) : x >= 1 ? x.toFixed(3) : x.toFixed(4);
const rate = (x) => x == null ? "–" : x >= 1e6 ? (x / 1e6).toFixed(2) + " M" : (x / 1e3).toFixed(1) + " k";
const mib = (b) => (b / 1048576).toFixed(1);
const mb = (b) => (b / 1e6).toFixed(1);
const X = (r) => (r == null ? "" : r.toFixed(2) + "×");

function findIn(R, group, name, field, method, threads, templates = true, cube = null) {
  const g = R.groups.find((g) => g.name === group);
  if (!g || !g.result) return null;
  return g.result.cases.find((c) => c.name === name && c.field === field && c.method === method &&
    c.threads === threads && c.templates === templates && c.status === "ok" &&
    (cube == null || c.cube_size === cube)) || null;
}
const find = (...a) => findIn(B, ...a);
// an older run on the same machine (BENCH_BASELINE), for issue 34's ratios
let BASE = null;
try { if (baseFile) BASE = JSON.parse(fs.readFileSync(baseFile, "utf8")); } catch (e) { BASE = null; }
const sec = (c) => (c ? c.ms.total.median / 1e3 : null);

// the side-by-side runs with splashsurf: medians over the rounds
const median = (a) => {
  const v = a.filter((x) => x != null && isFinite(x)).sort((x, y) => x - y);
  if (!v.length) return null;
  return v.length % 2 ? v[(v.length - 1) / 2] : (v[v.length / 2 - 1] + v[v.length / 2]) / 2;
};
function peerRuns(prefix, pick) {
  if (!peerBuild || !peerDir || !fs.existsSync(peerDir)) return [];
  return fs.readdirSync(peerDir).filter((n) => n.startsWith(prefix + "_") && n.endsWith(".json")).map((n) => {
    try { return pick(JSON.parse(fs.readFileSync(peerDir + "/" + n, "utf8"))); } catch (e) { return null; }
  });
}
const ssTotal = (t) => median(peerRuns("ss_t" + t, (d) => d.total_s * 1e3));
const jmTotal = (t) => median(peerRuns("jm_t" + t, (d) => d.cases[0].status === "ok" ? d.cases[0].ms.total.median : null));
const ssPost = median(peerRuns("ss_post", (d) => d.post_s * 1e3));
const ss1m = (t) => median(peerRuns("ss1m_t" + t, (d) => d.total_s * 1e3));
const jm1m = (t) => median(peerRuns("jm1m_t" + t, (d) => d.cases[0].status === "ok" ? d.cases[0].ms.total.median : null));
// the post-processing's own time (jm_stats.ms_post) in the smoothed runs, and
// what it adds to the rest of those same runs: both halves of the ratio from
// the same runs, so load that comes and goes between rounds does not enter
const jmPostOk = (d) => d.cases[0].status === "ok" && d.cases[0].ms.post;
const jmPost = median(peerRuns("jm_post", (d) => jmPostOk(d) ? d.cases[0].ms.post.median : null));
const jmPostBase = median(peerRuns("jm_post", (d) => jmPostOk(d) ? d.cases[0].ms.total.median - d.cases[0].ms.post.median : null));
const jmPostAdd = median(peerRuns("jm_post", (d) => jmPostOk(d) ? d.cases[0].ms.post.median / (d.cases[0].ms.total.median - d.cases[0].ms.post.median) : null));
// the steady smoothing (--smooth-implicit), in the same rounds
const jmPostI = median(peerRuns("jm_posti", (d) => jmPostOk(d) ? d.cases[0].ms.post.median : null));
const jmPostIAdd = median(peerRuns("jm_posti", (d) => jmPostOk(d) ? d.cases[0].ms.post.median / (d.cases[0].ms.total.median - d.cases[0].ms.post.median) : null));
// issue 10: whole processes (read, mesh, write) side by side, medians over the rounds
function wholeRuns(prefix, ext, pick) {
  if (!wholeDir || !fs.existsSync(wholeDir)) return [];
  return fs.readdirSync(wholeDir).filter((n) => n.startsWith(prefix + "_") && n.endsWith(ext)).map((n) => {
    try { return pick(JSON.parse(fs.readFileSync(wholeDir + "/" + n, "utf8"))); } catch (e) { return null; }
  });
}
const W = {
  ss: (t) => median(wholeRuns("ss_t" + t, ".time", (d) => d.wall_s)),
  jm: (t) => median(wholeRuns("jm_t" + t, ".time", (d) => d.wall_s)),
  ssRss: (t) => median(wholeRuns("ss_t" + t, ".time", (d) => d.max_rss_kb * 1024)),
  jmRss: (t) => median(wholeRuns("jm_t" + t, ".time", (d) => d.max_rss_kb * 1024)),
  jmLib: (t) => median(wholeRuns("jm_t" + t, ".json", (d) => d.frames[0].lib_peak_bytes)),
  ssPart: (t, k) => median(wholeRuns("ss_t" + t, ".json", (d) => d[k])),
  jmPart: (t, k) => median(wholeRuns("jm_t" + t, ".json", (d) => d.frames[0][k])),
};
const wholeOk = [1, 2].every((t) => W.ss(t) != null && W.jm(t) != null);

p("# jetmesh benchmarks");
p();
p("Generated by `make bench` (`scripts/bench.sh`); do not edit by hand: rerun it. " +
  "Raw numbers: `build/bench.json` (one `jetmesh bench --json` document per group) and the " +
  "bench's own text tables in `build/bench/*.txt`.");
p();
if (B.quick) p("**QUICK RUN (BENCH_QUICK=1): one timed run per case, not medians. Do not quote these numbers.**\n");
p(`- Date: ${B.date}`);
p(`- Machine: ${m.cpu_model}${m.cpu_detail ? " (" + m.cpu_detail + ")" : ""}, ${m.cores} cores, ${(B.memory_bytes / 1073741824).toFixed(1)} GiB memory, ${m.os}`);
p(`- Commit: \`${B.commit}\` (jetmesh ${ver}; "-dirty": uncommitted changes to tracked files were built in)`);
p(`- Suite wall time: ${elapsed} s; load average (1, 5, 15 min) before: ${B.load_before}, after: ${B.load_after} ` +
  "(other work on the machine during the run makes the numbers noisier, 2-thread cases most)");
p();
p("Method: `jetmesh bench` meshes each case repeatedly with `jm_mesh_particles` on one reused context, " +
  "after one untimed warm-up run, until at least 5 timed runs and 1 s (the 1M block and the real " +
  "frames: exactly 3 runs). Times are `jm_stats` milliseconds; **total is the median**, spread is " +
  "min and p90 (nearest rank) of the timed runs; stages are medians. part/s and tri/s come from the " +
  "median total. lib peak = `jm_stats.peak_bytes` (the library's own heap, mesh included; max over " +
  "the runs); RSS peak = the process's peak resident set during the case (VmHWM, reset before each " +
  "case), which includes the input particles. ×1T = speed-up over the same case with 1 thread; " +
  "×tpl = speed-up of sphere templates on over off (`no_templates`). MB = 10⁶ bytes, MiB = 2²⁰.");
p();

// ---- targets
function row(target, value, ok) {
  p(`| ${target} | ${value} | ${ok == null ? "not measured" : ok ? "**met**" : "**not met**"} |`);
}
p("## Targets");
p();
p("| target | measured | status |");
p("|---|---|---|");
const b1m1 = find("block_1m", "block:1000000", "sph", "mc", 1), b1m2 = find("block_1m", "block:1000000", "sph", "mc", 2);
row("1M block, sph mc, 2 threads ≤ 3.0 s", b1m2 ? f(sec(b1m2)) + " s" : "–", b1m2 ? sec(b1m2) <= 3.0 : null);
row("1M block, sph mc, 1 thread ≤ 5.0 s", b1m1 ? f(sec(b1m1)) + " s" : "–", b1m1 ? sec(b1m1) <= 5.0 : null);
const peak = [b1m1, b1m2].filter(Boolean).reduce((a, c) => Math.max(a, c.lib_peak_bytes), 0);
const rss = [b1m1, b1m2].filter(Boolean).reduce((a, c) => Math.max(a, c.peak_rss_bytes), 0);
row("1M block peak memory ≤ 240 MB incl. mesh (lib peak)", peak ? `${mb(peak)} MB lib peak (process RSS peak ${mb(rss)} MB)` : "–",
    peak ? peak <= 240e6 : null);
const b100k2 = find("block_sph", "block:100000", "sph", "mc", 2);
row("100k block, sph mc, 2 threads ≤ 0.3 s", b100k2 ? f(sec(b100k2)) + " s" : "–", b100k2 ? sec(b100k2) <= 0.3 : null);
const jet1 = find("jet", "jet", "metasphere", "mt", 1), jet2 = find("jet", "jet", "metasphere", "mt", 2);
row("jet (frame 99), metasphere mt, cube r/2, median ≤ 0.1 ms (1 thread)",
    jet1 ? `${ms(jet1.ms.total.median)} ms (2 threads: ${jet2 ? ms(jet2.ms.total.median) : "–"} ms)` : "–",
    jet1 ? jet1.ms.total.median <= 0.1 : null);
row("1M block: 2 threads ≥ 1.8× 1 thread", b1m2 && b1m2.speedup_vs_1_thread ? f(b1m2.speedup_vs_1_thread, 2) + "×" : "–",
    b1m2 && b1m2.speedup_vs_1_thread ? b1m2.speedup_vs_1_thread >= 1.8 : null);
// issue 34: the paper's jet four times faster, the metasphere usable on bulk
// fluid. With BENCH_BASELINE, ratios against that run's medians; without,
// against the issue's start on the same class of machine: on AVX-512 the
// issue's own figures (jet cube r/2 4.0 ms, cube r 1.5 ms, dam break
// 2.2 s), on AVX2 those of 2fe17ba's BENCHMARKS.md (jet 5.652 ms, dam break
// 2203.5 ms; cube r not measured there).
{
  const v4 = /AVX-512/.test(m.cpu_detail || "") && !/no AVX-512/.test(m.cpu_detail || "");
  const start = v4 ? {jet: 4.0, jet_r: 1.5, dam: 2200, src: "issue 34's figure on AVX-512"}
                   : {jet: 5.652, jet_r: null, dam: 2203.5, src: "2fe17ba on the Zen 2, AVX2"};
  const ratio = (now, grp, name, field, cube, ref, lim, what) => {
    const b = BASE ? findIn(BASE, grp, name, field, "mt", 1, true, cube) : null;
    const base = b ? b.ms.total.median : ref, src = b ? `baseline ${BASE.commit}` : start.src;
    if (!now || base == null) return row(what, "–", null);
    const r = now.ms.total.median / base;
    row(what, `${ms(now.ms.total.median)} ms against ${ms(base)} ms (${src}): ${f(r, 2)}×`, r <= lim);
  };
  const j1 = find("jet", "jet", "metasphere", "mt", 1), j2 = find("jet", "jet", "metasphere", "mt", 2);
  ratio(j1, "jet", "jet", "metasphere", 0.5, start.jet, 0.25, "jet (frame 99), metasphere mt, cube r/2, 1 thread ≤ ¼ of issue 34's start");
  ratio(find("jet_r", "jet", "metasphere", "mt", 1), "jet_r", "jet", "metasphere", 1, start.jet_r, 1 / 3,
        "jet (frame 99), metasphere mt, cube r, 1 thread ≤ ⅓ of issue 34's start");
  // the speed-up from the alternating rounds (the jet group's own, a second
  // apart, in brackets)
  const JT = B.jet_threads, jts = JT && JT.one_thread_ms && JT.two_threads_ms ? JT.one_thread_ms / JT.two_threads_ms : null;
  const own = j2 && j2.speedup_vs_1_thread ? `; the jet group's own runs: ${f(j2.speedup_vs_1_thread, 2)}×` : "";
  row("jet (frame 99), metasphere mt, cube r/2: 2 threads ≥ 1.6× 1 thread",
      jts ? `${f(jts, 2)}× (medians of ${JT.rounds} alternating rounds: ${ms(JT.one_thread_ms)} ms / ${ms(JT.two_threads_ms)} ms${own})` : "–",
      jts ? jts >= 1.6 : null);
  ratio(find("real", "dam_break_frame_23_24389_particles.xyz", "metasphere", "mt", 1), "real",
        "dam_break_frame_23_24389_particles.xyz", "metasphere", 0.5, start.dam, 1 / 3,
        "dam break frame 23 (24,389 particles), metasphere mt, 1 thread ≤ ⅓ of issue 34's start");
}
const sp1 = find("spray", "spray:10000", "metasphere", "mt", 1), sps = find("spray", "spray:10000", "sph", "mt", 1);
row("spray 10k: template path ≥ 3× general path (metasphere mt, 1 thread)",
    sp1 && sp1.template_speedup ? `${f(sp1.template_speedup, 1)}× (sph: ${sps && sps.template_speedup ? f(sps.template_speedup, 1) + "×" : "–"})` : "–",
    sp1 && sp1.template_speedup ? sp1.template_speedup >= 3 : null);
const ai1 = find("block_aniso", "block:100000", "sph", "mc", 1), aa1 = find("block_aniso", "block:100000", "sph-aniso", "mc", 1);
row("100k block, mc, 1 thread: --anisotropic ≤ 2× the isotropic field",
    ai1 && aa1 ? `${f(sec(aa1), 3)} s against ${f(sec(ai1), 3)} s (${f(sec(aa1) / sec(ai1), 2)}×)` : "–",
    ai1 && aa1 ? sec(aa1) <= 2 * sec(ai1) : null);
// issue 31: the flicker of anisotropy and smoothing against the raw mesh's
for (const [what, grp, field] of [["--anisotropic", "flicker", "sph-aniso"], ["--smooth 25 --smooth-normals 10", "flicker_smooth", "sph"],
                                  ["--smooth 25 --smooth-normals 10 --smooth-implicit", "flicker_implicit", "sph"]]) {
  const got = ["mc", "mt"].map((m) => [find("flicker", "block:8000", "sph", m, 2), find(grp, "block:8000", field, m, 2)]);
  const ok = got.every(([r, x]) => r && x && r.flicker && x.flicker);
  row(`block 8k moved by a quarter cube a frame: ${what} shimmers no more than the raw mesh (flicker p99, mc and mt)`,
      ok ? got.map(([r, x], i) => `${["mc", "mt"][i]} ${f(x.flicker.p99_r, 4)} R against ${f(r.flicker.p99_r, 4)} R`).join("; ") : "–",
      ok ? got.every(([r, x]) => x.flicker.p99_r <= r.flicker.p99_r) : null);
}
const SQ = B.sequence;
// issue 32: the Blender streaming import of a 500-frame run
const BL = B.blender;
if (BL) {
  row(`Blender opens a ${BL.frames}-frame run of 6,859 particles (per-frame GLBs, velocities) in ≤ 30 s within 2 GB`,
      `${f(BL.open_s, 2)} s; process peak ${mb(BL.peak_rss_bytes)} MB (${mb(BL.rss_before_bytes)} MB before)`,
      BL.open_s <= 30 && BL.peak_rss_bytes <= 2e9);
  row("moving to any frame takes ≤ 1 s (40 random frames, none cached: the slowest)",
      `${f(BL.random_uncached.max_ms / 1e3, 2)} s (median ${f(BL.random_uncached.median_ms / 1e3, 2)} s)`,
      BL.random_uncached.max_ms <= 1000);
}
row("100-frame jet sequence to GLB faster than 100 process starts (medians)",
    SQ.convert_s != null && SQ.starts_s != null ? `${f(SQ.convert_s)} s against ${f(SQ.starts_s)} s (${f(SQ.starts_s / SQ.convert_s, 2)}×)` : "–",
    SQ.convert_s != null && SQ.starts_s != null && SQ.ok ? SQ.convert_s < SQ.starts_s : null);
const VL = B.velocity;
row(`--attributes velocity ≤ 1.3× the wall time without it (${VL ? VL.frames : "–"} frames of 6,859 particles to GLB, medians)`,
    VL && VL.ratio != null ? `${f(VL.ratio, 2)}× (${f(VL.velocity_s, 2)} s against ${f(VL.plain_s, 2)} s)` : "–",
    VL && VL.ratio != null && VL.ok ? VL.ratio <= 1.3 : null);
const w2 = b1m2 && b1m2.write ? b1m2.write.fraction_of_total : null, w1 = b1m1 && b1m1.write ? b1m1.write.fraction_of_total : null;
row("GLB write of the 1M mesh ≤ 15 % of total (write / (mesh + write), 2 threads)",
    w2 != null ? `${f(100 * w2, 1)} % (${ms(b1m2.ms.write.median)} ms for ${mb(b1m2.write.bytes)} MB; 1 thread: ${w1 != null ? f(100 * w1, 1) : "–"} %)` : "–",
    w2 != null ? w2 <= 0.15 : null);
if (peerBuild) {
  for (const [name, lim, ss, jm] of [["100k", 0.3, ssTotal, jmTotal], ["1M", 0.25, ss1m, jm1m]]) {
    const r1 = ss(1) && jm(1) ? jm(1) / ss(1) : null, r2 = ss(2) && jm(2) ? jm(2) / ss(2) : null;
    row(`${name} block, sph mc: jetmesh ≤ ${lim}× splashsurf's time at 1 and at 2 threads (side by side, medians)`,
        r1 != null && r2 != null ? `${f(r1, 2)}× / ${f(r2, 2)}×` : "–", r1 != null && r2 != null ? r1 <= lim && r2 <= lim : null);
  }
  const add = jmPostAdd;
  row("100k block, 1 thread: --smooth 25 --smooth-normals 10 adds ≤ 25 % (its own time in the same runs, medians)",
      add != null ? `+${f(100 * add, 1)} % (${f(jmPost, 1)} ms on ${f(jmPostBase, 1)} ms)` : "–", add != null ? add <= 0.25 : null);
  row("the same smoothing takes less than splashsurf's post-processing on the same mesh",
      jmPost != null && ssPost != null ? `${f(jmPost, 1)} ms against ${f(ssPost, 1)} ms` : "–",
      jmPost != null && ssPost != null ? jmPost < ssPost : null);
  // the steady smoothing is opt-in: its cost is reported, its target is splashsurf's
  row("with --smooth-implicit (what it adds, as above; its post-processing against the explicit steps') it still takes less than splashsurf's post-processing",
      jmPostI != null && ssPost != null && jmPost != null ?
        `+${f(100 * jmPostIAdd, 1)} %; ${f(jmPostI, 1)} ms (${f(jmPostI / jmPost, 2)}× the explicit steps') against ${f(ssPost, 1)} ms` : "–",
      jmPostI != null && ssPost != null ? jmPostI < ssPost : null);
  // issue 10: whole process
  if (wholeOk) {
    const r1 = W.jm(1) / W.ss(1), r2 = W.jm(2) / W.ss(2);
    row("1M block, whole process (read .xyz, mesh, write): `jetmesh convert` to GLB ≤ 0.4× splashsurf's to OBJ, 1 and 2 threads",
        `${f(r1, 2)}× / ${f(r2, 2)}× (${f(W.jm(1), 2)} s against ${f(W.ss(1), 2)} s; ${f(W.jm(2), 2)} s against ${f(W.ss(2), 2)} s)`,
        r1 <= 0.4 && r2 <= 0.4);
    const mx = (g) => Math.max(g(1) || 0, g(2) || 0);
    row("1M block, whole process: peak RSS ≤ splashsurf's (max of 1 and 2 threads)",
        `${mb(mx(W.jmRss))} MB against ${mb(mx(W.ssRss))} MB (jetmesh lib peak ${mb(mx(W.jmLib))} MB)`,
        mx(W.jmRss) <= mx(W.ssRss));
  }
}
p();

// ---- reference
p("## Side by side with splashsurf");
p();
if (!peerBuild) {
  p("`../shared/peers/splashsurf/ssbench` was not found: no side-by-side run in this report.");
} else {
  p(`splashsurf 0.14 through \`ssbench\`, build ${peerBuild}, on the same 100,000-particle block file ` +
    "(`block 100000`, spacing 2r, jittered), sph colour field, cube 0.5 r, support 4r, threshold 0.6, " +
    "marching cubes; splashsurf's read + reconstruct against jetmesh's library time; rounds alternate " +
    "the two; milliseconds, medians over the rounds. Post-processing: splashsurf's recommended " +
    "`--mesh-cleanup --mesh-smoothing-weights --mesh-smoothing-iters 25 --normals " +
    "--normals-smoothing-iters 10` (its post_s) against the post-processing time of `--smooth 25 --smooth-normals 10` " +
    "in jetmesh's runs (`jm_stats.ms_post`, the `post` stage of `jetmesh bench --json`).");
  p();
  p("| block | splashsurf | jetmesh | ratio |");
  p("|---|---|---|---|");
  for (const t of [1, 2])
    p(`| 100k, ${t} thread${t > 1 ? "s" : ""} | ${f(ssTotal(t), 1)} | ${f(jmTotal(t), 1)} | ${ssTotal(t) && jmTotal(t) ? f(jmTotal(t) / ssTotal(t), 2) : "–"} |`);
  for (const t of [1, 2])
    p(`| 1M, ${t} thread${t > 1 ? "s" : ""} (one jetmesh run a round) | ${f(ss1m(t), 1)} | ${f(jm1m(t), 1)} | ${ss1m(t) && jm1m(t) ? f(jm1m(t) / ss1m(t), 2) : "–"} |`);
  p(`| post-processing, 1 thread | ${f(ssPost, 1)} | ${f(jmPost, 1)} | ${ssPost && jmPost ? f(jmPost / ssPost, 2) : "–"} |`);
  p();
  // issue 10: whole process
  if (wholeOk) {
    p("Whole process on the 1M block file (medians of the rounds, which alternate the two): " +
      "`jetmesh convert <block1m.xyz> -r 0.025 --field sph --smoothing-length 2 --threshold 0.6 --method mc -o x.glb` " +
      "(reads the .xyz, meshes, writes the GLB with normals and UVs, flushed to disk before its rename) against " +
      "`ssbench <block1m.xyz> -r 0.025 -s 0.0125 -o x.obj` (reads, reconstructs, writes its only mesh output, an OBJ " +
      "with normals); wall time and peak RSS of each process from `/usr/bin/time`; the parts from each " +
      "one's own report (jetmesh `--stats`: read, mesh = field + extract + attributes, write including the flush " +
      "and rename; ssbench's JSON: read_s, field_s, write_s).");
    p();
    p("| threads | splashsurf s | jetmesh s | ratio | splashsurf read / reconstruct / write s | jetmesh read / mesh / write s | splashsurf peak RSS MB | jetmesh peak RSS MB | jetmesh lib peak MB |");
    p("|---|--:|--:|--:|---|---|--:|--:|--:|");
    for (const t of [1, 2]) {
      const jmMesh = W.jmPart(t, "ms_field") + W.jmPart(t, "ms_extract") + W.jmPart(t, "ms_attributes");
      p(`| ${t} | ${f(W.ss(t), 2)} | ${f(W.jm(t), 2)} | ${f(W.jm(t) / W.ss(t), 2)} | ` +
        `${f(W.ssPart(t, "read_s"), 2)} / ${f(W.ssPart(t, "field_s"), 2)} / ${f(W.ssPart(t, "write_s"), 2)} | ` +
        `${f(W.jmPart(t, "ms_read") / 1e3, 2)} / ${f(jmMesh / 1e3, 2)} / ${f(W.jmPart(t, "ms_write") / 1e3, 2)} | ` +
        `${mb(W.ssRss(t))} | ${mb(W.jmRss(t))} | ${mb(W.jmLib(t))} |`);
    }
    p();
  }
  p("The figures an earlier report quoted for splashsurf (10.2 s / 6.3 s at 1M particles) came from a " +
    "build for generic x86-64, not from a side-by-side run: they are withdrawn.");
}
p();

// ---- the groups
const titles = {
  jet: "Jet (125 particles, frame 99), both fields and methods",
  jet_r: "Jet (frame 99), metasphere mt at cube r",
  real: "Real frames (radius 0.025; 3 runs each)",
  block_sph: "Blocks 10k and 100k, sph (the reference case: mc)",
  block_meta: "Block 10k, metasphere",
  block_aniso: "Block 100k, sph against sph with anisotropic kernels (mc)",
  flicker: "Flicker: block 8k moved by a quarter cube a frame, raw and anisotropic (one timed run each)",
  flicker_smooth: "Flicker: the same block smoothed (--smooth 25 --smooth-normals 10)",
  flicker_implicit: "Flicker: the same block with the steady smoothing (--smooth 25 --smooth-normals 10 --smooth-implicit)",
  block_1m: "Block 1M, sph mc, with a GLB write stage (3 runs)",
  spray: "Spray 10k isolated droplets, templates off (general path) and on",
};
for (const g of B.groups) {
  p(`## ${titles[g.name] || g.name}`);
  p();
  if (g.exit === "skipped") { p("Skipped: the shared data folder (`" + B.shared + "`) is missing."); p(); continue; }
  p("```sh\n" + g.command + "\n```");
  p();
  if (!g.result) { p(`No result (exit ${g.exit}).`); p(); continue; }
  const hasWrite = g.result.cases.some((c) => c.write);
  p("| case | field | method | cube | thr | tpl | runs | total ms (median) | min | p90 | prepare | field | extract | attrs |" +
    (hasWrite ? " write |" : "") + " part/s | tri/s | vertices | triangles | lib peak MiB | RSS peak MiB | ×1T | ×tpl |");
  p("|---|---|---|--:|--:|---|--:|--:|--:|--:|--:|--:|--:|--:|" + (hasWrite ? "--:|" : "") + "--:|--:|--:|--:|--:|--:|--:|--:|");
  for (const c of g.result.cases) {
    const head = `| ${c.name} | ${c.field} | ${c.method} | ${c.cube_size} | ${c.threads} | ${c.templates ? "on" : "off"} |`;
    if (c.status !== "ok") { p(`${head} FAILED: ${c.error} |`); continue; }
    p(`${head} ${c.repetitions} | **${ms(c.ms.total.median)}** | ${ms(c.ms.total.min)} | ${ms(c.ms.total.p90)} | ` +
      `${ms(c.ms.prepare.median)} | ${ms(c.ms.field.median)} | ${ms(c.ms.extract.median)} | ${ms(c.ms.attributes.median)} |` +
      (hasWrite ? ` ${c.write ? ms(c.ms.write.median) : "–"} |` : "") +
      ` ${rate(c.particles_per_s)} | ${rate(c.triangles_per_s)} | ${c.vertices} | ${c.triangles} | ` +
      `${mib(c.lib_peak_bytes)} | ${mib(c.peak_rss_bytes)} | ${X(c.speedup_vs_1_thread)} | ${X(c.template_speedup)} |`);
  }
  p();
  const fl = g.result.cases.filter((c) => c.status === "ok" && c.flicker);
  if (fl.length) {
    p("| case | field | method | flicker frames | p99 R | max R |");
    p("|---|---|---|--:|--:|--:|");
    for (const c of fl) p(`| ${c.name} | ${c.field} | ${c.method} | ${c.flicker.frames} | ${f(c.flicker.p99_r, 4)} | ${f(c.flicker.max_r, 4)} |`);
    p();
  }
}

// ---- sequence
const S = B.sequence;
p("## A 100-frame jet sequence to GLB vs. 100 process starts");
p();
p(`Medians of ${S.rounds} rounds; each round runs every line once, in this order.`);
p();
p("| what | wall s (median) |");
p("|---|--:|");
p(`| \`jetmesh convert\` of samples/jet (100 frames → GLB; default: all threads, frames at once) | ${S.convert_s == null ? "failed or no samples" : f(S.convert_s) + (S.ok ? "" : " (not 100 files)")} |`);
p(`| the same with \`--frame-jobs 1\` (one frame at a time, all threads on it) | ${S.one_at_a_time_s == null ? "-" : f(S.one_at_a_time_s)} |`);
p(`| the same with \`--no-sync\` (no flush to disk before each rename) | ${S.no_sync_s == null ? "-" : f(S.no_sync_s)} |`);
p(`| 100 × \`jetmesh --version\` (process start and exit) | ${f(S.starts_s)} |`);
p();
p("```sh\n" + S.convert_command + "\n" + S.convert_command + " --frame-jobs 1\n" + S.convert_command + " --no-sync\n" + S.starts_command + "\n```");
p();
if (BL) {
  p(`## Blender: a ${BL.frames}-frame run streamed`);
  p();
  p(`\`scripts/bench_blender.sh\`: ${BL.frames} frames (numbers ${BL.first}-${BL.last}) of SPlisHSPlasH's 6,859-particle ` +
    "dam-break frame, sloshing along x, converted with `--attributes velocity` to per-frame GLBs (about 57,000 " +
    "vertices and 114,000 triangles each), opened by `jetmesh_blender.open_sequence` in headless Blender " +
    `${BL.blender} (file names, the first frame shown), then \`scene.frame_set\` to 40 frames in a seeded random ` +
    "order (each read from its file), 20 consecutive frames, and 8 of the 40 again from the cache of 8. " +
    "Blender's own normals (the default outside renders), milliseconds of wall time.");
  p();
  p("| what | median | slowest |");
  p("|---|--:|--:|");
  p(`| open | ${f(BL.open_s * 1e3, 0)} | |`);
  for (const [k, t] of [["random_uncached", "40 random frames, from their files"], ["playback", "20 consecutive frames"],
                        ["cached", "8 frames from the cache"]])
    p(`| ${t} | ${f(BL[k].median_ms, 0)} | ${f(BL[k].max_ms, 0)} |`);
  p(`| process memory: before / after the open / peak, MB | ${mb(BL.rss_before_bytes)} / ${mb(BL.rss_after_open_bytes)} | ${mb(BL.peak_rss_bytes)} |`);
  p();
}
p("## Commands");
p();
p("Every command of this run, in order (`$JETMESH_SHARED` = `" + B.shared + "`):");
p();
p("```sh\n" + cmds + "\n```");
p();
process.stdout.write(out.join("\n"));
EOF
else
  {
    echo "# jetmesh benchmarks"
    echo
    echo "Generated by \`make bench\`; node was not found, so these are the bench's text tables."
    echo
    echo "- Date: $(date -u +%Y-%m-%dT%H:%M:%SZ); commit \`$commit\`; $(grep -m1 'model name' /proc/cpuinfo | sed 's/.*: //'), $(nproc) cores"
    echo
    for f in "$OUT"/*.txt; do printf '```\n'; cat "$f"; printf '```\n\n'; done
    echo "Sequence: convert $seq_s s, 100 process starts $starts_s s."
    echo
    printf '## Commands\n\n```sh\n'; cat "$OUT/commands.sh"; printf '```\n'
  } >"$MD.tmp"
fi
if [ -s "$MD.tmp" ]; then mv "$MD.tmp" "$MD" && echo "wrote $MD"; else rm -f "$MD.tmp"; status=1; fi
echo "bench.sh: done in $(( $(date +%s) - started )) s"
exit $status

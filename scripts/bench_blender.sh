#!/bin/sh
# bench_blender.sh - the Blender streaming import at real scale: 500 frames of a real 6,859-particle frame, moving, opened and stepped through in headless Blender.
# Usage: scripts/bench_blender.sh BUILD_DIR OUT_DIR   (run by scripts/bench.sh; writes OUT_DIR/blender.json)
# Env: JETMESH_SHARED (the shared data), BENCH_BLENDER_FRAMES (default 500),
#      BENCH_BLENDER_KEEP=DIR (keep the frames there and reuse them next time)
# Targets (issue 32): open in <= 30 s within 2 GB, any frame in <= 1 s.
set -u
BUILD=$1 OUT=$2
root=$(cd "$(dirname "$0")/.." && pwd)
J="$BUILD/jetmesh"
SHARED=${JETMESH_SHARED:-$root/../shared}
N=${BENCH_BLENDER_FRAMES:-500}
SRC="$SHARED/data/splashsurf/dam_break_frame_9_6859_particles.bgeo"
mkdir -p "$OUT" || exit 1
command -v blender >/dev/null 2>&1 || { echo "bench_blender: skipped: no blender (scripts/deps.sh test)"; exit 0; }
[ -f "$SRC" ] || { echo "bench_blender: skipped: $SRC is missing (set JETMESH_SHARED)"; exit 0; }
W=${BENCH_BLENDER_KEEP:-}
if [ -z "$W" ]; then
  W=$(mktemp -d "${TMPDIR:-/tmp}/jetmesh-bench-blender.XXXXXX") || exit 1
  trap 'rm -rf "$W"' EXIT INT TERM
fi
if [ "$(find "$W/glb" -name 'f_*.glb' 2>/dev/null | wc -l)" != "$N" ]; then
  rm -rf "$W/p" "$W/glb"
  python3 "$root/scripts/bench_blender_frames.py" "$SRC" "$W/p" "$N" || exit 1
  t0=$(date +%s)
  "$J" convert "$W/p/p_{}.csv" -r 0.025 --attributes velocity -o "$W/glb/f_{}.glb" -q || exit 1
  echo "bench_blender: converted $N frames in $(( $(date +%s) - t0 )) s ($(du -sh "$W/glb" | cut -f1))"
  rm -rf "$W/p"
fi
HOME=$W blender -b --factory-startup --python-exit-code 1 --python "$root/scripts/bench_blender.py" -- \
  "$root/share/jetmesh/jetmesh_blender.py" "$W/glb" "$OUT/blender.json" >"$OUT/blender.log" 2>&1 ||
  { tail -n 20 "$OUT/blender.log"; echo "bench_blender: the Blender run failed" >&2; exit 1; }
grep '^bench_blender:' "$OUT/blender.log"

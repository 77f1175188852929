#!/bin/sh
# fuzz.sh - builds and runs one libFuzzer target per particle reader, and one that meshes CSV input, keeping a small minimized corpus and any crashes.
#
# Usage: scripts/fuzz.sh [TARGET...]        (default: csv xyz vtk vtu bgeo ply auto mesh)
# Environment:
#   FUZZ_SECONDS   seconds per target (default 60)
#   FUZZ_JOBS      targets run at the same time (default 1)
#   FUZZ_MAX_SEED  seeds larger than this many bytes are skipped (default 65536)
#   FUZZ_MAX_LEN   -max_len for generated inputs (default 65536)
#   FUZZ_CC        compiler (default clang)
#   JETMESH_SHARED shared data (default ../shared next to the repository)
# Results: tests/fuzz/corpus/<target>/ (merged, at most ~50 files / 2 MB),
#          tests/fuzz/crashes/<target>/ (crash-*, leak-*, timeout-*, oom-*),
#          build/fuzz/<target>.log. Exits 1 if any target found something.
set -eu

root=$(cd "$(dirname "$0")/.." && pwd)
shared=${JETMESH_SHARED:-$root/../shared}
secs=${FUZZ_SECONDS:-60}
jobs=${FUZZ_JOBS:-1}
max_seed=${FUZZ_MAX_SEED:-65536}
max_len=${FUZZ_MAX_LEN:-65536}
cc=${FUZZ_CC:-clang}
out=$root/build/fuzz
targets=${*:-csv xyz vtk vtu bgeo ply auto mesh}
corpus_max_files=50
corpus_max_bytes=2097152

command -v "$cc" >/dev/null 2>&1 || { echo "fuzz: $cc not found (apt-get install clang libclang-rt-14-dev)" >&2; exit 2; }
mkdir -p "$out"
# the readers only: not the C++ writers or other format code
srcs="$root/formats/reader.c $root/formats/read/readbuf.c $(ls "$root"/formats/read/read_*.c)"

build() { # target
  echo "fuzz: building fuzz_$1"
  # the meshing target also builds the library (and its one dependency)
  lib=""
  [ "$1" = mesh ] && lib="-I$root/lib $(find "$root/lib" -name "*.c" | sort) -lmeshoptimizer -lstdc++ -pthread"
  # shellcheck disable=SC2086
  "$cc" -g -O1 -fsanitize=fuzzer,address,undefined -fno-sanitize-recover=undefined \
    -std=c11 -D_POSIX_C_SOURCE=200809L -D_DEFAULT_SOURCE -Wall -Wextra \
    -I"$root/formats" "$root/tests/fuzz/fuzz_$1.c" $srcs $lib -lz -lm -o "$out/fuzz_$1"
}

# Copies the seeds for a target into $2: matching shared files and samples
# (small ones only), plus a few generated ones the shared data lacks.
seed() { # target dir
  t=$1; d=$2
  case $t in
    csv|mesh) pat='*.csv *.txt' ;; xyz) pat='*.xyz' ;; vtk) pat='*.vtk' ;; vtu) pat='*.vtu' ;;
    bgeo) pat='*.bgeo *.bgeo.gz' ;; ply) pat='*.ply' ;; *) pat='*.csv *.xyz *.vtk *.vtu *.bgeo *.ply *.gz' ;;
  esac
  for base in "$shared/data" "$root/samples"; do
    [ -d "$base" ] || continue
    for p in $pat; do
      find "$base" -type f -name "$p" -size -"$((max_seed + 1))"c 2>/dev/null
    done
  done | sort -u | while read -r f; do
    cp "$f" "$d/seed-$(basename "$f")"
  done
  case $t in
    csv|auto|mesh)
      printf 'x,y,z,id\n0,0,0,1\n1.5,2.5,-3e-2,2\n' >"$d/gen-header.csv"
      printf '# comment\r\n1;2;3\r\n4;5;6\r\n' >"$d/gen-semicolon.csv"
      printf 'pos_x\tpos_y\tpos_z\n1\t2\t3\nnan\t1\t1\n' >"$d/gen-tab.csv"
      printf '1 2 3\n  4 5 6  \n' >"$d/gen-space.csv" ;;
  esac
  case $t in
    xyz|auto)
      xyz=$shared/data/derived/dam_break_frame_23_24389_particles.xyz
      [ -f "$xyz" ] && head -c 1200 "$xyz" >"$d/gen-100.xyz" ;;
  esac
  case $t in
    bgeo|auto)
      for f in "$shared"/data/partio_testfiles/*.bgeo; do
        [ -f "$f" ] && gzip -9 -n -c "$f" >"$d/gen-$(basename "$f").gz"
      done ;;
  esac
  case $t in
    ply|auto)
      printf 'ply\nformat ascii 1.0\nelement vertex 2\nproperty float x\nproperty float y\nproperty float z\nproperty int id\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 7\n1 2 3 8\n3 0 1 1\n' >"$d/gen-ascii.ply" ;;
  esac
  case $t in
    vtk|auto)
      printf '# vtk DataFile Version 3.0\nt\nASCII\nDATASET POLYDATA\nPOINTS 2 float\n0 0 0 1 2 3\nVERTICES 2 4\n1 0\n1 1\nPOINT_DATA 2\nSCALARS id int 1\nLOOKUP_TABLE default\n5 6\n' >"$d/gen-ascii.vtk" ;;
  esac
  case $t in
    vtu|auto)
      printf '<?xml version="1.0"?>\n<VTKFile type="UnstructuredGrid" version="0.1" byte_order="LittleEndian">\n<UnstructuredGrid><Piece NumberOfPoints="2" NumberOfCells="0">\n<Points><DataArray type="Float32" NumberOfComponents="3" format="ascii">0 0 0 1 2 3</DataArray></Points>\n<PointData><DataArray type="Int32" Name="id" format="ascii">4 5</DataArray></PointData>\n</Piece></UnstructuredGrid></VTKFile>\n' >"$d/gen-ascii.vtu" ;;
  esac
}

# Keeps the smallest files of a merged corpus within the caps.
cap_corpus() { # dir
  n=0; bytes=0
  for f in $(ls -rS "$1"); do
    sz=$(wc -c <"$1/$f")
    if [ $n -ge $corpus_max_files ] || [ $((bytes + sz)) -gt $corpus_max_bytes ]; then
      rm -f "$1/$f"
    else
      n=$((n + 1)); bytes=$((bytes + sz))
    fi
  done
}

run_one() { # target
  t=$1
  work=$out/work/$t; seeds=$out/seeds/$t; saved=$root/tests/fuzz/corpus/$t; crashes=$root/tests/fuzz/crashes/$t
  rm -rf "$work" "$seeds"
  mkdir -p "$work" "$seeds" "$saved" "$crashes"
  seed "$t" "$seeds"
  cp "$saved"/* "$work"/ 2>/dev/null || true
  start=$(date +%s)
  set +e
  "$out/fuzz_$t" -max_total_time="$secs" -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 \
    -print_final_stats=1 -artifact_prefix="$crashes/" "$work" "$seeds" >"$out/$t.log" 2>&1
  rc=$?
  set -e
  took=$(( $(date +%s) - start ))
  # merge into a fresh minimal corpus, then cap it
  merged=$out/merged/$t
  rm -rf "$merged"; mkdir -p "$merged"
  "$out/fuzz_$t" -merge=1 -max_len="$max_len" -timeout=10 -rss_limit_mb=2048 "$merged" "$work" "$seeds" \
    >"$out/$t.merge.log" 2>&1 || true
  if [ -n "$(ls "$merged")" ]; then
    cap_corpus "$merged"
    rm -f "$saved"/*
    cp "$merged"/* "$saved"/
  fi
  execs=$(grep -o 'stat::number_of_executed_units: *[0-9]*' "$out/$t.log" | grep -o '[0-9]*$' || echo '?')
  found=$(ls "$crashes" 2>/dev/null | wc -l)
  echo "fuzz: $t: ${took}s, $execs runs, rc=$rc, corpus $(ls "$saved" | wc -l) files, crashes dir $found files"
  [ "$rc" = 0 ]
}

for t in $targets; do
  [ -f "$root/tests/fuzz/fuzz_$t.c" ] || { echo "fuzz: no target $t" >&2; exit 2; }
  build "$t"
done

status=0
running=0
pids=""
for t in $targets; do
  if [ "$jobs" -le 1 ]; then
    run_one "$t" || status=1
  else
    run_one "$t" &
    pids="$pids $!"
    running=$((running + 1))
    if [ $running -ge "$jobs" ]; then
      for p in $pids; do wait "$p" || status=1; done
      pids=""; running=0
    fi
  fi
done
for p in $pids; do wait "$p" || status=1; done
[ $status = 0 ] && echo "fuzz: no crashes" || echo "fuzz: FOUND PROBLEMS: see tests/fuzz/crashes/ and build/fuzz/*.log" >&2
exit $status

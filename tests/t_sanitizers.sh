#!/bin/sh
# t_sanitizers.sh - rebuilds the unit tests with AddressSanitizer + UndefinedBehaviorSanitizer and runs them all.
set -e
root=${JETMESH_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
cd "$root"
san="-fsanitize=address,undefined -fno-sanitize-recover=all -fno-omit-frame-pointer"
make --no-print-directory -j2 BUILD=build-asan SAN="$san" OPT="-O1 -g" LIB_OPT="-O1 -g" tests-build >/dev/null
export ASAN_OPTIONS=detect_leaks=1:abort_on_error=0:halt_on_error=1
export UBSAN_OPTIONS=print_stacktrace=1:halt_on_error=1
# the culling tests' byte comparisons without the two big bench frames: the
# same code paths on the smaller real frames (the full set runs uninstrumented
# in test_cull and test_aniso_cull)
export JETMESH_TEST_SMALL=1
status=0
# two binaries at a time (CI has two cores; the instrumented binaries are the
# suite's longest part); each writes its own log, and any failure fails this
# test: xargs exits non-zero when one of its commands does
# shellcheck disable=SC2016 # $1 is expanded by the inner shell
# the longest first, so that the two lanes end together
{ for t in test_post test_aniso_cull test_cull test_memory; do
    [ -x "build-asan/bin/$t" ] && echo "build-asan/bin/$t"; done
  printf '%s\n' build-asan/bin/test_*; } | awk '!seen[$0]++' | xargs -P 2 -n 1 sh -c '
  log="build-asan/$(basename "$1").log"
  if "$1" >"$log" 2>&1; then echo "sanitizers: $(basename "$1") ok"
  else echo "sanitizers: $(basename "$1") FAILED"; tail -n 40 "$log"; exit 1; fi' sh || status=1
# the CLI end to end under the sanitizers too: a conversion and a rejected file
tmp=$(mktemp -d); trap 'rm -rf "$tmp"' EXIT
build-asan/jetmesh convert samples/jet/jet_060.csv -r 0.025 -o "$tmp/a.glb" -q
build-asan/jetmesh convert samples/real/double_dam_break_frame_26_4732_particles.vtk -r 0.025 --field sph --method mc -o "$tmp/b.obj" -q
printf 'x,y,z\n1,2\n' > "$tmp/bad.csv"
if build-asan/jetmesh convert "$tmp/bad.csv" -r 0.025 -o "$tmp/bad.glb" -q 2>"$tmp/err"; then
  echo "sanitizers: a ragged CSV was accepted"; status=1
fi
grep -q 'bad.csv:2' "$tmp/err" || { echo "sanitizers: no line number in: $(cat "$tmp/err")"; status=1; }
# frames at once (worker contexts, outputs staged and published in order),
# with a failure: --keep-going, then a stop that removes outputs made ahead
mkdir "$tmp/in"
for i in 95 96 97 98; do cp "samples/jet/jet_0$i.csv" "$tmp/in/"; done
cp "$tmp/bad.csv" "$tmp/in/jet_096.csv"
for kg in --keep-going ""; do
  # shellcheck disable=SC2086 # $kg: one option or none
  st=0
  build-asan/jetmesh convert "$tmp/in/jet_{}.csv" -r 0.025 -o "$tmp/fj/m_{}.glb" --frame-jobs 3 -j 3 -q $kg \
    2>"$tmp/err" || st=$?
  [ "$st" = 1 ] || { echo "sanitizers: frames at once $kg: exit $st, not 1"; cat "$tmp/err"; status=1; }
  grep -q 'jet_096.csv:2' "$tmp/err" || { echo "sanitizers: frames at once: $(cat "$tmp/err")"; status=1; }
done
# shards and stats merge: the reports' readers (CSV quoting, JSON escapes,
# malformed files) and the merge
for i in 0 1; do
  build-asan/jetmesh convert 'samples/jet/jet_%03d.csv' --frames 0:9 -r 0.025 -q -o "$tmp/sh/j_%03d.obj" \
    --shard $i/2 --stats "$tmp/s$i.$([ $i = 0 ] && echo csv || echo json)" || { echo "sanitizers: shard $i"; status=1; }
done
build-asan/jetmesh stats merge "$tmp/s0.csv" "$tmp/s1.json" -o "$tmp/m.json" --svg "$tmp/m.svg" -q &&
  build-asan/jetmesh stats merge "$tmp/m.json" -o "$tmp/m.csv" -q || { echo "sanitizers: stats merge"; status=1; }
printf 'index,input,status,error\n3,"a,""b""\nc",failed,"x, y"\n4,"open\n' >"$tmp/w.csv"
printf '{"frames":[{"index":1,"status":"ok","input":"\\ud83d\\ude00\\u00e9","x":[1,{"a":[]}]},{"index":2' >"$tmp/w.json"
for w in w.csv w.json; do
  st=0
  build-asan/jetmesh stats merge "$tmp/$w" -o "$tmp/w.csv.out.csv" 2>"$tmp/err" || st=$?
  [ "$st" = 1 ] || { echo "sanitizers: stats merge $w: exit $st, not 1"; cat "$tmp/err"; status=1; }
done
exit $status

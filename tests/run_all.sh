#!/bin/sh
# run_all.sh - runs every unit test binary and script test, then prints "N passed, N failed".
# Usage: tests/run_all.sh BUILD_DIR [unit|scripts|all]
BUILD=${1:-build}
what=${2:-all}
here=$(cd "$(dirname "$0")" && pwd)
root=$(cd "$here/.." && pwd)
pass=0; fail=0; failed=""
export JETMESH_BUILD="$root/$BUILD" JETMESH_ROOT="$root"
export JETMESH="$root/$BUILD/jetmesh"
export JETMESH_SHARED="${JETMESH_SHARED:-$root/../shared}"
run() { # name, command...
  name=$1; shift
  log="$root/$BUILD/logs/$name.log"
  mkdir -p "$root/$BUILD/logs"
  start=$(date +%s)
  if "$@" >"$log" 2>&1; then
    pass=$((pass + 1)); st=ok
  else
    fail=$((fail + 1)); st=FAIL; failed="$failed $name"
  fi
  printf '%-40s %s (%ss)\n' "$name" "$st" "$(( $(date +%s) - start ))"
  if [ "$st" = FAIL ]; then sed 's/^/    | /' "$log" | tail -n 40; fi
}
if [ "$what" != scripts ]; then
  # every tests/test_*.c must have been built: a missing binary is a failure,
  # never a silent pass
  for src in "$here"/test_*.c; do
    t="$root/$BUILD/bin/$(basename "$src" .c)"
    if [ -x "$t" ]; then
      run "$(basename "$t")" "$t"
    else
      run "$(basename "$t")" sh -c "echo 'not built: $t (run make tests-build)'; exit 1"
    fi
  done
fi
if [ "$what" != unit ]; then
  for t in "$here"/t_*.sh; do
    [ -f "$t" ] || continue
    run "$(basename "$t" .sh)" sh "$t"
  done
fi
echo
[ -n "$failed" ] && echo "failed:$failed"
echo "$pass passed, $fail failed"
[ "$fail" = 0 ]

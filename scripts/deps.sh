#!/bin/sh
# deps.sh - installs the Debian packages (and pinned npm test tools) jetmesh needs, if missing.
# Usage: scripts/deps.sh [build|test|all]   (default: all)
#   build: the compilers and libraries (make, make demo, make bench)
#   test|all: those and the test tools (make check): Blender, Slurm and munge,
#          GNU parallel, valgrind, clang, mandoc, node and npm with tests/js
set -e
what=${1:-all}
build_pkgs="gcc g++ make pkg-config zlib1g-dev libtinygltf-dev libdraco-dev libcmocka-dev libmeshoptimizer-dev"
test_pkgs="draco mandoc clang valgrind libclang-rt-14-dev libxml2-utils strace blender python3-numpy"
# the cluster recipes' tests (tests/t_parallel.sh, tests/t_slurm.sh)
test_pkgs="$test_pkgs parallel slurmctld slurmd slurm-client munge"
case "$what" in
  build) pkgs="$build_pkgs" ;;
  test|all) pkgs="$build_pkgs $test_pkgs" ;;
  *) echo "usage: $0 [build|test|all]" >&2; exit 2 ;;
esac
missing=""
for p in $pkgs; do
  dpkg-query -W -f='${Status}' "$p" 2>/dev/null | grep -q "install ok installed" || missing="$missing $p"
done
# node and npm may come from another repository (npm is bundled there and the
# Debian npm package conflicts with it): check the commands, not packages
if [ "$what" != build ]; then
  command -v node >/dev/null 2>&1 || missing="$missing nodejs"
  command -v npm >/dev/null 2>&1 || missing="$missing npm"
fi
if [ -n "$missing" ]; then
  if [ "$(id -u)" = 0 ]; then
    echo "deps: installing:$missing"
    export DEBIAN_FRONTEND=noninteractive
    apt-get update -qq >/dev/null
    # shellcheck disable=SC2086
    apt-get install -y -qq $missing >/dev/null
  else
    echo "deps: missing Debian packages:$missing" >&2
    echo "deps: run as root:  apt-get install -y$missing" >&2
    exit 1
  fi
fi
if [ "$what" != build ]; then
  here=$(cd "$(dirname "$0")/.." && pwd)
  js="$here/tests/js"
  if [ -f "$js/package.json" ] && ! [ -f "$js/node_modules/.jetmesh-ok" ] ; then
    echo "deps: installing pinned npm test tools in tests/js"
    (cd "$js" && npm ci --no-audit --no-fund --loglevel=error >/dev/null && touch node_modules/.jetmesh-ok)
  fi
fi
exit 0

# lib.sh - the common start of the t_cli_*.sh tests (sourced): ROOT, the binary J, the jet sample S, fail, run, a scratch T.
#
# Source it as `. "$(dirname "$0")/lib.sh"` from a script in tests/; $0 is
# then that script, so ROOT is the repository without JETMESH_ROOT too.
# Env: JETMESH_ROOT (the repository), JETMESH (the binary), TMPDIR.
set -u
ROOT=${JETMESH_ROOT:-$(cd "$(dirname "$0")/.." && pwd)}
J=${JETMESH:-$ROOT/build/jetmesh}
# shellcheck disable=SC2034 # S is for the scripts that source this
S=$ROOT/samples/jet
fail() { echo "FAIL: $*"; exit 1; }
[ -x "$J" ] || fail "no jetmesh binary at $J (run make all)"

scratch() { # name: T, a new directory jetmesh-NAME.XXXXXX, removed on exit
    T=$(mktemp -d "${TMPDIR:-/tmp}/jetmesh-$1.XXXXXX") || exit 1
    trap 'rm -rf "$T"' EXIT INT TERM
}

run() { # expected-status args...: runs jetmesh, output in $T/out, $T/err
    want=$1; shift
    "$J" "$@" >"$T/out" 2>"$T/err"
    st=$?
    [ "$st" = "$want" ] || { cat "$T/out" "$T/err"; fail "exit $st, not $want: jetmesh $*"; }
}

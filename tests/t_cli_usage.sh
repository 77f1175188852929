#!/bin/sh
# t_cli_usage.sh - jetmesh --help/--version, help texts, and usage errors that must exit 2 with a --help hint.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch usage

# --version prints "jetmesh JM_VERSION_STRING"
ver=$(sed -n 's/^#define JM_VERSION_STRING "\(.*\)"$/\1/p' "$ROOT/lib/jetmesh.h")
[ -n "$ver" ] || fail "no JM_VERSION_STRING in lib/jetmesh.h"
[ "$("$J" --version)" = "jetmesh $ver" ] || fail "--version: got '$("$J" --version)'"
[ "$("$J" convert --version)" = "jetmesh $ver" ] || fail "convert --version"

# help texts on stdout, exit 0
"$J" --help >"$T/h" 2>"$T/e" || fail "--help exit $?"
for w in convert generate bench help; do grep -q "$w" "$T/h" || fail "--help does not mention $w"; done
[ ! -s "$T/e" ] || fail "--help wrote to stderr"
"$J" convert --help >"$T/ch" || fail "convert --help exit $?"
grep -q '^Usage: jetmesh convert' "$T/ch" || fail "convert --help has no usage line"
"$J" help convert >"$T/ch2" || fail "help convert exit $?"
cmp -s "$T/ch" "$T/ch2" || fail "'help convert' differs from 'convert --help'"
"$J" generate --help >"$T/gh" || fail "generate --help exit $?"
grep -q 'spray N' "$T/gh" || fail "generate --help does not list the scenes"

# usage errors: exit 2, a message, and the one-line hint to --help
n=0
usage_error() { # args...: must exit 2 with a hint
    n=$((n + 1))
    "$J" "$@" >"$T/o" 2>"$T/e"
    st=$?
    [ "$st" = 2 ] || { cat "$T/o" "$T/e"; fail "exit $st, not 2, for: jetmesh $*"; }
    grep -q -- "--help" "$T/e" || { cat "$T/e"; fail "no --help hint for: jetmesh $*"; }
    [ "$(wc -l <"$T/e")" -le 3 ] || { cat "$T/e"; fail "usage message too long for: jetmesh $*"; }
    [ ! -e "$T/x.obj" ] || fail "an output was written for: jetmesh $*"
}
IN=$S/jet_010.csv
usage_error
usage_error frobnicate
usage_error help frobnicate
usage_error convert
usage_error convert "$IN" -o "$T/x.obj"                     # no radius
usage_error convert "$IN" -r 0.025                          # no output
usage_error convert -r 0.025 -o "$T/x.obj"                  # no input
usage_error convert "$IN" -r 0 -o "$T/x.obj"
usage_error convert "$IN" -r -1 -o "$T/x.obj"
usage_error convert "$IN" -r abc -o "$T/x.obj"
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --bogus
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" -Z
usage_error convert "$IN" -o "$T/x.obj" -r
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" -c 0
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --field blobby
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --method dc
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --uv cubic
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --uv-scale 0
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --threshold x
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --smoothing-length -2
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --link-distance 0
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" -j -1
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" -j two
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --format stl
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --input-format xls
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --frames 9:1
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --frames 1:9:0
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --frames a:b
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --frames 0:5     # selects nothing (frame 10)
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --max-memory 12Q
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --max-memory -1G
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --draco-position-bits 0
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --draco-normal-bits 31
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --draco-uv-bits x
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --stats "$T/s.txt"
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --draco
usage_error convert "$IN" -r 0.025 -o "$T/x.obj" --embed
usage_error convert "$IN" -r 0.025 -o "$T/x.unknown"
usage_error convert "$IN" -r 0.025 -o "$T/x_{}_{}.obj"
usage_error convert "$T/none_{}.csv" -r 0.025 -o "$T/x.obj"          # matches nothing
usage_error convert "$T/dir_{}/a.csv" -r 0.025 -o "$T/x.obj"         # placeholder in a directory
usage_error convert "$S/jet_010.csv" "$S/jet_011.csv" -r 0.025 -o "$T/x.obj"  # 2 frames, 1 file
mkdir "$T/d" "$T/sub"
cp "$S/jet_010.csv" "$T/a.csv"
cp "$S/jet_011.csv" "$T/sub/a.csv"
usage_error convert "$T/a.csv" "$T/sub/a.csv" -r 0.025 -o "$T/d/"        # both would write d/a.glb
usage_error generate
usage_error generate volcano -o "$T/v.csv"
usage_error generate block -o "$T/v.csv"
usage_error generate block 10 -o "$T/v.txt"
usage_error generate block ten -o "$T/v.csv"
usage_error generate block 10
usage_error generate jet extra -o "$T/v.csv"
usage_error generate jet -o "$T/v.csv" --frames 0:9
usage_error generate jet -o "$T/v_{}.csv" --seed -3
usage_error generate jet -o "$T/v_{}.csv" -r 0
echo "$n usage errors exit 2 with a hint"

#!/bin/sh
# t_cli_params.sh - every refused parameter is named by its option, value and range; oversized frames name --cube-size; empty meshes warn.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch params
F=$S/jet_050.csv

# bad VALUE for OPTION: exit 2, the option, the value and the accepted range
refused() { # option value range-words extra-args...
    opt=$1 val=$2 words=$3; shift 3
    run 2 convert "$F" -r 0.025 "$@" "$opt" "$val" -o "$T/x.obj"
    grep -q -- "$opt $val is out of range" "$T/err" || { cat "$T/err"; fail "$opt $val: not named"; }
    grep -q -- "$words" "$T/err" || { cat "$T/err"; fail "$opt $val: no range '$words'"; }
    if grep -q "invalid argument" "$T/err"; then fail "$opt $val: the bare status message"; fi
    [ ! -e "$T/x.obj" ] || fail "$opt $val: wrote an output"
}
refused --cube-size 0.0005 "0.001 to 100"
refused --cube-size 150 "0.001 to 100"
refused --smoothing-length 0.01 "0.05 to 100" --field sph
refused --smoothing-length 1000 "0.05 to 100"
refused --threshold 1.5 "above -1 and below 1" --field metasphere
refused --threshold -1 "above -1 and below 1" --field metasphere
refused --threshold -0.5 "above 0 for the sph field" --field sph
# the issue's own example
run 2 convert "$F" -r 0.025 -c 0.0005 -o "$T/out.obj"
grep -q "^jetmesh convert: --cube-size 0.0005 is out of range; accepted: 0.001 to 100" "$T/err" || { cat "$T/err"; fail "the -c 0.0005 message"; }
# accepted ends of the ranges still convert
run 0 convert "$F" -r 0.025 -q -c 100 --field metasphere --threshold 0.99 -o "$T/a.obj"
run 0 convert "$F" -r 0.025 -q --field sph --smoothing-length 0.05 -o "$T/b.obj"

# bench shares the path
run 1 bench --scene jet -c 0.0001 -j 1 --repeat 1 --warmup 1
grep -q -- "--cube-size 0.0001 is out of range; accepted: 0.001 to 100" "$T/err" "$T/out" || { cat "$T/out" "$T/err"; fail "bench: option not named"; }

# a frame that would need more than the machine has points at --cube-size
# (with a cube size that fits), not only at --max-memory
"$J" generate block 20000 -o "$T/block.xyz" -q || fail "generate"
run 3 convert "$T/block.xyz" -r 0.025 -c 0.001 -o "$T/big.obj"
grep -q "more than this machine has" "$T/err" || { cat "$T/err"; fail "no 'more than this machine has'"; }
grep -q "use a larger --cube-size; --cube-size [0-9.]* would need about" "$T/err" || { cat "$T/err"; fail "no --cube-size advice with a size"; }
if grep -q "raise --max-memory" "$T/err"; then fail "advises --max-memory for a frame the machine cannot hold"; fi
# the suggested size converts within the default limit
c=$(sed -n 's/.*; --cube-size \([0-9.]*\) would need.*/\1/p' "$T/err" | head -n 1)
[ -n "$c" ] || fail "no suggested size"
# over --max-memory only: both options, and the machine's memory
run 3 convert "$T/block.xyz" -r 0.025 -c 0.25 --max-memory 40M -o "$T/big.obj"
grep -q "over the limit of 40.0 MiB: raise --max-memory (this machine has .*) or use a larger --cube-size" "$T/err" \
    || { cat "$T/err"; fail "over --max-memory: both options"; }
run 0 convert "$T/block.xyz" -r 0.025 -c 0.25 --max-memory 40M -o "$T/big.obj" -q -c "$(sed -n 's/.*; --cube-size \([0-9.]*\) would need.*/\1/p' "$T/err" | head -n 1)"

# a threshold that leaves particles with an empty mesh warns (once, then a count)
run 0 convert "$S/jet_05{}.csv" -r 0.025 --field sph --threshold 5 -q -o "$T/e_{}.obj"
grep -q "warning: frame 0 (.*jet_050.csv): 64 particles gave an empty mesh.*--threshold 5" "$T/err" || { cat "$T/err"; fail "no empty-mesh warning"; }
[ "$(grep -c 'gave an empty mesh' "$T/err")" = 1 ] || { cat "$T/err"; fail "one detailed warning expected"; }
grep -q "warning: 10 frames with particles gave empty meshes" "$T/err" || { cat "$T/err"; fail "no count of empty meshes"; }
# values too small for a float became 0, which means "the default": refused,
# naming the range
for a in "-c 1e-50:from 0.001 to 100" "-r 1e-40:from 1.2e-38 to 1e+30" \
    "--field sph --threshold 1e-50:at least 1.2e-38 in size"; do
    # shellcheck disable=SC2086
    run 2 convert "$F" -r 0.025 ${a%%:*} -o "$T/tiny.obj"
    grep -q "must be a number .*${a#*:}.*, not '" "$T/err" || { cat "$T/err"; fail "${a%%:*}: not refused with its range"; }
done
# no warning for a normal conversion
run 0 convert "$F" -r 0.025 -q -o "$T/n.obj"
[ ! -s "$T/err" ] || { cat "$T/err"; fail "unexpected warning"; }
echo "ok"

#!/bin/sh
# t_cli_units.sh - the unit of length does not matter: two particles 1.5 r apart mesh alike at -r 1e10, 1e-25 and 1e19 (issue 14), and what float precision cannot hold is refused with advice.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch units

pair() { # r file: two particles 1.5 r apart (off the lattice's nodes)
    awk -v r="$1" 'BEGIN { printf "x,y,z\n%.9g,%.9g,%.9g\n%.9g,%.9g,%.9g\n", 0.3 * r, 0.2 * r, 0.1 * r, 1.8 * r, 0.2 * r, 0.1 * r }' >"$2"
}

# vertices: a count, no NaN or infinity; prints the x extent in units of r
extent() { # obj r what
    n=$(grep -c '^v ' "$1")
    [ "$n" -gt 100 ] || fail "$3: $n vertices"
    if grep -i '^v .*\(nan\|inf\)' "$1" >/dev/null; then fail "$3: NaN or infinite vertices"; fi
    awk -v r="$2" '$1 == "v" { x = $2 / r; if (!seen || x < lo) lo = x; if (!seen || x > hi) hi = x; seen = 1 }
        END { printf "%.6f %.6f\n", lo, hi }' "$1"
}
# the same extent within a thousandth of r (the two balls and the neck:
# about -0.6 r to 2.7 r or more)
same() { # "lo hi" "lo hi" what
    echo "$1 $2" | awk -v what="$3" '{ if (($1 - $3) ^ 2 > 1e-6 || ($2 - $4) ^ 2 > 1e-6 || $1 > -0.5 || $2 < 2.6) {
        printf "FAIL: %s: x from %g r to %g r, at -r 1 from %g r to %g r\n", what, $3, $4, $1, $2; exit 1 } }' || exit 1
}

pair 1 "$T/one.csv"
for f in "--field metasphere --method mt" "--field metasphere --method mc" "--field sph --method mc" "--field sph --method mt"; do
    # shellcheck disable=SC2086
    run 0 convert "$T/one.csv" -r 1 $f -o "$T/one.obj" -q
    ref=$(extent "$T/one.obj" 1 "-r 1 $f") || { echo "$ref"; exit 1; }
    for r in 1e10 1e-25 1e19; do
        pair "$r" "$T/p.csv"
        # shellcheck disable=SC2086
        run 0 convert "$T/p.csv" -r "$r" $f -o "$T/p.obj"
        if grep -q "empty mesh" "$T/err"; then cat "$T/err"; fail "-r $r $f: an empty mesh"; fi
        got=$(extent "$T/p.obj" "$r" "-r $r $f") || { echo "$got"; exit 1; }
        same "$ref" "$got" "-r $r $f"
    done
done
# the issue's commands, exactly
pair 1e10 "$T/a.csv"
run 0 convert "$T/a.csv" -r 1e10 -o "$T/a.obj"
got=$(extent "$T/a.obj" 1e10 "-r 1e10") || { echo "$got"; exit 1; }
pair 1e-25 "$T/b.csv"
run 0 convert "$T/b.csv" -r 1e-25 -o "$T/b.obj"
got=$(extent "$T/b.obj" 1e-25 "-r 1e-25") || { echo "$got"; exit 1; }
pair 1e19 "$T/c.csv"
run 0 convert "$T/c.csv" -r 1e19 --field sph -o "$T/c.obj"
got=$(extent "$T/c.obj" 1e19 "--field sph -r 1e19") || { echo "$got"; exit 1; }
echo "ok: -r 1e10, 1e-25 and 1e19 mesh like -r 1"

# a subnormal radius is refused as a number, before reading anything
run 2 convert "$T/one.csv" -r 1e-40 -o "$T/t.obj"
grep -q "from 1.2e-38 to 1e+30, not '1e-40'" "$T/err" || { cat "$T/err"; fail "-r 1e-40 not refused"; }
# coordinates beyond 2^16 cubes from the origin: refused with the way out
awk -F, 'NR == 1 { print; next } { printf "%.9g,%.9g,%.9g\n", $1 + 1e4, $2, $3 }' "$S/jet_050.csv" >"$T/far.csv"
run 1 convert "$T/far.csv" -r 0.025 -o "$T/far.obj"
grep -q "outside the numeric domain: the particles lie from .* the lattice reaches 819.2 from the origin (65536 cube edges .*: --cube-size 6.11 or more reaches them (a coarser mesh), or move them nearer the origin: subtract their centre" "$T/err" \
    || { cat "$T/err"; fail "far coordinates not refused with advice"; }
[ ! -e "$T/far.obj" ] || fail "a refused frame wrote a mesh"
# ... and they mesh once nearer (or with cubes large enough)
run 0 convert "$T/far.csv" -r 0.025 -c 8 -o "$T/far.obj" -q
echo "ok: the numeric domain is refused with advice"

#!/bin/sh
# t_cli_man.sh - man/jetmesh.1 is clean under mandoc -Tlint and documents every long option the --help texts list.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
MAN=$ROOT/man/jetmesh.1
[ -f "$MAN" ] || fail "no $MAN"
command -v mandoc >/dev/null 2>&1 || fail "mandoc is not installed (scripts/deps.sh test installs it)"
scratch man

mandoc -Tlint -W style "$MAN" >"$T/lint" 2>&1
st=$?
[ "$st" = 0 ] && [ ! -s "$T/lint" ] || { cat "$T/lint"; fail "mandoc -Tlint reports the above (status $st)"; }
echo "mandoc -Tlint: clean"

mandoc -Tascii "$MAN" 2>/dev/null | col -b >"$T/page" || fail "mandoc cannot render the page"
for s in NAME SYNOPSIS DESCRIPTION OPTIONS FIELDS FORMATS STATISTICS "EXIT STATUS" EXAMPLES "SEE ALSO"; do
    grep -q "^$s\$" "$T/page" || fail "no section $s"
done

# every long option of the help texts appears in the rendered page
"$J" convert --help >"$T/help" || fail "convert --help"
"$J" generate --help >>"$T/help" || fail "generate --help"
"$J" stats merge --help >>"$T/help" || fail "stats merge --help"
if "$J" bench --help >"$T/bench" 2>/dev/null; then # the placeholder bench has no --help
    cat "$T/bench" >>"$T/help"
else
    echo "note: jetmesh bench --help fails: bench options not cross-checked"
fi
grep -o -- '--[a-z][a-z0-9-]*' "$T/help" | sort -u >"$T/opts"
[ "$(wc -l <"$T/opts")" -ge 30 ] || fail "too few options found in the help texts"
missing=""
while read -r opt; do
    grep -Eq -- "$opt([^a-z0-9-]|\$)" "$T/page" || missing="$missing $opt"
done <"$T/opts"
[ -z "$missing" ] || fail "options in --help but not in the man page:$missing"
echo "$(wc -l <"$T/opts") long options, all documented"

# the bench options and the exit statuses are documented
for opt in --json --repeat --min-time --threads --field --method; do
    grep -Eq -- "$opt([^a-z0-9-]|\$)" "$T/page" || fail "bench option $opt not documented"
done
for st in 0 1 2 3; do
    sed -n '/^EXIT STATUS$/,/^EXAMPLES$/p' "$T/page" | grep -Eq "^[[:space:]]+$st([[:space:]]|\$)" || fail "exit status $st not documented"
done
# the statistics columns
for c in index input particles dropped vertices triangles bytes ms_read ms_field ms_extract \
    ms_attributes ms_post ms_write ms_total peak_rss_bytes lib_peak_bytes status error; do
    sed -n '/^STATISTICS$/,/^EXIT STATUS$/p' "$T/page" | grep -q -- "$c" || fail "statistics column $c not documented"
done
echo "man page ok"

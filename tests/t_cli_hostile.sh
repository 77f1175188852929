#!/bin/sh
# t_cli_hostile.sh - hostile and unusual inputs, paths and options hold the contract (issue 30): each part fails on the code before it.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
scratch hostile

no_temps() {
    if find "$T" -name '*jetmesh-tmp*' | grep -q .; then fail "temporaries left: $(find "$T" -name '*jetmesh-tmp*')"; fi
}
V=$ROOT/samples/real/double_dam_break_frame_26_4732_particles.vtk

# 1. standard input ("-", /dev/stdin) and FIFOs are read once: the field
#    choice, --attributes all and the conversion share the bytes (a second
#    open of a drained FIFO waited for a writer forever; /dev/stdin said
#    "empty file"). timeout only guards against that hang.
cp "$S/jet_050.csv" "$T/in.csv"
run 0 convert "$T/in.csv" -r 0.025 -o "$T/file.obj"
timeout 120 "$J" convert - --input-format csv -r 0.025 -o "$T/dash.obj" <"$T/in.csv" >"$T/out" 2>"$T/err" ||
    { cat "$T/err"; fail "convert - from a file"; }
cmp -s "$T/file.obj" "$T/dash.obj" || fail "'-' gave another mesh"
cat "$T/in.csv" | timeout 120 "$J" convert /dev/stdin --input-format csv -r 0.025 -o "$T/devstdin.obj" \
    >"$T/out" 2>"$T/err" || { cat "$T/err"; fail "/dev/stdin from a pipe"; }
cmp -s "$T/file.obj" "$T/devstdin.obj" || fail "/dev/stdin gave another mesh"
gzip -c "$V" | timeout 120 "$J" convert - -r 0.025 -o "$T/vtk.ply" --attributes all >"$T/out" 2>"$T/err" ||
    { cat "$T/err"; fail "a gzipped VTK on a pipe (format by magic, --attributes all)"; }
run 0 convert "$V" -r 0.025 -o "$T/vtk_file.ply" --attributes all
cmp -s "$T/vtk.ply" "$T/vtk_file.ply" || fail "the piped VTK gave another mesh"
mkfifo "$T/fifo.csv"
cat "$T/in.csv" >"$T/fifo.csv" &
writer=$!
timeout 120 "$J" convert "$T/fifo.csv" -r 0.025 -o "$T/fifo.obj" >"$T/out" 2>"$T/err"
st=$?
kill "$writer" 2>/dev/null
[ "$st" = 0 ] || { cat "$T/err"; fail "a FIFO input: exit $st (124: it hung)"; }
cmp -s "$T/file.obj" "$T/fifo.obj" || fail "the FIFO gave another mesh"
printf 'x,y,z\n0,0,0\n' | "$J" convert - -r 0.025 -o "$T/x.obj" >"$T/out" 2>"$T/err"
grep -q '<stdin>.*--input-format' "$T/err" || { cat "$T/err"; fail "CSV on standard input without --input-format: no hint"; }
no_temps
echo "ok: standard input and FIFOs are read once"

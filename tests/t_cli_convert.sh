#!/bin/sh
# t_cli_convert.sh - end to end: jet sample frames to OBJ/GLB/PLY, patterns and output naming, CSV edge cases.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
[ -f "$S/jet_099.csv" ] || fail "no jet sample in $S"
scratch convert

# the number N in "... N what," of a frame line
field() { # line what
    echo "$1" | sed -n "s/.* \([0-9][0-9]*\) $2[,)].*/\1/p"
}

# an OBJ has as many v/vn/vt lines as the frame line's vertices, f lines as triangles
check_obj() { # file line
    v=$(field "$2" vertices); t=$(field "$2" triangles)
    [ -n "$v" ] && [ -n "$t" ] || fail "cannot parse the frame line: $2"
    [ "$(grep -c '^v ' "$1")" = "$v" ] || fail "$1: v lines differ from $v vertices"
    [ "$(grep -c '^vn ' "$1")" = "$v" ] || fail "$1: vn lines differ from $v vertices"
    [ "$(grep -c '^vt ' "$1")" = "$v" ] || fail "$1: vt lines differ from $v vertices"
    [ "$(grep -c '^f ' "$1")" = "$t" ] || fail "$1: f lines differ from $t triangles"
}

# a GLB: magic "glTF", version 2, total length = file size
check_glb() {
    [ "$(head -c 4 "$1")" = "glTF" ] || fail "$1: no glTF magic"
    set -- "$1" $(od -An -tu4 -j4 -N8 "$1")
    [ "$2" = 2 ] || fail "$1: glTF version $2"
    [ "$3" = "$(wc -c <"$1" | tr -d ' ')" ] || fail "$1: GLB length $3 is not the file size"
}

# 1. a {} pattern and --frames to an OBJ template: padding carries over
run 0 convert "$S/jet_{}.csv" --frames 40:45 -r 0.025 -o "$T/obj/m_{}.obj"
[ "$(grep -c '^frame ' "$T/out")" = 6 ] || fail "expected 6 frame lines"
[ ! -s "$T/err" ] || { cat "$T/err"; fail "stderr not empty (no terminal: no progress bar)"; }
for i in 40 41 42 43 44 45; do
    line=$(grep "^frame $i " "$T/out") || fail "no line for frame $i"
    echo "$line" | grep -Eq "^frame $i .*/jet_0$i\.csv: [0-9]+ particles, [0-9]+ vertices, [0-9]+ triangles, [0-9.]+ ms -> .*/m_0$i\.obj\$" ||
        fail "frame line format: $line"
    check_obj "$T/obj/m_0$i.obj" "$line"
done
[ "$(ls "$T/obj" | wc -l)" = 6 ] || fail "expected exactly 6 outputs: $(ls -A "$T/obj")"
grep -q '^converted 6 of 6 frames' "$T/out" || fail "no summary line"
echo "ok: {} pattern to OBJ template"

# 2. printf pattern with a range, to a printf template
run 0 convert "$S/jet_%03d.csv" --frames 7:11:2 -r 0.025 -o "$T/p/f%04d.obj" -q
[ ! -s "$T/out" ] || fail "-q printed something"
[ "$(ls "$T/p")" = "$(printf 'f0007.obj\nf0009.obj\nf0011.obj')" ] || fail "printf naming: $(ls "$T/p")"
echo "ok: %03d pattern, STEP, %04d output"

# 3. a directory output to GLB (the default extension), plain paths
mkdir "$T/glb"
run 0 convert "$S/jet_098.csv" "$S/jet_099.csv" -r 0.025 -o "$T/glb"
for i in 98 99; do check_glb "$T/glb/jet_0$i.glb"; done
[ "$(ls "$T/glb" | wc -l)" = 2 ] || fail "directory output: $(ls -A "$T/glb")"
run 0 convert "$S/jet_050.csv" "$S/jet_051.csv" -r 0.025 -o "$T/newdir/" --format ply
[ -f "$T/newdir/jet_050.ply" ] && [ -f "$T/newdir/jet_051.ply" ] || fail "directory output with --format ply"
head -c 3 "$T/newdir/jet_050.ply" | grep -q ply || fail "not a PLY"
echo "ok: directory outputs (glb by default, --format ply)"

# 4. a single frame: plain path index from its name, GLB with Draco by name
run 0 convert "$S/jet_012.csv" -r 0.025 -o "$T/one_{}.glb"
[ -f "$T/one_012.glb" ] || fail "plain path index: $(ls "$T")"
run 0 convert "$S/jet_099.csv" -r 0.025 -o "$T/web.draco.glb"
check_glb "$T/web.draco.glb"
grep -q KHR_draco_mesh_compression "$T/web.draco.glb" || fail ".draco.glb has no KHR_draco_mesh_compression"
run 0 convert "$S/jet_099.csv" -r 0.025 -o "$T/plain.glb"
[ "$(wc -c <"$T/web.draco.glb")" -lt "$(wc -c <"$T/plain.glb")" ] || fail "Draco GLB is not smaller"
echo "ok: single frames, Draco"

# 4b. the real frame (legacy VTK, binary): its plain-path index is the number after "frame"
R=$ROOT/samples/real/double_dam_break_frame_26_4732_particles.vtk
if [ -f "$R" ]; then
    run 0 convert "$R" -r 0.025 -o "$T/real_{}.glb"
    grep -q '^frame 26 .*: 4732 particles, [1-9][0-9]* vertices' "$T/out" || fail "real frame: $(cat "$T/out")"
    check_glb "$T/real_26.glb"
    echo "ok: the real VTK frame"
else
    echo "note: no samples/real frame yet"
fi

# 5. deterministic, whatever the thread count
run 0 convert "$S/jet_099.csv" -r 0.025 -j 1 -o "$T/j1.obj"
run 0 convert "$S/jet_099.csv" -r 0.025 -j 2 -o "$T/j2.obj"
run 0 convert "$S/jet_099.csv" -r 0.025 -j 0 -o "$T/j0.obj"
cmp -s "$T/j1.obj" "$T/j2.obj" && cmp -s "$T/j1.obj" "$T/j0.obj" || fail "the mesh depends on -j"
echo "ok: -j 1/2/0 give identical files"

# 6. options reach the library and writer
run 0 convert "$S/jet_099.csv" -r 0.025 --no-normals --uv none -o "$T/bare.obj"
[ "$(grep -c '^vn ' "$T/bare.obj")" = 0 ] && [ "$(grep -c '^vt ' "$T/bare.obj")" = 0 ] ||
    fail "--no-normals --uv none still wrote vn/vt"
run 0 convert "$S/jet_099.csv" -r 0.025 -c 1 -o "$T/coarse.obj"
[ "$(grep -c '^f ' "$T/coarse.obj")" -lt "$(grep -c '^f ' "$T/j1.obj")" ] || fail "-c 1 is not coarser"
run 0 convert "$S/jet_099.csv" -r 0.025 --field sph --method mc -v -o "$T/sph.obj"
grep -q 'field sph, method mc' "$T/out" || fail "-v does not show the parameters"
grep -q '^  read [0-9.]* ms, field' "$T/out" || fail "-v does not show stage times"
[ "$(grep -c '^f ' "$T/sph.obj")" -gt 0 ] || fail "sph/mc gave no triangles"
echo "ok: options"

# 7. CSV edge cases
printf 'x,y,z\n' >"$T/empty.csv"
run 0 convert "$T/empty.csv" -r 0.025 -o "$T/empty.obj"
grep -q ': 0 particles, 0 vertices, 0 triangles' "$T/out" || fail "empty frame line: $(cat "$T/out")"
[ -f "$T/empty.obj" ] && [ "$(grep -c '^f ' "$T/empty.obj")" = 0 ] || fail "empty frame: no valid empty mesh"
run 0 convert "$T/empty.csv" -r 0.025 -o "$T/empty.glb"
check_glb "$T/empty.glb"
# CRLF, comments, blanks, an id column, quoted header, spaces
{
    printf '# exported by a simulator\r\n'
    printf '"id" , "x" , "y" , "z"\r\n'
    tail -n +2 "$S/jet_020.csv" | awk -F, '{ printf "%d , %s , %s , %s\r\n", NR - 1, $1, $2, $3 }'
    printf '\r\n'
} >"$T/crlf.csv"
run 0 convert "$S/jet_020.csv" -r 0.025 -o "$T/ref.obj"
ref=$(grep '^frame' "$T/out")
run 0 convert "$T/crlf.csv" -r 0.025 -o "$T/crlf.obj"
got=$(grep '^frame' "$T/out")
[ "$(field "$ref" triangles)" = "$(field "$got" triangles)" ] || fail "CRLF/id CSV meshes differently: $ref / $got"
cmp -s "$T/ref.obj" "$T/crlf.obj" || fail "CRLF/id CSV gives a different OBJ"
# gzip-compressed input
gzip -c "$S/jet_020.csv" >"$T/jet_020.csv.gz"
run 0 convert "$T/jet_020.csv.gz" -r 0.025 -o "$T/gz/"
[ -f "$T/gz/jet_020.glb" ] || fail "gz input: directory naming drops .csv.gz: $(ls "$T/gz")"
# a NaN: fails without --drop-invalid, dropped with it
{ cat "$S/jet_020.csv"; echo 'nan,0,0'; } >"$T/nan.csv"
run 1 convert "$T/nan.csv" -r 0.025 -o "$T/nan.obj"
grep -q 'nan.csv' "$T/err" || fail "the NaN error does not name the file: $(cat "$T/err")"
[ ! -e "$T/nan.obj" ] || fail "a failed frame left an output"
run 0 convert "$T/nan.csv" -r 0.025 --drop-invalid -o "$T/nan.obj"
grep -q '(1 dropped)' "$T/out" || fail "--drop-invalid: $(cat "$T/out")"
cmp -s "$T/ref.obj" "$T/nan.obj" || fail "dropping the NaN particle changed the mesh"
echo "ok: CSV edge cases (empty, CRLF/id/comments, gzip, NaN)"

# 8. the progress bar: on stderr only when it is a terminal, never with -q
if command -v script >/dev/null 2>&1 && script -qec true /dev/null >/dev/null 2>&1; then
    script -qec "'$J' convert '$S/jet_{}.csv' --frames 0:5 -r 0.025 -o '$T/tty/' >/dev/null" /dev/null >"$T/tty.txt" 2>&1
    grep -q 'frames/s' "$T/tty.txt" && grep -q 'ETA' "$T/tty.txt" || fail "no progress bar on a terminal"
    script -qec "'$J' convert '$S/jet_{}.csv' --frames 0:5 -r 0.025 -q -o '$T/tty/'" /dev/null >"$T/tty.txt" 2>&1
    [ ! -s "$T/tty.txt" ] || fail "-q still draws a progress bar"
    echo "ok: progress bar only on a terminal"
else
    echo "note: no script(1): progress bar on a terminal not checked"
fi

# 9. --no-sync writes the same bytes (it only skips the flush to disk), and
#    a default run does flush each output before its rename
"$J" convert "$S/jet_040.csv" -r 0.025 -q -o "$T/sync.glb"
"$J" convert "$S/jet_040.csv" -r 0.025 -q --no-sync -o "$T/nosync.glb"
cmp -s "$T/sync.glb" "$T/nosync.glb" || fail "--no-sync changed the output"
if command -v strace >/dev/null 2>&1; then
    n=$(strace -f -e trace=fsync,fdatasync -o "$T/strace.txt" "$J" convert "$S/jet_040.csv" -r 0.025 -q -o "$T/s2.glb" && grep -c 'sync(' "$T/strace.txt")
    [ "$n" -ge 1 ] || fail "the output was not flushed before its rename"
    m=$(strace -f -e trace=fsync,fdatasync -o "$T/strace2.txt" "$J" convert "$S/jet_040.csv" -r 0.025 -q --no-sync -o "$T/s3.glb" && grep -c 'sync(' "$T/strace2.txt" || true)
    [ "$m" = 0 ] || fail "--no-sync still flushed ($m)"
fi
echo "ok: --no-sync"

# 10. no temporaries left anywhere
if find "$T" -name '*jetmesh-tmp*' | grep -q .; then fail "temporaries left: $(find "$T" -name '*jetmesh-tmp*')"; fi
echo "all convert checks passed"

#!/bin/sh
# t_cli_kill.sh - SIGTERM/SIGHUP/SIGKILL mid-run never leave a truncated output; a killed run's leftovers go at the next run.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
T=$(mktemp -d "${TMPDIR:-/tmp}/jetmesh-kill.XXXXXX") || exit 1
pid=""
cleanup() { [ -n "$pid" ] && kill -KILL "$pid" 2>/dev/null; rm -rf "$T"; }
trap cleanup EXIT
trap 'exit 1' INT TERM

temps() { # dir: the atomic writer's temporaries in it
    ls -A "$1" | grep 'jetmesh-tmp' || true
}

# the previous good output, and a large input (a block meshes into a big mesh)
"$J" convert "$S/jet_099.csv" -r 0.025 -q -o "$T/big.obj" || fail "setup: convert"
cp "$T/big.obj" "$T/good.obj"
"$J" generate block 4000 -q -o "$T/block.csv" || fail "setup: generate"
# the complete new mesh, for a signal that lands just after the rename
"$J" convert "$T/block.csv" -r 0.025 -q -o "$T/new.obj" || fail "setup: reference"
# After a signal: big.obj is the previous file or the complete new mesh,
# never anything else (the rename may land between the temporary showing
# up and the signal, on a loaded machine)
old_or_new() {
    cmp -s "$T/big.obj" "$T/good.obj" || cmp -s "$T/big.obj" "$T/new.obj"
}

# Starts the big conversion to $T/big.obj in the background; sets pid.
start_big() {
    "$J" convert "$T/block.csv" -r 0.025 -o "$T/big.obj" >"$T/out" 2>"$T/err" &
    pid=$!
}
# Waits up to ~20 s for the temporary of big.obj to appear (the write stage);
# returns 1 if the process ended first.
await_temp() {
    i=0
    while [ $i -lt 1000 ]; do
        [ -n "$(temps "$T")" ] && return 0
        kill -0 "$pid" 2>/dev/null || return 1
        sleep 0.02
        i=$((i + 1))
    done
    return 1
}
# After a run that ended normally: the output must be the complete new mesh.
check_complete() {
    line=$(grep '^frame ' "$T/out") || { cat "$T/out" "$T/err"; fail "no frame line"; }
    t=$(echo "$line" | sed -n 's/.* \([0-9][0-9]*\) triangles.*/\1/p')
    [ "$(grep -c '^f ' "$T/big.obj")" = "$t" ] || fail "big.obj is not the complete mesh"
    "$J" convert "$S/jet_099.csv" -r 0.025 -q -o "$T/big.obj" || fail "restore"
}

# 1. SIGTERM while the output is being written
start_big
if await_temp; then
    kill -TERM "$pid"
    wait "$pid"
    st=$?
    pid=""
    if [ "$st" = 143 ]; then
        [ -z "$(temps "$T")" ] || fail "SIGTERM left a temporary: $(temps "$T")"
        old_or_new || fail "SIGTERM during the write left big.obj neither the old file nor the new mesh"
        echo "ok: SIGTERM while writing: exit 143, no temporary, output old or complete"
    else
        [ "$st" = 0 ] || { cat "$T/err"; fail "exit $st after SIGTERM"; }
        check_complete
        echo "note: the conversion finished before SIGTERM landed; output complete"
    fi
else
    wait "$pid"
    pid=""
    check_complete
    echo "note: no write stage seen (too fast); output complete"
fi

# 2. SIGHUP while meshing (before any output is opened)
start_big
sleep 0.2
if [ -z "$(temps "$T")" ] && kill -HUP "$pid" 2>/dev/null; then
    wait "$pid"
    st=$?
    pid=""
    [ "$st" = 129 ] || [ "$st" = 0 ] || fail "exit $st after SIGHUP"
    [ -z "$(temps "$T")" ] || fail "SIGHUP left a temporary: $(temps "$T")"
    if [ "$st" = 129 ]; then
        old_or_new || fail "SIGHUP left big.obj neither the old file nor the new mesh"
        echo "ok: SIGHUP while meshing: exit 129, output old or complete"
    fi
else
    wait "$pid"
    pid=""
fi
[ -z "$(temps "$T")" ] || fail "temporary left: $(temps "$T")"
old_or_new || fail "big.obj is neither the old file nor the new mesh"
cp "$T/good.obj" "$T/big.obj"

# 3. SIGKILL while writing: no cleanup possible, but the target is the
#    previous good file, and the leftover is a hidden temporary that never
#    takes the target's name
start_big
if await_temp; then
    kill -KILL "$pid"
    wait "$pid"
    st=$?
    pid=""
    if [ "$st" = 137 ]; then
        old_or_new || fail "SIGKILL during the write left big.obj neither the old file nor the new mesh"
        left=$(temps "$T" | wc -l)
        for f in $(temps "$T"); do
            case "$f" in .big.obj.jetmesh-tmp-*-*-*) ;; *) fail "unexpected leftover $f" ;; esac
        done
        # the next run writing big.obj removes what the dead process left
        "$J" convert "$S/jet_099.csv" -r 0.025 -o "$T/big.obj" >"$T/out" 2>"$T/err" || fail "convert after SIGKILL"
        [ -z "$(temps "$T")" ] || fail "the leftover of the killed run is still there: $(temps "$T")"
        if [ "$left" = 1 ]; then
            grep -q 'removed 1 temporary left by an interrupted run' "$T/out" || fail "no note of the removed temporary"
        fi
        echo "ok: SIGKILL while writing: output old or complete, leftover hidden, removed by the next run"
    else
        check_complete
    fi
else
    wait "$pid"
    pid=""
    check_complete
fi

# 4. a sequence killed with SIGKILL, then --resume: every output that exists
#    is complete, and the resumed run gives exactly the uninterrupted result
"$J" convert "$S/jet_{}.csv" --frames 60:99 -r 0.025 -q -o "$T/ref/" --format ply || fail "reference run"
"$J" convert "$S/jet_{}.csv" --frames 60:99 -r 0.025 -o "$T/seq/" --format ply >"$T/out" 2>"$T/err" &
pid=$!
i=0
while [ $i -lt 1000 ] && [ "$(ls "$T/seq" 2>/dev/null | wc -l)" -lt 5 ] && kill -0 "$pid" 2>/dev/null; do
    sleep 0.01
    i=$((i + 1))
done
kill -KILL "$pid" 2>/dev/null
wait "$pid"
pid=""
n=$(ls "$T/seq" | wc -l)
for f in $(ls "$T/seq"); do
    cmp -s "$T/seq/$f" "$T/ref/$f" || fail "killed run left an incomplete $f"
done
"$J" convert "$S/jet_{}.csv" --frames 60:99 -r 0.025 -o "$T/seq/" --format ply --resume >"$T/out" 2>"$T/err" ||
    { cat "$T/err"; fail "--resume after SIGKILL"; }
[ "$(grep -c 'skipped' "$T/out")" -ge "$n" ] || fail "--resume did not skip the $n complete outputs"
[ -z "$(temps "$T/seq")" ] || fail "--resume left the killed run's temporaries: $(temps "$T/seq")"
[ "$(ls "$T/seq" | wc -l)" = 40 ] || fail "expected 40 outputs after --resume"
for f in $(ls "$T/ref"); do
    cmp -s "$T/seq/$f" "$T/ref/$f" || fail "$f differs from the uninterrupted run"
done
echo "ok: SIGKILL mid-sequence ($n of 40 done), --resume completes it identically"

# 5. SIGTERM mid-sequence: exit 143, no temporary, finished outputs complete
rm -rf "$T/seq"
"$J" convert "$S/jet_{}.csv" --frames 60:99 -r 0.025 -o "$T/seq/" --format ply >"$T/out" 2>"$T/err" &
pid=$!
i=0
while [ $i -lt 1000 ] && [ "$(ls "$T/seq" 2>/dev/null | wc -l)" -lt 3 ] && kill -0 "$pid" 2>/dev/null; do
    sleep 0.01
    i=$((i + 1))
done
kill -TERM "$pid" 2>/dev/null
wait "$pid"
st=$?
pid=""
[ "$st" = 143 ] || [ "$st" = 0 ] || fail "exit $st after SIGTERM"
[ -z "$(temps "$T/seq")" ] || fail "SIGTERM left a temporary: $(temps "$T/seq")"
for f in $(ls "$T/seq"); do cmp -s "$T/seq/$f" "$T/ref/$f" || fail "incomplete $f after SIGTERM"; done
echo "ok: SIGTERM mid-sequence (exit $st): $(ls "$T/seq" | wc -l) complete outputs, no temporary"
# 6. only leftovers of dead processes on this host beside this run's outputs
#    are removed: not a live process's (this shell's), not another file's,
#    not another host's (a shared file system: its pid means nothing here);
#    the older names without a host count as this host's
mkdir "$T/left"
sh -c 'exit 0' &
dead=$!
wait "$dead"
host=$(uname -n | cut -c1-64 | tr -c 'A-Za-z0-9._\n-' '_')
touch "$T/left/.m.glb.jetmesh-tmp-$dead" "$T/left/.m.glb.jetmesh-tmp-$$" "$T/left/.other.glb.jetmesh-tmp-$dead"
touch "$T/left/.n.bin.jetmesh-tmp-$dead"
touch "$T/left/.m.glb.jetmesh-tmp-$host-$dead-0123abcd" "$T/left/.m.glb.jetmesh-tmp-$host-$$-0123abcd"
touch "$T/left/.m.glb.jetmesh-tmp-other-node.$host-$dead-0123abcd"
"$J" convert "$S/jet_099.csv" -r 0.025 -o "$T/left/m.glb" >"$T/out" || fail "convert beside leftovers"
grep -q 'removed 2 temporaries left by an interrupted run' "$T/out" || { cat "$T/out"; fail "expected 2 removed"; }
"$J" convert "$S/jet_099.csv" -r 0.025 -q -o "$T/left/n.gltf" || fail "convert beside leftovers"
[ ! -e "$T/left/.m.glb.jetmesh-tmp-$dead" ] || fail "a dead run's temporary of m.glb was kept"
[ ! -e "$T/left/.m.glb.jetmesh-tmp-$host-$dead-0123abcd" ] || fail "a dead run's temporary (with host) was kept"
[ ! -e "$T/left/.n.bin.jetmesh-tmp-$dead" ] || fail "a dead run's temporary of the .bin of n.gltf was kept"
[ -e "$T/left/.m.glb.jetmesh-tmp-$$" ] || fail "a live process's temporary was removed"
[ -e "$T/left/.m.glb.jetmesh-tmp-$host-$$-0123abcd" ] || fail "a live process's temporary (with host) was removed"
[ -e "$T/left/.m.glb.jetmesh-tmp-other-node.$host-$dead-0123abcd" ] || fail "another host's temporary was removed"
[ -e "$T/left/.other.glb.jetmesh-tmp-$dead" ] || fail "the temporary of another output was removed"
echo "ok: leftovers of dead runs on this host beside the outputs removed, others kept"
echo "all kill checks passed"

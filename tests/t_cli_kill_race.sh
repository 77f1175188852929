#!/bin/sh
# t_cli_kill_race.sh - SIGTERM/SIGINT/SIGHUP at any moment of a sequence, frames 1, 2 and 4 at once, both cores loaded: no temporary, no incomplete output.
#
# Each run converts 40 jet frames (with --stats) and is signalled after a
# delay that sweeps the whole run: before the first output, while frames
# are meshed ahead, while they are written, renamed, and after the end.
# Afterwards the directory must hold no temporary, and every output in it
# must be byte-identical to an uninterrupted run's; the exit status must be
# the signal's (128+N) or 0 when the run finished first.
# Env: KILL_ROUNDS (default 1) rounds of the 9 cases (3 signals x 3
# frame-jobs settings); `make kill-soak` runs 24 rounds (216 kills).
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
B=${JETMESH_BUILD:-$ROOT/build}
SD="$B/tools/sigdefault"
[ -x "$SD" ] || fail "$SD is missing: run make tests-build"
ROUNDS=${KILL_ROUNDS:-1}
T=$(mktemp -d "${TMPDIR:-/tmp}/jetmesh-killrace.XXXXXX") || exit 1
pid=""
load=""
cleanup() {
    [ -n "$pid" ] && kill -KILL "$pid" 2>/dev/null
    for l in $load; do kill "$l" 2>/dev/null; done
    rm -rf "$T"
}
trap cleanup EXIT
trap 'exit 1' INT TERM

# the reference: the uninterrupted run (a finer lattice: each frame takes a
# few ms, so the run lasts long enough for a signal to land anywhere in it)
ARGS="--frames 60:99 -r 0.025 -c 0.3 --format ply"
# shellcheck disable=SC2086
"$J" convert "$S/jet_{}.csv" $ARGS -q -o "$T/ref/" || fail "reference run"
[ "$(ls "$T/ref" | wc -l)" = 40 ] || fail "reference run: expected 40 outputs"
start=$(date +%s%N)
# shellcheck disable=SC2086
"$J" convert "$S/jet_{}.csv" $ARGS -q -o "$T/timing/" || fail "timing run"
span_ms=$(( ($(date +%s%N) - start) / 1000000 ))

# both cores busy, as on a shared CI machine
for _ in 1 2; do
    sh -c 'while :; do :; done' &
    load="$load $!"
done

runs=0
killed=0
r=0
while [ $r -lt "$ROUNDS" ]; do
    for sig in TERM INT HUP; do
        case $sig in TERM) want=143 ;; INT) want=130 ;; HUP) want=129 ;; esac
        for fj in 1 2 4; do
            runs=$((runs + 1))
            # a delay sweeping 0 .. 1.5x the unloaded run, different every run
            d=$(( (runs * 7919 + r * 104729) % (span_ms * 3 / 2 + 1) ))
            out="$T/run$runs"
            # shellcheck disable=SC2086
            "$SD" "$J" convert "$S/jet_{}.csv" $ARGS --frame-jobs $fj -j 2 \
                --stats "$out/stats.csv" -o "$out/" >"$T/out" 2>"$T/err" &
            pid=$!
            sleep "$(printf '%d.%03d' $((d / 1000)) $((d % 1000)))"
            kill -$sig "$pid" 2>/dev/null
            wait "$pid"
            st=$?
            pid=""
            if [ "$st" = "$want" ]; then
                killed=$((killed + 1))
            elif [ "$st" != 0 ]; then
                cat "$T/err"
                fail "SIG$sig, --frame-jobs $fj, after $d ms: exit $st (want $want or 0)"
            fi
            if [ -d "$out" ]; then
                left=$(ls -A "$out" | grep 'jetmesh-tmp' || true)
                [ -z "$left" ] || fail "SIG$sig, --frame-jobs $fj, after $d ms: temporary left: $left"
                for f in $(ls "$out"); do
                    [ "$f" = stats.csv ] && continue
                    cmp -s "$out/$f" "$T/ref/$f" ||
                        fail "SIG$sig, --frame-jobs $fj, after $d ms: incomplete or wrong $f"
                done
                if [ "$st" = 0 ]; then
                    [ "$(ls "$out" | grep -c '\.ply$')" = 40 ] || fail "exit 0 without all 40 outputs"
                    [ -s "$out/stats.csv" ] || fail "exit 0 without the statistics"
                fi
            fi
            rm -rf "$out"
        done
    done
    r=$((r + 1))
done
# a test that signals nothing tests nothing
[ "$killed" -gt 0 ] || fail "none of the $runs runs was still going when signalled"
echo "ok: $runs runs signalled (SIGTERM/SIGINT/SIGHUP x --frame-jobs 1/2/4, cores loaded), $killed died by the signal, the others had finished: no temporary, no incomplete output"

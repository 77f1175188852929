#!/bin/sh
# t_parallel.sh - the GNU parallel recipes (local cores, --sshlogin): 4 shards at once give one run's bytes; merged stats hold every frame once.
# shellcheck source=tests/lib.sh
. "$(dirname "$0")/lib.sh"
# No skip: make check installs parallel (scripts/deps.sh) when run as root.
command -v parallel >/dev/null 2>&1 ||
    fail "GNU parallel is not installed: this test cannot run (apt-get install -y parallel, or run make check as root)"
scratch parallel
export HOME="$T/home" # parallel keeps its state under ~/.parallel: keep it here
mkdir -p "$HOME" "$T/work"
cd "$T/work" || exit 1
ln -s "$S" sim
PATH=$(dirname "$J"):$PATH # the recipes call jetmesh by name
export PATH

# the reference: one run
jetmesh convert 'sim/jet_%03d.csv' --frames 0:99 -r 0.025 -q -o 'ref/jet_%03d.glb' || fail "single run"

# check OUTDIR STATSDIR: byte-identical outputs, merged stats with every frame once
check() {
    diff -r ref "$1" >/dev/null || fail "$1: outputs differ from a single run's"
    [ "$(ls "$2" | wc -l)" = 4 ] || fail "$2: not 4 shard statistics files"
    jetmesh stats merge "$2"/shard_*.csv -o "$2/all.csv" --svg "$2/all.svg" >"$T/merge.out" 2>&1 ||
        { cat "$T/merge.out"; fail "$2: stats merge"; }
    grep -v '^#' "$2/all.csv" | tail -n +2 | cut -d, -f1 | cmp -s - "$T/seq" ||
        fail "$2: merged rows are not frames 0..99 once each, in order"
    grep -q '^# summary ok=100$' "$2/all.csv" || fail "$2: merged summary is not 100 ok"
    grep -q '^# summary shards=4$' "$2/all.csv" || fail "$2: merged summary is not 4 shards"
}
seq 0 99 >"$T/seq"

# recipe 1: the local cores, 4 shards at once (as in README "On a cluster")
parallel --will-cite -j 4 jetmesh convert 'sim/jet_%03d.csv' --frames 0:99 -r 0.025 --threads 1 -q \
    -o 'meshes/jet_%03d.glb' --resume --shard {}/4 --stats stats/shard_{}.csv ::: 0 1 2 3 </dev/null ||
    fail "parallel (local) failed"
check meshes stats

# recipe 2: --sshlogin. ssh is replaced by a stand-in that runs the command
# it is given here (dropping ssh's options and the host name, as a real
# login would on a shared filesystem), so parallel's remote quoting and
# --workdir are exercised for real. The stand-in sets SHELL as a login
# would: CI runs without one, and parallel's worker runs jobs with $SHELL.
cat >"$T/fakessh" <<EOS
#!/bin/sh
echo "\$*" >>"$T/ssh.log"
export SHELL=/bin/sh                  # a login sets it; parallel's remote worker runs the job with \$SHELL
while [ \$# -gt 0 ]; do case \$1 in -l|-p|-o|-i|-F) shift 2 ;; -*) shift ;; *) break ;; esac; done
shift                                 # the host
[ "\${1:-}" = -- ] && shift
exec sh -c "\$*"
EOS
chmod +x "$T/fakessh"
parallel --will-cite --ssh "$T/fakessh" --sshlogin 2/node1,2/node2 --workdir "$PWD" \
    jetmesh convert 'sim/jet_%03d.csv' --frames 0:99 -r 0.025 --threads 1 -q \
    -o 'remote/jet_%03d.glb' --resume --shard {}/4 --stats rstats/shard_{}.csv ::: 0 1 2 3 </dev/null ||
    fail "parallel (--sshlogin) failed"
grep -q '^node1 ' "$T/ssh.log" && grep -q '^node2 ' "$T/ssh.log" || { cat "$T/ssh.log"; fail "not both logins used"; }
check remote rstats

# --resume across shards: a second pass converts nothing
parallel --will-cite -j 4 jetmesh convert 'sim/jet_%03d.csv' --frames 0:99 -r 0.025 --threads 1 -q \
    -o 'meshes/jet_%03d.glb' --resume --shard {}/4 --stats again/shard_{}.csv ::: 0 1 2 3 </dev/null ||
    fail "parallel (resume) failed"
jetmesh stats merge again/shard_*.csv -o again/all.csv -q || fail "merge of the resumed pass"
grep -q '^# summary skipped=100$' again/all.csv || fail "the resumed pass converted frames again"
echo "ok"

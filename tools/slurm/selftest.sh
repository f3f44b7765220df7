#!/usr/bin/env bash
# Proves deploy/slurm/ on a real single-node Slurm (tools/slurm/local_cluster.sh) with the real
# filterbench binary (issue 19):
#   1. start the cluster;
#   2. deploy/slurm/submit.sh kalman_baseline $SHARDS OUT --trials 500 --per-trial: every array task
#      and the merge must complete, and OUT/merged must hold the tables of a one-machine run of the
#      same experiment bit for bit (timing columns aside), compared by the test crate's own check
#      (tests/it/shards.rs, `slurm_result_equals_one_run`);
#   3. the same with an option every shard refuses (--trials 1): the shards fail and the merge must
#      be cancelled, never run;
#   4. stop the cluster, also when a step fails (trap).
# The binary: FILTERBENCH, else target/release/filterbench of this repository (CARGO_TARGET_DIR
# honoured), built first with `cargo build --release` if missing.
# Prints the jobs' output and how long each step took; exits 0 only if every check passed.
set -euo pipefail

here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)
repo=$(cd "$here/../.." && pwd)
cluster=$here/local_cluster.sh
SHARDS=${SHARDS:-3}
TIMEOUT=${SELFTEST_TIMEOUT:-120}

fail() { echo "selftest: FAIL: $*" >&2; exit 1; }
now() { date +%s.%N; }
since() { awk -v a="$1" -v b="$(now)" 'BEGIN { printf "%.1f", b - a }'; }

target=${CARGO_TARGET_DIR:-$repo/target}
case "$target" in /*) ;; *) target=$repo/$target ;; esac
if [ -z "${FILTERBENCH:-}" ]; then
  FILTERBENCH=$target/release/filterbench
  [ -x "$FILTERBENCH" ] || (cd "$repo" && cargo build --release --quiet) || fail "cargo build --release failed"
fi
[ -x "$FILTERBENCH" ] || fail "no filterbench binary at $FILTERBENCH"
export FILTERBENCH
TRIALS=${SELFTEST_TRIALS:-500}
work=$(mktemp -d /tmp/filterbench-selftest.XXXXXX)
finish() {
  local rc=$?
  local t
  t=$(now)
  "$cluster" stop || rc=1
  echo "selftest: stop took $(since "$t")s"
  if [ $rc -eq 0 ]; then
    rm -rf "$work"
    echo "selftest: PASS"
  else
    echo "selftest: FAIL (exit $rc); job outputs kept in $work, cluster logs in ${FB_SLURM_DIR:-/tmp/filterbench-slurm}/log" >&2
  fi
  exit $rc
}
trap finish EXIT
trap 'exit 130' INT TERM

t=$(now)
"$cluster" start
echo "selftest: start took $(since "$t")s"
eval "$("$cluster" env)"
export SLURM_CONF

# Waits until none of the given jobs (array tasks expanded) is pending, running or completing, and
# prints each job's final "id state reason". Records of finished jobs stay visible to squeue for
# MinJobAge (60 s): without accounting there is no sacct to ask afterwards.
wait_jobs() {
  local deadline=$((SECONDS + TIMEOUT)) lines
  while :; do
    lines=$(squeue -h -r -t all -j "$1" -o '%i %T %r') || fail "squeue -j $1 failed"
    [ -n "$lines" ] || fail "squeue knows none of jobs $1"
    if ! grep -qE ' (PENDING|RUNNING|COMPLETING|CONFIGURING|SUSPENDED|REQUEUED|RESIZING)( |$)' <<<"$lines"; then
      echo "$lines"
      return 0
    fi
    [ $SECONDS -lt $deadline ] || { echo "$lines" >&2; fail "jobs $1 not finished after ${TIMEOUT}s"; }
    sleep 0.5
  done
}

ids() { sed -n "s/^$1 job \([0-9]*\)$/\1/p" <<<"$2"; }

show_logs() {
  local f
  for f in "$1"/logs/*.out; do
    [ -e "$f" ] || continue
    echo "--- ${f#"$1"/}"
    cat "$f"
  done
}

# --- 1. a whole run, compared with one machine ---
t=$(now)
(cd "$repo" && "$FILTERBENCH" experiment kalman_baseline --trials "$TRIALS" --per-trial --quiet --out "$work/one") ||
  fail "the one-machine run failed"
echo "selftest: one-machine run took $(since "$t")s"
out=$work/ok
t=$(now)
ids_text=$(cd "$repo" && deploy/slurm/submit.sh kalman_baseline "$SHARDS" "$out" --trials "$TRIALS" --per-trial) ||
  fail "submit.sh failed"
echo "$ids_text"
array=$(ids array "$ids_text") merge=$(ids merge "$ids_text")
[ -n "$array" ] && [ -n "$merge" ] || fail "submit.sh did not print both job ids"
states=$(wait_jobs "$array,$merge")
echo "selftest: submit to merged took $(since "$t")s"
echo "$states" | sed 's/^/  /'
show_logs "$out"
[ "$(grep -c " COMPLETED " <<<"$states")" -eq $((SHARDS + 1)) ] ||
  fail "expected $SHARDS array tasks and the merge COMPLETED"
for ((i = 0; i < SHARDS; i++)); do
  [ -f "$out/shard-$i/partial.json" ] || fail "shard $i wrote no partial result"
  grep -q "\"shard\": $i," "$out/shard-$i/partial.json" || fail "shard-$i is not shard $i"
  grep -q "\"shards\": $SHARDS," "$out/shard-$i/partial.json" || fail "shard-$i does not know N = $SHARDS"
done
[ -f "$out/merged/manifest.json" ] || fail "no merged result in $out/merged"
t=$(now)
(cd "$repo" && FB_ONE=$work/one FB_MERGED=$out/merged cargo test --release --quiet --test it -- --ignored --exact \
  shards::slurm_result_equals_one_run) || fail "the merged tables differ from the one-machine run"
echo "selftest: comparison took $(since "$t")s"
echo "selftest: ok: $SHARDS shards on Slurm, merged = one-machine run bit for bit (every table, timings aside)"

# --- 2. failed shards must cancel the merge ---
out=$work/failing
t=$(now)
ids_text=$(cd "$repo" && deploy/slurm/submit.sh kalman_baseline "$SHARDS" "$out" --trials 1) || fail "submit.sh failed"
echo "$ids_text"
array=$(ids array "$ids_text") merge=$(ids merge "$ids_text")
states=$(wait_jobs "$array,$merge")
echo "selftest: submit to settled took $(since "$t")s"
echo "$states" | sed 's/^/  /'
show_logs "$out"
grep -qE "^${array}_1 FAILED " <<<"$states" || fail "shard 1 did not end FAILED"
grep -qE "^$merge CANCELLED " <<<"$states" || fail "the merge job did not end CANCELLED"
[ ! -e "$out/merged" ] || fail "the merge ran although the shards failed"
[ ! -e "$out/logs/merge.out" ] || fail "the merge job wrote a log although the shards failed"
echo "selftest: ok: the shards failed (--trials 1), the merge was cancelled without running"

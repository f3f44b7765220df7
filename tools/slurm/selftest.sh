#!/usr/bin/env bash
# Proves deploy/slurm/ on a real single-node Slurm (tools/slurm/local_cluster.sh), with
# tools/slurm/standin-filterbench.sh in place of the filterbench binary (issue 19):
#   1. start the cluster;
#   2. deploy/slurm/submit.sh kalman_baseline $SHARDS OUT --seed 7: every array task must see its own
#      index, the shard count and the option, the merge must start only after all of them and see
#      every shard;
#   3. the same with one shard failing on purpose: the merge must be cancelled, never run;
#   4. stop the cluster, also when a step fails (trap).
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

# --- 1. a whole run ---
out=$work/ok
t=$(now)
ids_text=$(FILTERBENCH=$here/standin-filterbench.sh "$repo/deploy/slurm/submit.sh" kalman_baseline "$SHARDS" "$out" \
  --seed 7) ||
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
expected=$(for ((i = 0; i < SHARDS; i++)); do echo "kalman_baseline $i $SHARDS --seed 7"; done)
[ -f "$out/merged/merged.txt" ] || fail "no $out/merged/merged.txt"
[ "$(cat "$out/merged/merged.txt")" = "$expected" ] ||
  fail "merged output is not shards 0..$((SHARDS - 1)) of $SHARDS: $(tr '\n' '|' <"$out/merged/merged.txt")"
# The merge ran after every shard had finished (the stand-in's merge also refuses a missing shard).
for ((i = 0; i < SHARDS; i++)); do
  [ ! "$out/shard-$i/shard.txt" -nt "$out/merged/merged.txt" ] || fail "shard $i was written after the merge"
done
echo "selftest: ok: $SHARDS shards saw indices 0..$((SHARDS - 1)) of $SHARDS and --seed 7; the merge got all of them"

# --- 2. a failed shard must cancel the merge ---
out=$work/failing
t=$(now)
ids_text=$(STANDIN_FAIL_SHARD=1 FILTERBENCH=$here/standin-filterbench.sh \
  "$repo/deploy/slurm/submit.sh" kalman_baseline "$SHARDS" "$out") || fail "submit.sh failed"
echo "$ids_text"
array=$(ids array "$ids_text") merge=$(ids merge "$ids_text")
states=$(wait_jobs "$array,$merge")
echo "selftest: submit to settled took $(since "$t")s"
echo "$states" | sed 's/^/  /'
show_logs "$out"
grep -qE "^${array}_1 FAILED " <<<"$states" || fail "shard 1 did not end FAILED"
grep -qE "^$merge CANCELLED " <<<"$states" || fail "the merge job did not end CANCELLED"
[ ! -e "$out/merged" ] || fail "the merge ran although shard 1 failed"
[ ! -e "$out/logs/merge.out" ] || fail "the merge job wrote a log although shard 1 failed"
echo "selftest: ok: shard 1 failed, the merge was cancelled without running"

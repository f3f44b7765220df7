#!/usr/bin/env bash
# Runs a filterbench experiment as N shards on a Slurm job array, then merges them (issue 19).
#
#   deploy/slurm/submit.sh EXPERIMENT N OUT [filterbench experiment options…]
#   e.g. deploy/slurm/submit.sh aniso_dropout 16 /scratch/$USER/aniso --trials 10000000
#
# Submits filterbench-array.sbatch as --array=0-{N-1} (shard I writes OUT/shard-I), then
# filterbench-merge.sbatch with --dependency=afterok:<array job> (writes OUT/merged), and prints
#   array job <id>
#   merge job <id>
# OUT must be on a file system every node sees, and new or empty: nothing in it is overwritten.
# Job logs go to OUT/logs/. The jobs run in the current folder, where `experiments/NAME.toml` is
# looked up (submit from the repository, or give a TOML path). If a shard fails the merge job is
# cancelled rather than left pending.
#
# FILTERBENCH  the filterbench binary (default: filterbench on PATH, else target/release/filterbench
#              of this repository); it must be reachable at that path from every node.
# Anything else about the jobs is plain sbatch: SBATCH_PARTITION, SBATCH_ACCOUNT, SBATCH_TIMELIMIT…
# are read by sbatch itself, and `--cpus-per-task` defaults to 1 (SBATCH_CPUS_PER_TASK is not an
# sbatch input variable in 22.05; edit the #SBATCH line or pass the option in SUBMIT_SBATCH_ARGS).
set -euo pipefail

die() { echo "submit: $*" >&2; exit 2; }

[ $# -ge 3 ] || die "usage: $0 EXPERIMENT N OUT [filterbench experiment options…]"
experiment=$1 n=$2 out=$3
shift 3
here=$(cd "$(dirname "${BASH_SOURCE[0]}")" && pwd)

case "$n" in '' | *[!0-9]* | 0*) die "N must be a whole number ≥ 1, not '$n'" ;; esac
command -v sbatch >/dev/null || die "sbatch is not on PATH (is this a Slurm login node?)"

if [ -z "${FILTERBENCH:-}" ]; then
  FILTERBENCH=$(command -v filterbench || true)
  [ -n "$FILTERBENCH" ] || FILTERBENCH=$(cd "$here/../.." && pwd)/target/release/filterbench
fi
[ -x "$FILTERBENCH" ] || die "filterbench binary $FILTERBENCH is not an executable file (set FILTERBENCH)"
FILTERBENCH=$(cd "$(dirname "$FILTERBENCH")" && pwd)/$(basename "$FILTERBENCH")

if [ -e "$out" ]; then
  [ -d "$out" ] || die "output $out exists and is not a folder"
  [ -z "$(ls -A "$out")" ] || die "output folder $out is not empty (choose a new one; nothing is overwritten)"
fi
mkdir -p "$out/logs" || die "cannot create $out/logs"
out=$(cd "$out" && pwd)

export EXPERIMENT=$experiment OUT=$out FILTERBENCH
# The array is whole (0..N-1), so each task reads N from SLURM_ARRAY_TASK_COUNT; a SHARDS left in the
# caller's environment (from re-running single shards by hand) must not override it.
unset SHARDS
# Extra sbatch options for both jobs (word-split on purpose: "--partition=long --qos=low").
# shellcheck disable=SC2206
extra=(${SUBMIT_SBATCH_ARGS:-})

array=$(sbatch --parsable "${extra[@]}" --array="0-$((n - 1))" \
  --output="$out/logs/shard-%a.out" "$here/filterbench-array.sbatch" "$@") ||
  die "sbatch of the array failed"
array=${array%%;*}
merge=$(sbatch --parsable "${extra[@]}" --dependency="afterok:$array" --kill-on-invalid-dep=yes \
  --output="$out/logs/merge.out" "$here/filterbench-merge.sbatch") || {
  scancel "$array" 2>/dev/null || true
  die "sbatch of the merge failed; array job $array cancelled"
}
merge=${merge%%;*}
echo "array job $array"
echo "merge job $merge"

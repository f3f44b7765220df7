#!/usr/bin/env bash
# STAND-IN for the filterbench binary, used ONLY by tools/slurm/selftest.sh to exercise the Slurm
# mechanics of deploy/slurm/ (array indices, shard count, dependency, merge over every shard) before
# `filterbench experiment --shard` and `filterbench merge` exist (issue 19). It computes nothing.
#
#   standin-filterbench.sh experiment NAME --shard I/N --out D [--threads T] [--quiet]
#                          [--trials T] [--seed S]
#       writes D/shard.txt: "NAME I N", then "--trials T" / "--seed S" if given (so the selftest sees
#       options passed through submit.sh); fails (exit 3) if STANDIN_FAIL_SHARD=I, so the selftest can
#       check that a failed shard cancels the merge
#   standin-filterbench.sh merge --out D SHARD_DIR…
#       checks the shards are N distinct indices 0..N-1 of one experiment and one N, and writes
#       D/merged.txt: their shard.txt lines in index order
# Errors: one line on stderr, exit 2 (as filterbench does).
set -euo pipefail

fail() { echo "standin-filterbench: $*" >&2; exit 2; }

cmd=${1:-}
shift || true
case "$cmd" in
  experiment)
    [ $# -ge 1 ] || fail "experiment: missing NAME"
    name=$1
    shift
    shard='' out='' extra=''
    while [ $# -gt 0 ]; do
      case "$1" in
        --shard) shard=${2:-}; shift 2 || fail "--shard needs I/N" ;;
        --out) out=${2:-}; shift 2 || fail "--out needs a folder" ;;
        --threads) [ -n "${2:-}" ] || fail "--threads needs a number"; shift 2 ;;
        --quiet) shift ;;
        --trials | --seed) [ -n "${2:-}" ] || fail "$1 needs a value"; extra+=" $1 $2"; shift 2 ;;
        *) fail "experiment: unexpected argument '$1'" ;;
      esac
    done
    [[ "$shard" =~ ^([0-9]+)/([0-9]+)$ ]] || fail "--shard '$shard' is not I/N"
    i=${BASH_REMATCH[1]} n=${BASH_REMATCH[2]}
    [ "$n" -ge 1 ] && [ "$i" -lt "$n" ] || fail "--shard $i/$n: need 0 ≤ I < N"
    [ -n "$out" ] || fail "experiment: missing --out"
    if [ "${STANDIN_FAIL_SHARD:-}" = "$i" ]; then
      echo "standin-filterbench: shard $i fails on purpose (STANDIN_FAIL_SHARD)" >&2
      exit 3
    fi
    mkdir -p "$out"
    echo "$name $i $n$extra" >"$out/shard.txt"
    echo "standin-filterbench: wrote $out/shard.txt ($name $i $n$extra)"
    ;;
  merge)
    [ "${1:-}" = --out ] && [ -n "${2:-}" ] || fail "merge: usage: merge --out D SHARD_DIR…"
    out=$2
    shift 2
    [ $# -ge 1 ] || fail "merge: no shard folders given"
    declare -A seen=()
    name='' n=''
    for d in "$@"; do
      [ -s "$d/shard.txt" ] || fail "merge: $d/shard.txt is missing"
      read -r s_name s_i s_n _ <"$d/shard.txt"
      [ -z "$name" ] && name=$s_name n=$s_n
      [ "$s_name" = "$name" ] || fail "merge: $d is of experiment $s_name, not $name"
      [ "$s_n" = "$n" ] || fail "merge: $d is shard $s_i of $s_n, the others are of $n"
      [ -z "${seen[$s_i]:-}" ] || fail "merge: shard $s_i given twice ($d and ${seen[$s_i]})"
      seen[$s_i]=$d
    done
    missing=()
    for ((i = 0; i < n; i++)); do [ -n "${seen[$i]:-}" ] || missing+=("$i"); done
    [ ${#missing[@]} -eq 0 ] || fail "merge: shard(s) ${missing[*]} of $n missing"
    mkdir -p "$out"
    for ((i = 0; i < n; i++)); do cat "${seen[$i]}/shard.txt"; done >"$out/merged.txt"
    echo "standin-filterbench: merged $n shards of $name into $out/merged.txt"
    ;;
  *) fail "unknown command '$cmd' (this stand-in knows experiment and merge)" ;;
esac

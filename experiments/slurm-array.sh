#!/usr/bin/env bash
# Run an experiment as a Slurm job array, one shard per array task, then merge the shards.
#
#   sbatch --array=1-16 experiments/slurm-array.sh experiments/default.toml 16
#
# Arguments: the experiment file and N, the number of shards. Give N explicitly (it is the size
# of the first submission's array): a resubmitted task cannot learn it from Slurm. Task I runs
# `magbench bench FILE --shard I/N --resume` into results/<name>-shard-I-of-N.
#
# The lowest task of each submission also submits a merge job (this script with a third
# argument, `merge`). It waits for every task of that submission (afterany) and for earlier
# merges of the same experiment (singleton), then joins the shard folders that exist into
# results/<name>/, replacing an earlier merge; it warns about missing runs.
#
# A task that was cancelled, preempted or timed out: resubmit it with the same arguments,
#
#   sbatch --array=3 experiments/slurm-array.sh experiments/default.toml 16
#
# and it runs only its missing runs (--resume), then merges again. To merge by hand:
#   sbatch experiments/slurm-array.sh experiments/default.toml 16 merge   (or run it with bash)
#
# MAGBENCH (default target/release/magbench) is the binary; MAGBENCH_ARGS adds options to each
# task's `magbench bench`. Build once before submitting (`cargo build --release -p magbench`),
# so that tasks do not race to compile. Adjust the #SBATCH lines to your cluster; the task uses
# --cpus-per-task worker threads. Paths are relative to the folder you submit from.
#SBATCH --job-name=magbench
#SBATCH --cpus-per-task=4
#SBATCH --time=02:00:00
#SBATCH --output=magbench-%A_%a.out
set -euo pipefail

# Inside a job, $0 is Slurm's copy of the script: messages name the script as documented.
SELF="experiments/slurm-array.sh"
USAGE="usage: sbatch --array=1-N $SELF EXPERIMENT.toml N  (or: $SELF EXPERIMENT.toml N merge)"
bad() {
  echo "slurm-array.sh: $*; $USAGE" >&2
  exit 2
}
if [ $# -lt 2 ] || [ $# -gt 3 ]; then bad "expected 2 or 3 arguments, got $#"; fi
FILE="$1"
N="$2"
MODE="${3:-task}"
cd "${SLURM_SUBMIT_DIR:-.}"
MAGBENCH="${MAGBENCH:-target/release/magbench}"
case "$N" in
'' | *[!0-9]* | 0*) bad "N: \"$N\" is not a number of shards (1 or more)" ;;
esac
[ -f "$FILE" ] || bad "$FILE: no such experiment file (paths are relative to $PWD)"
NAME="$(sed -n 's/^name *= *"\(.*\)".*/\1/p' "$FILE" | head -n1)"
NAME="${NAME:-$(basename "$FILE" .toml)}"
shard_dir() { echo "results/${NAME}-shard-$1-of-${N}"; }

# Joins the shard folders that exist into results/<name>/ (via a new folder, then a swap).
merge() {
  local dirs=() missing=() k
  for k in $(seq 1 "$N"); do
    if [ -f "$(shard_dir "$k")/manifest.json" ]; then
      dirs+=("$(shard_dir "$k")")
    else
      missing+=("$k")
    fi
  done
  if [ "${#dirs[@]}" -eq 0 ]; then
    echo "slurm-array.sh: no shard of $NAME has started (results/${NAME}-shard-*-of-${N}): nothing to merge" >&2
    exit 1
  fi
  if [ "${#missing[@]}" -gt 0 ]; then
    echo "warning: shards ${missing[*]} of $N have not started; resubmit them: sbatch --array=$(
      IFS=,
      echo "${missing[*]}"
    ) $SELF $FILE $N" >&2
  fi
  local out="results/$NAME" new="results/.${NAME}-merge-${SLURM_JOB_ID:-$$}"
  if [ -e "$out" ] && ! tr -d ' \n' <"$out/manifest.json" 2>/dev/null | grep -q '"merged_from":\["'; then
    echo "slurm-array.sh: $out holds results that are not a merge of shards; move them away, then merge again: $SELF $FILE $N merge" >&2
    exit 2
  fi
  rm -rf "$new"
  "$MAGBENCH" merge "${dirs[@]}" --out "$new"
  rm -rf "$out.old"
  if [ -e "$out" ]; then mv "$out" "$out.old"; fi
  mv -T "$new" "$out"
  rm -rf "$out.old"
  echo "slurm-array.sh: the merge of ${#dirs[@]} of $N shards is in $out"
}

case "$MODE" in
merge)
  merge
  exit 0
  ;;
task) ;;
*) bad "\"$MODE\": unknown third argument (only \"merge\")" ;;
esac

I="${SLURM_ARRAY_TASK_ID:-}"
[ -n "$I" ] || bad "SLURM_ARRAY_TASK_ID is not set: submit this script as a job array"
case "$I" in
'' | *[!0-9]* | 0*) bad "array task $I is not a shard of 1-$N" ;;
esac
[ "$I" -le "$N" ] || bad "array task $I is not a shard of 1-$N"
OUT="$(shard_dir "$I")"

if [ "$I" = "${SLURM_ARRAY_TASK_MIN:-$I}" ]; then
  # The merge job is this script (Slurm's copy of it) in merge mode. It inherits this task's
  # environment, SLURM_ARRAY_* included, hence the explicit mode argument.
  if ! sbatch --dependency="afterany:${SLURM_ARRAY_JOB_ID},singleton" \
    --job-name="magbench-merge-${NAME}" --cpus-per-task=1 --output="magbench-merge-%j.out" \
    "$0" "$FILE" "$N" merge; then
    echo "warning: could not submit the merge job; when the tasks are done, run: $SELF $FILE $N merge" >&2
  fi
fi

RESUME=""
if [ -f "$OUT/manifest.json" ]; then RESUME="--resume"; fi
# shellcheck disable=SC2086 # MAGBENCH_ARGS: extra options, split on spaces
"$MAGBENCH" bench "$FILE" --shard "$I/$N" --out "$OUT" --threads "${SLURM_CPUS_PER_TASK:-1}" --lines $RESUME ${MAGBENCH_ARGS:-}

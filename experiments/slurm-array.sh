#!/usr/bin/env bash
# Run an experiment as a Slurm job array, one shard per array task, then merge the shards.
#
#   sbatch --array=1-16 experiments/slurm-array.sh experiments/default.toml
#
# Each task runs `magbench bench FILE --shard I/N` into results/<name>-shard-I-of-N, where I is
# the array task id and N the array size. A merge job, submitted by the first task with a
# dependency on the whole array, joins the shards into results/<name>/. A task that was
# preempted or timed out can be resubmitted as is: --resume runs only its missing runs.
#
# MAGBENCH (default target/release/magbench) is the binary; MAGBENCH_ARGS adds options.
# Build once before submitting (`cargo build --release -p magbench`), so that tasks do not race
# to compile. Adjust the #SBATCH lines to your cluster.
#SBATCH --job-name=magbench
#SBATCH --cpus-per-task=4
#SBATCH --time=02:00:00
#SBATCH --output=magbench-%A_%a.out
set -euo pipefail

FILE="${1:?usage: sbatch --array=1-N experiments/slurm-array.sh EXPERIMENT.toml}"
cd "${SLURM_SUBMIT_DIR:-.}"
MAGBENCH="${MAGBENCH:-target/release/magbench}"
I="${SLURM_ARRAY_TASK_ID:?run this script as a job array (sbatch --array=1-N)}"
N="${SLURM_ARRAY_TASK_COUNT:?}"
NAME="$(sed -n 's/^name *= *"\(.*\)".*/\1/p' "$FILE" | head -n1)"
NAME="${NAME:-$(basename "$FILE" .toml)}"
OUT="results/${NAME}-shard-${I}-of-${N}"

if [ "$I" = "${SLURM_ARRAY_TASK_MIN:-1}" ]; then
  # The merge waits for every task of this array (afterany: merge whatever finished).
  DIRS=""
  for k in $(seq 1 "$N"); do DIRS="$DIRS results/${NAME}-shard-${k}-of-${N}"; done
  sbatch --dependency="afterany:${SLURM_ARRAY_JOB_ID}" --job-name=magbench-merge \
    --output="magbench-merge-%j.out" --wrap="$MAGBENCH merge $DIRS --out results/${NAME}"
fi

RESUME=""
if [ -f "$OUT/manifest.json" ]; then RESUME="--resume"; fi
# shellcheck disable=SC2086 # MAGBENCH_ARGS: extra options, split on spaces
"$MAGBENCH" bench "$FILE" --shard "$I/$N" --out "$OUT" --threads "${SLURM_CPUS_PER_TASK:-1}" --lines $RESUME ${MAGBENCH_ARGS:-}

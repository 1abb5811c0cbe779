#!/usr/bin/env bash
# A bake spread over a Slurm cluster without Dask: one array task per shard, then the merge
# as a job that waits for every task (afterok). Each task reads its index from Slurm's
# environment (SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_COUNT). SHARD_DIR and OUT must be on a
# filesystem every node sees; the scene too.
#
#   SHARDS=16 SHARD_DIR=/shared/shards OUT=/shared/bake-out \
#     BAKE_ARGS="--scene /shared/world.glb --passes 4096 --device gpu" \
#     sbatch --array=0-15 docs/distributed/slurm-array.sh
#   sbatch --dependency=afterok:<array job id> --wrap \
#     "baker merge /shared/bake-out /shared/shards/shard-*-of-16.sbfshard"
#
# A task that fails (node lost, preempted) can be requeued (--requeue, or `scontrol
# requeue`): it resumes from its checkpoint and writes the same shard file.
#SBATCH --job-name=baker-shard
#SBATCH --gpus=1
#SBATCH --cpus-per-task=16
#SBATCH --time=04:00:00
#SBATCH --requeue
set -euo pipefail
: "${SHARD_DIR:?set SHARD_DIR (shared folder for shard files and checkpoints)}"
: "${SLURM_ARRAY_TASK_ID:?run as an array job: sbatch --array=0-(N-1)}"
SHARDS="${SHARDS:-${SLURM_ARRAY_TASK_COUNT:?set SHARDS or run as an array job}}"
BAKER="${BAKER:-baker}"
# BAKE_ARGS: the bake's arguments, the same for every task (split on spaces).
read -r -a args <<< "${BAKE_ARGS:-}"
exec "$BAKER" "${args[@]}" --shard "$SLURM_ARRAY_TASK_ID/$SHARDS" --out "$SHARD_DIR" \
  --resume --checkpoint-every "${CHECKPOINT_EVERY:-64}"

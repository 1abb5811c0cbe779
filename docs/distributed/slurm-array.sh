#!/usr/bin/env bash
# A bake spread over a Slurm cluster without Dask: one array task per shard, then the merge
# as a job that waits for every task (afterok). Each task reads its index from Slurm's
# environment (SLURM_ARRAY_TASK_ID, SLURM_ARRAY_TASK_COUNT). SHARD_DIR must be on a
# filesystem every node sees, the scene and the merge's output folder too.
#
#   SHARDS=16 SHARD_DIR=/shared/shards \
#     BAKE_ARGS="--scene /shared/world.glb --passes 4096 --device gpu" \
#     sbatch --array=0-15 docs/distributed/slurm-array.sh
#   sbatch --dependency=afterok:<array job id> --mem=<the merge's memory> --time=01:00:00 \
#     --wrap "baker merge /shared/bake-out /shared/shards/shard-*-of-16.sbfshard"
#
# (The merge holds the whole bake's state: give it the memory of a single-machine bake of
# the scene, docs/distributed.md.) A bake that exits with an error is run again up to
# RETRIES times (default 3) within the task, each time resuming from its checkpoint and
# writing the same shard file; a task whose node is lost or preempted is requeued
# (--requeue) and resumes the same way.
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
retries="${RETRIES:-3}"
# The GPU Slurm gave this task: GPU_DEVICE_ORDINAL, its index among the devices the task sees
# (0 where the cluster constrains devices), becomes baker's adapter index (SBF_GPU_INDEX, as
# --gpu-index). Vulkan ignores CUDA_VISIBLE_DEVICES: without this, every task on a multi-GPU
# node would bake on the same (the best) GPU.
if [ -n "${GPU_DEVICE_ORDINAL:-}" ] && [ -z "${SBF_GPU_INDEX:-}" ]; then
  export SBF_GPU_INDEX="${GPU_DEVICE_ORDINAL%%,*}"
fi
for ((attempt = 0; ; attempt++)); do
  if "$BAKER" "${args[@]}" --shard "$SLURM_ARRAY_TASK_ID/$SHARDS" --out "$SHARD_DIR" \
    --resume --checkpoint-every "${CHECKPOINT_EVERY:-64}"; then
    exit 0
  else
    status=$?
  fi
  if ((attempt >= retries)); then
    echo "shard $SLURM_ARRAY_TASK_ID/$SHARDS: failed with status $status after $((attempt + 1)) attempts" >&2
    exit "$status"
  fi
  echo "shard $SLURM_ARRAY_TASK_ID/$SHARDS: status $status; retrying from its checkpoint ($((attempt + 1)) of $retries)" >&2
done

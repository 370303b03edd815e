#!/bin/bash
# A sharded `tooltouch tune` on a Slurm cluster (docs/tune.md#scale-out): a job array of
# four tasks, each one slice of the sweep, then one merge job that starts when every task
# has succeeded. The merge is byte-identical to the unsharded run.
#
# Run from a checkout on the cluster's shared file system, with `tooltouch` on the PATH
# (`cargo install --path .`):
#
#   bash examples/scale-out/slurm.sh
#
# The number of slices is the `/4` of `--shard` and the `--array=0-3` below: change both.
set -euo pipefail

shards_job=$(sbatch --parsable --job-name=tooltouch-tune --array=0-3 --cpus-per-task=4 \
  --wrap 'tooltouch tune --spec examples/sweep.toml --shard ${SLURM_ARRAY_TASK_ID}/4 --out out/shard-${SLURM_ARRAY_TASK_ID}')

sbatch --job-name=tooltouch-tune-merge --dependency=afterok:"$shards_job" \
  --wrap 'tooltouch tune merge out/shard-* --out out/tune'

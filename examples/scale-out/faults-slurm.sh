#!/bin/bash
# A sharded fault campaign (`tooltouch faults`, docs/faults.md#on-a-slurm-cluster) on a Slurm
# cluster: a job array of four tasks, each one slice of the campaign's cells, then one merge
# job that starts when every task has succeeded. The merge is byte-identical to the
# unsharded run: faults.json, one plot per kind and the table (in the merge job's
# slurm-<job>.out).
#
# Run from a checkout on the cluster's shared file system, with `tooltouch` on the PATH
# (`cargo install --path .`):
#
#   bash examples/scale-out/faults-slurm.sh
#
# The campaign here is small (two kinds at their three default levels, two methods, 10
# measurements per cell: 12 cells, seconds): for the whole campaign drop `--kinds` and
# `--methods` (96 cells), raise `--measurements`, and give your lathe with `--config`.
# The number of slices is the `/4` of `--shard` and the `--array=0-3` below: change both.
#
# `tooltouch faults` exits 1 when a cell let a reading through silently wrong (its results
# are written all the same): a slice's `|| [ $? -eq 1 ]` keeps that from failing the task,
# which would keep the merge from starting. The merge job's exit code is the campaign's
# verdict, 0 or 1 as the unsharded run's (`sacct` or `scontrol show job` shows it); 2 (bad
# input) fails a slice, and the merge then never runs (it stays pending, reason
# DependencyNeverSatisfied, until you `scancel` it).
set -euo pipefail

shards_job=$(sbatch --parsable --job-name=tooltouch-faults --array=0-3 --cpus-per-task=4 \
  --wrap 'tooltouch faults --config examples/measure.toml --kinds chips,fes-lost --methods counter,single-pulse --measurements 10 --shard ${SLURM_ARRAY_TASK_ID}/4 --out out/faults-shard-${SLURM_ARRAY_TASK_ID} || [ $? -eq 1 ]')

sbatch --job-name=tooltouch-faults-merge --dependency=afterok:"$shards_job" \
  --wrap 'tooltouch faults merge out/faults-shard-* --out out/faults'

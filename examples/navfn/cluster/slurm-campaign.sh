#!/usr/bin/env bash
#SBATCH --job-name=navfn-campaign
#SBATCH --array=0-15
#SBATCH --cpus-per-task=2
#SBATCH --mem=1G
#SBATCH --time=04:00:00
#SBATCH --output=logs/navfn-shard-%a.out
#
# A NavFn verification campaign as a Slurm array job of 16 shards. Every array task generates
# its share of the suite on node-local scratch (the suite never exists whole on one node), runs
# the campaign on it and writes one report per shard to a shared folder. A second job, started
# when the whole array has finished, merges the reports strictly: a missing, duplicated or
# inconsistent shard fails the merge with the reason in its log.
#
#   mkdir -p logs reports
#   job=$(sbatch --parsable slurm-campaign.sh)
#   sbatch --dependency=afterany:$job --output=logs/navfn-merge.out \
#          --wrap 'vouch navfn report merge -o report.json reports/shard-*.json'
#
# `--shard auto` takes the shard index from SLURM_ARRAY_TASK_ID − SLURM_ARRAY_TASK_MIN and the
# number of shards from SLURM_ARRAY_TASK_COUNT: change the number of shards in --array only
# (0-(N-1) or 1-N, step 1).
set -euo pipefail

SEED=${SEED:-7}
MAPS=${MAPS:-1000}              # maps per category (9 categories)
CASES=${CASES:-500}             # cases per map
OUT=${OUT:-$SLURM_SUBMIT_DIR/reports}
# a fresh private folder (mktemp: mode 0700, an unpredictable name), never one that exists
work=$(mktemp -d "${TMPDIR:-/tmp}/navfn-suite.XXXXXXXX")
trap 'rm -rf "$work"' EXIT
suite=$work/suite

# this shard's maps only (deterministic: the shards' files add up to the whole generation)
vouch navfn suite gen --seed "$SEED" --maps "$MAPS" --cases "$CASES" --shard auto -o "$suite"

# split by map, like the generation; exit 3 = findings, the report is written all the same
status=0
vouch -q navfn campaign "$suite" --shard auto -o "$OUT/shard-$SLURM_ARRAY_TASK_ID.json" || status=$?
[ "$status" -eq 0 ] || [ "$status" -eq 3 ]

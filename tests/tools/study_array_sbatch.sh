#!/usr/bin/env bash
# docs/study-array.sbatch as Slurm runs it: each array task with its SLURM_ARRAY_TASK_ID / _COUNT (one requeued after
# being killed), then the merge job; the merged study must be byte-identical to the study run in one piece.
#   study_array_sbatch.sh SOURCE_DIR ROCKWATCH_BINARY
set -euo pipefail
src=$(readlink -f "$1")
rockwatch=$(readlink -f "$2")
work=$(mktemp -d)
trap 'rm -rf "$work"' EXIT
cd "$work"
export ROCKWATCH=$rockwatch OUT=study
export STUDY_ARGS="--suite $src/sim/suites/npr9998-2015 --sets 1 --pga 0.15:0.23:0.02 --walls $src/sim/portfolios/example_walls.csv"
for k in 1 2 3; do
  SLURM_ARRAY_TASK_ID=$k SLURM_ARRAY_TASK_COUNT=3 bash "$src/docs/study-array.sbatch" >/dev/null 2>"task$k.err"
done
# A requeued task (its directory is there): it resumes, and finds nothing left to do.
SLURM_ARRAY_TASK_ID=2 SLURM_ARRAY_TASK_COUNT=3 bash "$src/docs/study-array.sbatch" >/dev/null 2>task2-again.err
grep -q "resuming: " task2-again.err || { echo "the requeued task did not resume:"; cat task2-again.err; exit 1; }
MERGE=1 bash "$src/docs/study-array.sbatch" >/dev/null
# shellcheck disable=SC2086
"$rockwatch" study $STUDY_ARGS --out whole >/dev/null 2>&1
for f in runs.csv summary.json walls_summary.csv; do
  cmp "whole/$f" "study/$f" || { echo "merged $f differs from the whole study's"; exit 1; }
done
echo "study-array.sbatch: 3 tasks + merge = the whole study (runs.csv, summary.json, walls_summary.csv)"

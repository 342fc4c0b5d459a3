#!/usr/bin/env bash
# Requirement: the cluster job script (scripts/cluster/gradmpm.sbatch) launches a
# distributed run that gives the serial answer. SLURM is not here: the variables sbatch
# would set are set by hand (2 tasks on one node, one thread each), and the script's
# mpirun line runs as it would in the job.
#
#   slurm_script.sh GRADMPM CASE WORKDIR
set -euo pipefail
gradmpm=$1 case=$2 work=$3
here=$(cd "$(dirname "$0")" && pwd)
script="$here/../../scripts/cluster/gradmpm.sbatch"
rm -rf "$work" && mkdir -p "$work"
bash -n "$script"
"$gradmpm" run "$case" --out "$work/serial" -q -j1
SLURM_NTASKS=2 SLURM_NTASKS_PER_NODE=2 SLURM_CPUS_PER_TASK=1 GRADMPM="$gradmpm" \
  OMPI_ALLOW_RUN_AS_ROOT=1 OMPI_ALLOW_RUN_AS_ROOT_CONFIRM=1 OMPI_MCA_rmaps_base_oversubscribe=1 \
  bash "$script" "$case" "$work/job" -q \
  --set 'linear_solver.options=-ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps'
echo -n "points_final.csv: "
python3 "$here/compare_csv.py" "$work/serial/points_final.csv" "$work/job/points_final.csv"

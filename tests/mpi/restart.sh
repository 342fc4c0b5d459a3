#!/usr/bin/env bash
# Requirement (issues 14 and the reliability issue): a distributed run restarted from its
# checkpoint ends as the uninterrupted distributed run, its VTK pieces included.
#
#   restart.sh GRADMPM MPIEXEC RANKS CASE WORKDIR
set -euo pipefail
gradmpm=$1 mpiexec=$2 ranks=$3 case=$4 work=$5
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work" && mkdir -p "$work"
run() {
  "$mpiexec" --allow-run-as-root --oversubscribe -n "$ranks" "$gradmpm" run "$case" -q -j1 \
    --set linear_solver.type=petsc --set output.vtk_every=1 --set output.checkpoint_every=2 "$@"
}
run --out "$work/full"
run --out "$work/again" --restart "$work/full.checkpoints/step_000002"
for f in points_final.csv points_gradient.csv newton_history.csv; do
  echo -n "$f: "
  python3 "$here/compare_csv.py" "$work/full/$f" "$work/again/$f"
done
/usr/bin/python3 "$here/pvtu_check.py" "$work/again" "$ranks"

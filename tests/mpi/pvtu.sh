#!/usr/bin/env bash
# Runs CASE on RANKS ranks writing every step's VTK files, then tests/mpi/pvtu_check.py
# (--moves: CASE must move points into other ranks' cells, so pieces change); and
# serially, then tests/mpi/grid_pieces_check.py (the grid's pieces against the serial grid).
#   pvtu.sh GRADMPM MPIEXEC RANKS CASE WORKDIR [--set KEY=VALUE ...]
set -euo pipefail
gradmpm=$1 mpiexec=$2 ranks=$3 case=$4 work=$5
shift 5
rm -rf "$work" "$work.serial"
# (MUMPS's LU on the ranks: the two runs differ by round-off, not by a Krylov tolerance)
"$gradmpm" run "$case" --out "$work.serial" -q -j1 --set output.vtk_every=1 "$@"
"$mpiexec" --allow-run-as-root --oversubscribe -n "$ranks" "$gradmpm" run "$case" --out "$work" -q -j1 \
  --set output.vtk_every=1 --set linear_solver.type=petsc \
  --set "linear_solver.options=-ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps" "$@"
# Debian's Python: python3-vtk9 (scripts/install-deps) is installed for it, not for another python3 on PATH
status=0
/usr/bin/python3 "$(dirname "$0")/pvtu_check.py" "$work" "$ranks" --moves || status=1
/usr/bin/python3 "$(dirname "$0")/grid_pieces_check.py" "$work.serial" "$work" "$ranks" || status=1
exit $status

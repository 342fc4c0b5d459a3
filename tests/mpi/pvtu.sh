#!/usr/bin/env bash
# Runs CASE on RANKS ranks writing every step's VTK files, then tests/mpi/pvtu_check.py
# (--moves: CASE must move points into other ranks' cells, so pieces change).
#   pvtu.sh GRADMPM MPIEXEC RANKS CASE WORKDIR [--set KEY=VALUE ...]
set -euo pipefail
gradmpm=$1 mpiexec=$2 ranks=$3 case=$4 work=$5
shift 5
rm -rf "$work"
"$mpiexec" --allow-run-as-root --oversubscribe -n "$ranks" "$gradmpm" run "$case" --out "$work" -q -j1 \
  --set output.vtk_every=1 --set linear_solver.type=petsc "$@"
# Debian's Python: python3-vtk9 (scripts/install-deps) is installed for it, not for another python3 on PATH
/usr/bin/python3 "$(dirname "$0")/pvtu_check.py" "$work" "$ranks" --moves

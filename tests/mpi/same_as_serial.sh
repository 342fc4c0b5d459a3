#!/usr/bin/env bash
# Requirement: a run on N MPI ranks gives the serial answer: positions,
# stresses and state of every point (points_final.csv), the reactions, the gradient
# fields, the tracked points and the energy balance (gathered from the ranks that own the
# points) to 1e-8 of each column's scale.
#
#   same_as_serial.sh GRADMPM MPIEXEC RANKS CASE WORKDIR [--set KEY=VALUE ...]
#
# The serial run uses the case's solver (CHOLMOD by default); the distributed one PETSc
# with MUMPS's parallel LU, so the two differ by round-off only, not by a Krylov tolerance.
# With PETSC_OPTIONS_OF_RANKS set (possibly empty) the ranks get those options instead;
# empty: PETSc's defaults (MUMPS's LU for a general tangent, as with F-bar). With
# RANKS_DEFAULT_SOLVER=1 the ranks get no linear_solver key at all: a case without that
# section must run on ranks (PETSc is their default) and give the serial answer too.
set -euo pipefail
gradmpm=$1 mpiexec=$2 ranks=$3 case=$4 work=$5
shift 5
here=$(cd "$(dirname "$0")" && pwd)
options=${PETSC_OPTIONS_OF_RANKS--ksp_type preonly -pc_type lu -pc_factor_mat_solver_type mumps}
rank_args=(--set linear_solver.type=petsc)
[ -z "$options" ] || rank_args+=(--set "linear_solver.options=$options")
[ -z "${RANKS_DEFAULT_SOLVER:-}" ] || rank_args=()
rm -rf "$work" && mkdir -p "$work"
"$gradmpm" run "$case" --out "$work/serial" -q -j1 "$@"
# With MIGRATIONS_AT_LEAST=N the distributed run prints its steps, and its points must
# have changed rank N times or more in all (the steps' "N point(s) moved to another rank").
quiet=(-q)
[ -z "${MIGRATIONS_AT_LEAST:-}" ] || quiet=()
"$mpiexec" --allow-run-as-root --oversubscribe -n "$ranks" "$gradmpm" run "$case" --out "$work/ranks" "${quiet[@]}" -j1 "$@" \
  "${rank_args[@]}" >"$work/ranks.log"
status=0
if [ -n "${MIGRATIONS_AT_LEAST:-}" ]; then
  grep -h "cut into" "$work/ranks.log" | sed 's/.*; the grid/the grid/' || true
  moved=$(grep -o '[0-9]* point(s) moved' "$work/ranks.log" | awk '{s += $1} END {print s + 0}')
  echo "points that changed rank: $moved (at least $MIGRATIONS_AT_LEAST expected)"
  [ "$moved" -ge "$MIGRATIONS_AT_LEAST" ] || status=1
fi
for f in points_final.csv reactions.csv points_gradient.csv tracked_points.csv energy.csv; do
  [ -f "$work/serial/$f" ] || continue
  [ -f "$work/ranks/$f" ] || { echo "$f: written by the serial run only"; status=1; continue; }
  echo -n "$f: "
  python3 "$here/compare_csv.py" "$work/serial/$f" "$work/ranks/$f" || status=1
done
exit $status

#!/usr/bin/env bash
# Requirement (issue 14): an error on N MPI ranks stops every rank with one message and
# the serial exit code, never a hang: a solver that cannot run distributed (exit 2, the
# key named), an output folder rank 0 cannot create (exit 2), a Newton failure (exit 1),
# points leaving the grid (exit 1, their ids named once).
#
#   errors.sh GRADMPM MPIEXEC CASE WORKDIR
set -uo pipefail
gradmpm=$1 mpiexec=$2 case=$3 work=$4
rm -rf "$work" && mkdir -p "$work"
run() { timeout 120 "$mpiexec" --allow-run-as-root --oversubscribe -n 2 "$gradmpm" run "$case" -q -j1 "$@"; }
failed=0
expect() {  # expect CODE TEXT LOG
  local code=$1 text=$2 log=$3 got=$4
  local count
  count=$(grep -c -- "$text" "$log" || true)
  if [ "$got" -ne "$code" ] || [ "$count" -ne 1 ]; then
    echo "FAILED: expected exit $code and one line with '$text', got exit $got and $count:"; cat "$log"; failed=1
  else
    echo "ok: exit $got, one message: $(grep -- "$text" "$log")"
  fi
}
run --out "$work/a" --set linear_solver.type=cholmod >"$work/a.log" 2>&1
expect 2 "linear_solver.type" "$work/a.log" $?
touch "$work/file"
run --out "$work/file/out" --set linear_solver.type=petsc >"$work/b.log" 2>&1
expect 2 "gradmpm: error" "$work/b.log" $?
run --out "$work/c" --set linear_solver.type=petsc --set nonlinear_solver.max_iterations=1 \
  --set nonlinear_solver.max_cuts=0 >"$work/c.log" 2>&1
expect 1 "solver failure" "$work/c.log" $?
# The footing pulled up 1.5 (the grid ends 0.75 above the body): points leave the grid.
run --out "$work/d" --set linear_solver.type=petsc --set mpm.fbar=false --set load_steps.count=2 \
  --set 'constraints[3].displacement=[0.0,1.5]' >"$work/d.log" 2>&1
expect 1 "material point(s) outside the grid (ids)" "$work/d.log" $?
exit $failed

#!/usr/bin/env bash
# Requirement: an error on N MPI ranks stops every rank with one message and
# the serial exit code, never a hang: a solver that cannot run distributed (exit 2, the
# key named), an output folder rank 0 cannot create (exit 2), a Newton failure (exit 1),
# points leaving the grid, seen by a load step or by the gradient step (exit 1, their ids
# named once), a case too large for the machine's memory (exit 2: every rank decides from
# the same available memory, the ranks of the machine counted together), a checkpoint
# folder that cannot be made (exit 2).
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
# Points leaving the grid: the 3D column's base nodes pulled down 0.75 in two steps (the
# grid ends 0.25 below the body; elastic, so the path does not depend on round-off: the
# footing pulled up out of its grid, used before, tears the body, and the distributed
# run's round-off sometimes ended it by a Newton failure first). Found by the second load
# step's stencils (the gradient step at the end), then by the gradient step after the first.
here=$(cd "$(dirname "$0")" && pwd)
column=("$here/column_3d_gradient.toml" --set linear_solver.type=petsc --set load_steps.count=2
        --set 'constraints[0].displacement=[0.0,0.0,-0.75]')
timeout 120 "$mpiexec" --allow-run-as-root --oversubscribe -n 2 "$gradmpm" run "${column[@]}" -q -j1 \
  --out "$work/d" --set gradient.apply=end >"$work/d.log" 2>&1
expect 1 "load step 2 (load factor 0.5): 32 material point(s) outside the grid (ids): 0, 1, 2" "$work/d.log" $?
timeout 120 "$mpiexec" --allow-run-as-root --oversubscribe -n 2 "$gradmpm" run "${column[@]}" -q -j1 \
  --out "$work/e" >"$work/e.log" 2>&1
expect 1 "solver failure: gradient step: 32 material point(s) outside the grid (ids): 0, 1, 2" "$work/e.log" $?
# A checkpoint folder rank 0 cannot create (a file of that name): exit 2, one message.
touch "$work/g.checkpoints"
run --out "$work/g" --set linear_solver.type=petsc --set output.checkpoint_every=1 >"$work/g.log" 2>&1
expect 2 "cannot create the checkpoint folder" "$work/g.log" $?
GRADMPM_MAX_MEMORY=0.001 run --out "$work/f" --set linear_solver.type=petsc >"$work/f.log" 2>&1
expect 2 "a case that fits in memory: it needs about .* 2 of the 2 ranks on this machine" "$work/f.log" $?
exit $failed

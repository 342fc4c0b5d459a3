#!/usr/bin/env bash
# Requirement (checkpoints of a distributed run): each rank writes its own points
# into a checkpoint (one file per rank, no rank holding every point), and a run restarted
# from it on another number of ranks, serially included, or from a serial checkpoint on
# several ranks, ends as the uninterrupted run (points_final, points_gradient, tracked
# points, energy to 1e-8); a point file that only one rank reads (restarted on as many
# ranks, each reads its own) missing stops every rank with one message and exit 2.
#
#   restart_other_ranks.sh GRADMPM MPIEXEC CASE WORKDIR [--set KEY=VALUE ...]
#
# FIRST_RANKS (default 3): the ranks of the run that writes the checkpoint; it is
# restarted on 2 ranks and serially.
set -euo pipefail
gradmpm=$1 mpiexec=$2 case=$3 work=$4
shift 4
extra=("$@")
here=$(cd "$(dirname "$0")" && pwd)
rm -rf "$work" && mkdir -p "$work"
run() {  # run RANKS ARGS...: RANKS = 1 is a serial run, without mpirun
  local n=$1
  shift
  local launch=()
  [ "$n" -gt 1 ] && launch=("$mpiexec" --allow-run-as-root --oversubscribe -n "$n")
  timeout 200 "${launch[@]}" "$gradmpm" run "$case" -q -j1 --set linear_solver.type=petsc \
    --set output.checkpoint_every=2 --set output.checkpoint_keep=0 "${extra[@]}" "$@"
}
first=${FIRST_RANKS:-3}
run "$first" --out "$work/three"
run 1 --out "$work/serial"
ck3="$work/three.checkpoints/step_000002"
for ((r = 0; r < first; ++r)); do
  f=$(printf 'points_%04d.h5' "$r")
  [ -f "$ck3/$f" ] || { echo "FAILED: the $first-rank checkpoint has no $f"; ls "$ck3"; exit 1; }
done
[ -f "$ck3/checkpoint.h5" ] || { echo "FAILED: the $first-rank checkpoint has no checkpoint.h5"; exit 1; }
[ ! -e "$work/serial.checkpoints/step_000002/points_0000.h5" ] || { echo "FAILED: a serial checkpoint with point files"; exit 1; }
echo "$first-rank checkpoint: checkpoint.h5 and points_0000.h5 .. $(printf 'points_%04d.h5' $((first - 1)))"
run 2 --out "$work/three_on_2" --restart "$ck3"
run 1 --out "$work/three_on_1" --restart "$ck3"
run 2 --out "$work/serial_on_2" --restart "$work/serial.checkpoints/step_000002"
for restarted in three_on_2 three_on_1 serial_on_2; do
  for f in points_final.csv points_gradient.csv tracked_points.csv energy.csv; do
    [ -f "$work/three/$f" ] || continue
    echo -n "$restarted $f: "
    python3 "$here/compare_csv.py" "$work/three/$f" "$work/$restarted/$f"
  done
done
# A missing point file: on as many ranks only rank 1 reads it.
cp -r "$ck3" "$work/broken"
rm "$work/broken/points_0001.h5"
set +e
run "$first" --out "$work/broken_run" --restart "$work/broken" >"$work/broken.log" 2>&1
code=$?
set -e
count=$(grep -c "points_0001.h5 is missing" "$work/broken.log" || true)
if [ "$code" -ne 2 ] || [ "$count" -ne 1 ]; then
  echo "FAILED: a missing point file: expected exit 2 and one message, got exit $code and $count:"
  cat "$work/broken.log"
  exit 1
fi
echo "missing point file: exit 2, one message: $(grep 'is missing' "$work/broken.log")"

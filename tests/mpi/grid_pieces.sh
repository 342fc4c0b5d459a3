#!/usr/bin/env bash
# Requirement: the grid's outputs come from the nodes'
# owners and give the serial answer: the node sets' reactions (reactions.csv, summed over
# the ranks from the nodes each owns) and the grid's VTU (one piece per rank, its cells,
# the values at their corners fetched from their owners) as the serial run's, with the
# points' files (tests/mpi/same_as_serial.sh, then tests/mpi/grid_pieces_check.py).
#
#   grid_pieces.sh GRADMPM MPIEXEC RANKS CASE WORKDIR [--set KEY=VALUE ...]
set -euo pipefail
gradmpm=$1 mpiexec=$2 ranks=$3 case=$4 work=$5
shift 5
here=$(cd "$(dirname "$0")" && pwd)
status=0
"$here/same_as_serial.sh" "$gradmpm" "$mpiexec" "$ranks" "$case" "$work" --set output.vtk_every=1 "$@" || status=1
[ -f "$work/serial/reactions.csv" ] || { echo "the case has no named node set (no reactions.csv)"; status=1; }
# Debian's Python: python3-vtk9 (scripts/install-deps) is installed for it, not for another python3 on PATH
/usr/bin/python3 "$here/grid_pieces_check.py" "$work/serial" "$work/ranks" "$ranks" || status=1
exit $status
